// Everyday footage at 1080p: `hoofimpact init` and `hoofimpact track` on a 1920 x 1080 H.264
// phone clip of a ball bouncing in a room, side by side with OpenCV decoding the same clip
// alone, in one run (docs/performance.md, "Everyday footage").
//   build/bench/footage_bench --benchmark_repetitions=3
// The clip (the renderer's default bounce, 3 s at 30 fps: 90 frames, re-encoded by ffmpeg at a
// phone's 12 Mb/s) is rendered once into the temporary folder and kept for later runs. Each of
// BM_Init and BM_Track reports "x_decode", its time over BM_Decode's, measured in the same run just
// before it (the median of three decodes), so the ratio does not move with the machine.
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>

#include "synth/footage_renderer.h"

namespace {

namespace fs = std::filesystem;

const fs::path& Clip() {
  static const fs::path clip = [] {
    const fs::path dir = fs::temp_directory_path() / "hoofimpact-footage-bench-1080p";
    if (!fs::exists(dir / "phone.mp4")) {
      hoof::synth::FootageSpec spec =
          hoof::synth::DefaultFootageSpec(hoof::synth::FootageScenario::kBounce);
      spec.camera.width_px = 1920;
      spec.camera.height_px = 1080;
      spec.timing.duration_s = 3.0;
      hoof::synth::RenderFootage(spec, dir, /*overwrite=*/true, /*jobs=*/0);
      // OpenCV's writer encodes the clean scene at about 0.3 Mb/s; a phone records 1080p at
      // 10 to 20, and decoding costs more the more there is to decode.
      const std::string reencode = "ffmpeg -v error -y -i " + (dir / "clip.mp4").string() +
                                   " -c:v libx264 -b:v 12M -pix_fmt yuv420p " +
                                   (dir / "phone.mp4").string();
      if (std::system(reencode.c_str()) != 0)
        throw std::runtime_error("re-encoding failed (ffmpeg; tools/install-deps): " + reencode);
    }
    return dir / "phone.mp4";
  }();
  return clip;
}

/// Decodes every frame of the clip with OpenCV's FFmpeg backend; returns the frame count.
int DecodeAll() {
  cv::VideoCapture capture(Clip().string(), cv::CAP_FFMPEG);
  if (!capture.isOpened()) throw std::runtime_error(Clip().string() + ": cannot be opened");
  int n = 0;
  for (cv::Mat frame; capture.read(frame);) ++n;
  return n;
}

/// The median wall time (s) of three decodes of the clip.
double DecodeSeconds() {
  std::vector<double> t;
  for (int i = 0; i < 3; ++i) {
    const auto start = std::chrono::steady_clock::now();
    DecodeAll();
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(t.begin(), t.end());
  return t[1];
}

void BM_Decode(benchmark::State& state) {
  int frames = 0;
  for (auto _ : state) frames = DecodeAll();
  state.SetItemsProcessed(state.iterations() * frames);
}
BENCHMARK(BM_Decode)->Unit(benchmark::kMillisecond)->UseRealTime();

const fs::path& TrialDir() {
  static const fs::path dir = fs::temp_directory_path() / "hoofimpact-footage-bench-trial";
  return dir;
}

/// Runs `hoofimpact` with `args`, its output discarded; wall seconds per run in `state`.
void TimeCommand(benchmark::State& state, const std::string& args) {
  const double decode_s = DecodeSeconds();
  const std::string cmd = std::string(HOOF_CLI_PATH) + " " + args + " > /dev/null 2>&1";
  double total_s = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    if (std::system(cmd.c_str()) != 0) state.SkipWithError(("failed: " + cmd).c_str());
    total_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  state.counters["decode_ms"] = 1e3 * decode_s;
  state.counters["x_decode"] = total_s / static_cast<double>(state.iterations()) / decode_s;
}

void BM_Init(benchmark::State& state) {
  TimeCommand(state, "init " + Clip().string() + " -o " + TrialDir().string() + " --overwrite");
}
BENCHMARK(BM_Init)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Track(benchmark::State& state) {
  const std::string init = std::string(HOOF_CLI_PATH) + " init " + Clip().string() + " -o " +
                           TrialDir().string() + " --overwrite > /dev/null 2>&1";
  if (std::system(init.c_str()) != 0) {
    state.SkipWithError("init failed");
    return;
  }
  TimeCommand(state, "track " + TrialDir().string());
}
BENCHMARK(BM_Track)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
