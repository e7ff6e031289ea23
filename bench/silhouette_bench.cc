// Reading and tracking a camera file by the body's silhouette (issue 16: "reading and tracking a
// 16-bit 1024 x 1024 MRAW clip keeps up with at least 2000 frames/s on 2 cores, and memory stays
// flat with clip length"): open + read + track (TrackSilhouette) of every frame of a 16-bit
// 1024 x 1024 Photron MRAW clip, in frames/s (items_per_second); with timing=1 the frames also
// pass through the frame-timing comparison on the way, as in `hoofimpact track`.
//   build/bench/silhouette_bench --benchmark_repetitions=5
//
// The clip: a back-lit ball (a dark disc of radius 40 px with an anti-aliased edge, on a bright
// field with Gaussian noise of s.d. 1 % of the contrast) falling on a parabola onto a dark
// surface at 8000 fps-like steps (up to 5 px per frame) and bouncing from it (e = 0.9), the ball
// joining the surface at each contact. It is written once, with tracking's MrawWriter, into a
// temporary folder removed at exit, so the reads come from the page cache (the reader, not the
// disk). BM_ReadAndTrack/250 and /2000 differ only in the clip's length: "peak_rss_MB" is the
// process's peak resident memory during the pass (the kernel's high-water mark reset just before
// it through /proc/self/clear_refs), "rss_growth_MB" the resident memory after the pass minus
// before it. "cpu_ms_per_frame" is the CPU time of all the process's threads per frame, reading
// and tracking together: on a machine shared with other work it is steadier than the wall clock.
// Both memory figures stay flat with the clip's length: only the per-frame observations (about
// 300 bytes a frame) grow with it.
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <opencv2/core.hpp>

#include "tracking/camera_file.h"
#include "tracking/frame_differences.h"
#include "tracking/frame_timing.h"
#include "tracking/silhouette_tracker.h"

