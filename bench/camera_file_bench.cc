// Reading camera files: frames/s of CameraFileSource::Read() on a 1024 x 1024 Photron MRAW clip
// of 200 frames, 16-bit and 12-bit packed, and on the same 16-bit frames as a Phantom CINE.
//   build/bench/camera_file_bench --benchmark_repetitions=3 --benchmark_report_aggregates_only
//
// The clips are written once by the writers of tracking/camera_file.h into a temporary folder
// (removed at exit), so the reads come from the page cache: this measures the reader (seek,
// read, unpack), not the disk. "rss_growth_MB" is the growth of the process's resident memory
// over the passes through the clip (one frame buffer is already held before): about zero,
// whatever the clip's length.
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <opencv2/imgproc.hpp>

#include "tracking/camera_file.h"

namespace hoof::tracking {
namespace {

namespace fs = std::filesystem;
constexpr int kFrames = 200, kSide = 1024;

const fs::path& Dir() {
  static const fs::path dir = [] {
    fs::path d = fs::temp_directory_path() / ("hoof-camera-bench-" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
  }();
  return dir;
}

/// A frame of the clip: a dark disc moving across a lit, slightly textured background.
cv::Mat Frame(int i, int bits) {
  cv::Mat f(kSide, kSide, CV_16U);
  cv::randu(f, cv::Scalar(3000), cv::Scalar(3400));
  cv::circle(f, cv::Point(200 + 3 * i, 300 + 2 * i), 120, cv::Scalar(400), cv::FILLED);
  if (bits == 16) f *= 16;  // 16 significant bits
  return f;
}

fs::path Clip(const std::string& kind, int bits) {
  const fs::path path = Dir() / ("clip" + std::to_string(bits) + "." + kind);
  if (fs::exists(path)) return path;
  CameraFileSpec spec;
  spec.width = spec.height = kSide;
  spec.frame_count = kFrames;
  spec.bits = bits;
  spec.fps = 20000;
  cv::setRNGSeed(7);
  if (kind == "mraw") {
    MrawWriter w(path, spec);
    for (int i = 0; i < kFrames; ++i) w.Write(Frame(i, bits));
    w.Finish();
  } else {
    CineWriter w(path, spec);
    for (int i = 0; i < kFrames; ++i) w.Write(Frame(i, bits));
    w.Finish();
  }
  return path;
}

/// Resident memory now (kB), from /proc/self/statm.
long RssKb() {
  long pages = 0, resident = 0;
  if (std::FILE* f = std::fopen("/proc/self/statm", "r")) {
    if (std::fscanf(f, "%ld %ld", &pages, &resident) != 2) resident = 0;
    std::fclose(f);
  }
  return resident * (::sysconf(_SC_PAGESIZE) / 1024);
}

void Read(benchmark::State& state, const std::string& kind, int bits, bool shuffled) {
  const fs::path path = Clip(kind, bits);
  auto src = OpenCameraFile(path);
  std::vector<int> order(kFrames);
  for (int i = 0; i < kFrames; ++i) order[static_cast<std::size_t>(i)] = i;
  if (shuffled) std::shuffle(order.begin(), order.end(), std::mt19937(11));
  src->Read(0);  // the one frame buffer
  const long rss0 = RssKb();
  std::uint64_t sum = 0;
  for (auto _ : state) {
    for (const int i : order) {
      const cv::Mat f = src->Read(i);
      sum += f.at<std::uint16_t>(kSide / 2, i);
    }
  }
  benchmark::DoNotOptimize(sum);
  state.SetItemsProcessed(state.iterations() * kFrames);
  state.SetBytesProcessed(state.iterations() * kFrames * static_cast<std::int64_t>(kSide) * kSide *
                          bits / 8);
  state.counters["frames_per_s"] = benchmark::Counter(
      static_cast<double>(kFrames), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["rss_growth_MB"] = static_cast<double>(RssKb() - rss0) / 1024.0;
}

void BM_Mraw16(benchmark::State& s) { Read(s, "mraw", 16, false); }
void BM_Mraw12Packed(benchmark::State& s) { Read(s, "mraw", 12, false); }
void BM_Mraw16RandomOrder(benchmark::State& s) { Read(s, "mraw", 16, true); }
void BM_Cine16(benchmark::State& s) { Read(s, "cine", 16, false); }
BENCHMARK(BM_Mraw16)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Mraw12Packed)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Mraw16RandomOrder)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Cine16)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace hoof::tracking

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  std::error_code ec;
  std::filesystem::remove_all(hoof::tracking::Dir(), ec);
  return 0;
}
