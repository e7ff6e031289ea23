// Tracking throughput against bare decoding of the same frames.
//   build/bench/tracking_bench --benchmark_repetitions=3 --benchmark_report_aggregates_only
//
// Frames: 512 x 384, 8-bit, a falling specimen with two white-dot markers on black patches,
// textured background and 1.5 % noise, drawn here and written once as PNG (compressed) and as
// PGM (uncompressed) into the build folder.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <benchmark/benchmark.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "tracking/frame_source.h"
#include "tracking/marker_tracker.h"

namespace hoof::tracking {
namespace {

namespace fs = std::filesystem;
constexpr int kFrames = 240;

cv::Mat DrawFrame(int i, std::mt19937& rng) {
  cv::Mat img(384, 512, CV_32F);
  cv::randu(img, 0.05, 0.12);  // dark, slightly textured background
  cv::GaussianBlur(img, img, cv::Size(0, 0), 3.0);
  const double y = 100.0 + 40.0 * std::sin(0.05 * i), x = 256.3;  // up to 2 px per frame
  // The specimen: a grey bar; the markers: black patches with white disks (16x supersampled).
  cv::rectangle(img, cv::Rect(static_cast<int>(x) - 40, static_cast<int>(y) - 10, 80, 225),
                cv::Scalar(0.5), cv::FILLED);
  for (double dy : {0.0, 90.0}) {
    const double cy = y + 170 - dy;
    cv::rectangle(img, cv::Rect(static_cast<int>(x) - 15, static_cast<int>(cy) - 15, 31, 31),
                  cv::Scalar(0.04), cv::FILLED);
    cv::Mat big(31 * 16, 31 * 16, CV_32F, cv::Scalar(0.04));
    cv::circle(big,
               cv::Point2d((x - (static_cast<int>(x) - 15) + 0.5) * 16 - 8,
                           (cy - (static_cast<int>(cy) - 15) + 0.5) * 16 - 8),
               7.5 * 16, cv::Scalar(0.9), cv::FILLED, cv::LINE_8);
    cv::Mat small;
    cv::resize(big, small, cv::Size(31, 31), 0, 0, cv::INTER_AREA);
    small.copyTo(img(cv::Rect(static_cast<int>(x) - 15, static_cast<int>(cy) - 15, 31, 31)));
  }
  cv::Mat noise(img.size(), CV_32F);
  cv::randn(noise, 0, 0.015);
  img += noise;
  cv::Mat out;
  img.convertTo(out, CV_8U, 255.0);
  (void)rng;
  return out;
}

const fs::path& FrameDir() {
  static const fs::path dir = [] {
    const fs::path d = fs::temp_directory_path() / "hoofimpact-tracking-bench";
    if (!fs::exists(d / "done")) {
      fs::create_directories(d);
      std::mt19937 rng(1);
      cv::setRNGSeed(1);
      for (int i = 0; i < kFrames; ++i) {
        const cv::Mat f = DrawFrame(i, rng);
        char name[32];
        std::snprintf(name, sizeof name, "%06d", i);
        cv::imwrite((d / (std::string(name) + ".png")).string(), f);
        cv::imwrite((d / (std::string(name) + ".pgm")).string(), f);
      }
      std::ofstream(d / "done") << "ok";
    }
    return d;
  }();
  return dir;
}

const std::vector<std::pair<std::string, Eigen::Vector2d>> kLayout = {{"M1", {0.006, 0.0}},
                                                                      {"M2", {0.024, 0.0}}};

/// Runs `work` (one pass over the frames) on `threads` threads at once.
template <class Fn>
void RunThreads(benchmark::State& state, int threads, Fn work) {
  for (auto _ : state) {
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t) pool.emplace_back(work);
    for (auto& t : pool) t.join();
  }
  // Frames per second of wall time (the benchmarks use real time), all threads together.
  state.SetItemsProcessed(state.iterations() * kFrames * threads);
}

void BM_DecodeOnly(benchmark::State& state, const std::string& ext) {
  const fs::path dir = FrameDir();
  RunThreads(state, static_cast<int>(state.range(0)), [&] {
    for (int i = 0; i < kFrames; ++i) {
      char name[32];
      std::snprintf(name, sizeof name, "%06d", i);
      benchmark::DoNotOptimize(cv::imread((dir / (name + ext)).string(), cv::IMREAD_UNCHANGED));
    }
  });
}

void BM_DecodeAndTrack(benchmark::State& state, const std::string& ext) {
  const fs::path dir = FrameDir();
  RunThreads(state, static_cast<int>(state.range(0)), [&] {
    ImageSequenceSource src(dir, "%06d" + ext, 0, kFrames);
    benchmark::DoNotOptimize(TrackMarkers(src, kLayout, 2e-4, {0, 1}));
  });
}

BENCHMARK_CAPTURE(BM_DecodeOnly, png, std::string(".png"))
    ->Arg(1)
    ->Arg(2)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_DecodeAndTrack, png, std::string(".png"))
    ->Arg(1)
    ->Arg(2)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_DecodeOnly, pgm, std::string(".pgm"))
    ->Arg(1)
    ->Arg(2)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_DecodeAndTrack, pgm, std::string(".pgm"))
    ->Arg(1)
    ->Arg(2)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace hoof::tracking

namespace hoof::tracking {
namespace {

// The one-off search of the first frame, and the per-frame windowed search of one marker.
void BM_FindDotsFullFrame(benchmark::State& state) {
  const cv::Mat f = cv::imread((FrameDir() / "000000.pgm").string(), cv::IMREAD_UNCHANGED);
  for (auto _ : state) benchmark::DoNotOptimize(FindDots(f, 4));
}
BENCHMARK(BM_FindDotsFullFrame)->Unit(benchmark::kMillisecond);

void BM_FindDotNear(benchmark::State& state) {
  const cv::Mat f = cv::imread((FrameDir() / "000000.pgm").string(), cv::IMREAD_UNCHANGED);
  const auto dots = FindDots(f, 2);
  const Eigen::Vector2d p = dots.at(0).p_I + Eigen::Vector2d(0.7, 1.6);
  for (auto _ : state) benchmark::DoNotOptimize(FindDotNear(f, p, 8.0, dots[0].radius_px));
}
BENCHMARK(BM_FindDotNear)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace hoof::tracking

BENCHMARK_MAIN();
