// Speed of the synthetic trial renderer: one 60-frame trial written to disk, the frames alone
// in memory, and the paper-sized study (144 trials x 60 frames at 512 x 384) on all cores.
//   build-synth/bench/synth_bench --benchmark_repetitions=3 --benchmark_report_aggregates_only
#include <filesystem>
#include <string>
#include <thread>

#include <benchmark/benchmark.h>
#include <unistd.h>

#include "synth/renderer.h"
#include "synth/study.h"

namespace hoof::synth {
namespace {

namespace fs = std::filesystem;

fs::path BenchDir(const std::string& name) {
  return fs::temp_directory_path() / ("hoof-synth-bench-" + std::to_string(::getpid())) / name;
}

TrialSpec ObliqueSteel() {
  TrialSpec s;
  s.id = "steel_20deg_v3.17_r1";
  s.angle_deg = 20;
  s.speed_m_s = 3.17;
  s.seed = 7;
  return s;
}

// One 60-frame trial with every default camera effect, PNGs and JSON written to a temp dir.
void BM_RenderTrialToDisk(benchmark::State& state) {
  const SpecimenGeometry geometry;
  const RenderOptions options;
  const SceneAssets assets = BuildSceneAssets(geometry, options, {dynamics::Surface::kSteel}, 1);
  const fs::path dir = BenchDir("trial");
  for (auto _ : state) RenderTrial(ObliqueSteel(), geometry, options, assets, dir, true);
  fs::remove_all(dir.parent_path());
  state.counters["frames_per_s"] = benchmark::Counter(
      60.0 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RenderTrialToDisk)->Unit(benchmark::kMillisecond)->UseRealTime();

// The same trial's frames in memory: drawing, lens and sensor without PNG encoding.
void BM_RenderTrialFramesInMemory(benchmark::State& state) {
  const SpecimenGeometry geometry;
  const RenderOptions options;
  const SceneAssets assets = BuildSceneAssets(geometry, options, {dynamics::Surface::kSteel}, 1);
  const TrialTruth truth = PlanTrial(ObliqueSteel(), geometry, options);
  for (auto _ : state) benchmark::DoNotOptimize(RenderFrames(truth, geometry, options, assets));
}
BENCHMARK(BM_RenderTrialFramesInMemory)->Unit(benchmark::kMillisecond)->UseRealTime();

// The textures shared by a study's trials (specimen and three surface blocks).
void BM_BuildSceneAssets(benchmark::State& state) {
  const SpecimenGeometry geometry;
  const RenderOptions options;
  for (auto _ : state)
    benchmark::DoNotOptimize(BuildSceneAssets(
        geometry, options,
        {dynamics::Surface::kSteel, dynamics::Surface::kConcrete, dynamics::Surface::kAsphalt}, 1));
}
BENCHMARK(BM_BuildSceneAssets)->Unit(benchmark::kMillisecond)->UseRealTime();

// The paper-sized study: 3 surfaces x 4 angles x 4 speeds x 3 repetitions, on all cores.
void BM_RenderPaperStudy(benchmark::State& state) {
  const fs::path dir = BenchDir("study");
  for (auto _ : state) {
    const StudyResult r = RenderStudy(StudyDesign{}, {}, RenderOptions{}, dir, 0, true);
    if (r.failed) state.SkipWithError("trials failed");
    state.counters["trials"] = static_cast<double>(r.trials.size());
  }
  fs::remove_all(dir.parent_path());
  state.counters["threads"] = std::thread::hardware_concurrency();
}
BENCHMARK(BM_RenderPaperStudy)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

}  // namespace
}  // namespace hoof::synth

BENCHMARK_MAIN();