namespace hoof::tracking {
namespace {

namespace fs = std::filesystem;
constexpr int kSide = 1024;
constexpr double kRadius = 40.0, kFloorY = 900.0;  // the surface's top row (px)
constexpr double kBright = 48000, kDark = 9000, kSurface = 20000, kNoise = 390;

const fs::path& Dir() {
  static const fs::path dir = [] {
    fs::path d =
        fs::temp_directory_path() / ("hoof-silhouette-bench-" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
  }();
  return dir;
}

/// The ball's centre in every frame: a parabola from rest, bouncing off the surface.
std::vector<cv::Point2d> Path(int frames) {
  std::vector<cv::Point2d> p;
  double x = 120, y = 200, vx = 0.4, vy = 0;
  const double g = 0.02, e = 0.9, floor_y = kFloorY - kRadius;
  for (int i = 0; i < frames; ++i) {
    p.emplace_back(x, y);
    vy += g;
    x += vx;
    y += vy;
    if (y > floor_y) {
      y = floor_y - e * (y - floor_y);
      vy = -e * vy;
    }
    if (x > kSide - 120 || x < 120) vx = -vx;
  }
  return p;
}

/// One frame: a noisy bright field (one of 8 drawn once, seeded), the dark surface below
/// kFloorY, the dark ball with its edge pixels weighted by their coverage (1-px ramp).
cv::Mat Frame(const cv::Point2d& c, int i) {
  static const std::vector<cv::Mat> fields = [] {
    std::vector<cv::Mat> v;
    cv::RNG rng(7);
    for (int k = 0; k < 8; ++k) {
      cv::Mat f(kSide, kSide, CV_32F);
      rng.fill(f, cv::RNG::NORMAL, kBright, kNoise);
      f.rowRange(static_cast<int>(kFloorY), kSide) += kSurface - kBright;
      v.push_back(f);
    }
    return v;
  }();
  cv::Mat f = fields[static_cast<std::size_t>(i % 8)].clone();
  const int x0 = static_cast<int>(c.x - kRadius - 2), y0 = static_cast<int>(c.y - kRadius - 2);
  for (int y = y0; y <= y0 + 2 * static_cast<int>(kRadius) + 4; ++y) {
    float* row = f.ptr<float>(y);
    for (int x = x0; x <= x0 + 2 * static_cast<int>(kRadius) + 4; ++x) {
      const double cover = std::clamp(kRadius - std::hypot(x - c.x, y - c.y) + 0.5, 0.0, 1.0);
      row[x] = static_cast<float>(row[x] + cover * (kDark - kBright));
    }
  }
  cv::Mat out;
  f.convertTo(out, CV_16U);
  return out;
}

fs::path Clip(int frames) {
  const fs::path path = Dir() / ("ball" + std::to_string(frames) + ".mraw");
  if (fs::exists(path)) return path;
  CameraFileSpec spec;
  spec.width = spec.height = kSide;
  spec.frame_count = frames;
  spec.bits = 16;
  spec.fps = 8000;
  MrawWriter w(path, spec);
  const auto p = Path(frames);
  for (int i = 0; i < frames; ++i) w.Write(Frame(p[static_cast<std::size_t>(i)], i));
  w.Finish();
  return path;
}

/// A "Vm..." field of /proc/self/status, in kB.
long StatusKb(const char* field) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(field, 0) == 0) return std::stol(line.substr(std::strlen(field) + 1));
  return -1;
}

/// CPU time of the whole process, every thread (ms).
double CpuMs() {
  rusage u{};
  ::getrusage(RUSAGE_SELF, &u);
  return 1e3 * static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-3 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

/// Resets the kernel's peak-RSS mark (VmHWM) to the current RSS.
void ResetPeakRss() { std::ofstream("/proc/self/clear_refs") << "5"; }

void BM_ReadAndTrack(benchmark::State& state) {
  const int frames = static_cast<int>(state.range(0));
  const fs::path path = Clip(frames);
  const auto truth = Path(frames);
  SilhouetteOptions options;
  options.read_ahead_frames = static_cast<int>(state.range(1));
  // timing 1: the frames pass through the frame-timing comparison on their way to the tracker,
  // as in `hoofimpact track` (src/pipeline/trial_analysis.cc); its result is checked to exist.
  const bool timing = state.range(2) != 0;
  double worst_px = 0, rss_growth = 0, peak_mb = 0, cpu_ms = 0;
  int found = 0;
  for (auto _ : state) {
    state.PauseTiming();
    ResetPeakRss();
    const long rss0 = StatusKb("VmRSS:");
    const double cpu0 = CpuMs();
    state.ResumeTiming();
    auto src = OpenCameraFile(path);
    DifferencingSource compared(*src, FrameTimingOptions{}.max_grid_pixels, timing);
    const SilhouetteTrack track = TrackSilhouette(compared, options);
    const bool timing_complete = compared.Differences().has_value();
    state.PauseTiming();
    if (timing && !timing_complete)
      state.SkipWithError("the frame-timing comparison is incomplete");
    cpu_ms += CpuMs() - cpu0;
    rss_growth = static_cast<double>(StatusKb("VmRSS:") - rss0) / 1024.0;
    peak_mb = static_cast<double>(StatusKb("VmHWM:")) / 1024.0;
    found = 0;
    worst_px = 0;
    for (int i = 0; i < track.frame_count(); ++i) {
      const auto& o = track.frames[static_cast<std::size_t>(i)];
      if (!o.found) continue;
      ++found;
      const auto& t = truth[static_cast<std::size_t>(i)];
      worst_px = std::max(worst_px, std::hypot(o.p_I.x() - t.x, o.p_I.y() - t.y));
    }
    state.ResumeTiming();
  }
  state.SetItemsProcessed(state.iterations() * frames);
  state.counters["cpu_ms_per_frame"] = cpu_ms / static_cast<double>(state.iterations() * frames);
  state.counters["frames_found"] = found;
  state.counters["worst_error_px"] = worst_px;
  state.counters["peak_rss_MB"] = peak_mb;
  state.counters["rss_growth_MB"] = rss_growth;
}
BENCHMARK(BM_ReadAndTrack)
    ->ArgNames({"frames", "read_ahead", "timing"})
    ->Args({250, 0, 0})
    ->Args({250, 2, 0})
    ->Args({250, 8, 0})
    ->Args({2000, 8, 0})
    ->Args({250, 2, 1})
    ->Args({2000, 2, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

/// Finding the body in a whole frame (the first frame, or when it was lost): FindSilhouette on
/// the clip's first 16-bit 1024 x 1024 frame.
void BM_FindInWholeFrame(benchmark::State& state) {
  const cv::Mat frame = Frame(Path(1)[0], 0);
  SilhouetteOptions options;
  double x = 0;
  for (auto _ : state) x += FindSilhouette(frame, options).p_I.x();
  benchmark::DoNotOptimize(x);
}
BENCHMARK(BM_FindInWholeFrame)->Unit(benchmark::kMillisecond)->UseRealTime();

/// Reading alone, for comparison (as bench/camera_file_bench.cc's BM_Mraw16 on this clip).
void BM_ReadOnly(benchmark::State& state) {
  const int frames = static_cast<int>(state.range(0));
  const fs::path path = Clip(frames);
  std::uint64_t sum = 0;
  for (auto _ : state) {
    auto src = OpenCameraFile(path);
    for (int i = 0; i < frames; ++i) sum += src->Read(i).at<std::uint16_t>(kSide / 2, i % kSide);
  }
  benchmark::DoNotOptimize(sum);
  state.SetItemsProcessed(state.iterations() * frames);
}
BENCHMARK(BM_ReadOnly)->Arg(250)->Unit(benchmark::kMillisecond)->UseRealTime();

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
