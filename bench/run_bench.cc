// The whole job on a paper-sized study: `hoofimpact run` on 144 rendered trials (3 surfaces x
// 4 angles x 4 speeds x 3 repetitions, 60 frames each, every camera effect on).
//   build/bench/run_bench
// The study is rendered once (about 30 s) into the temp folder and kept for later runs.
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>

#include <benchmark/benchmark.h>

namespace {

namespace fs = std::filesystem;

const fs::path& Study() {
  static const fs::path dir = [] {
    const fs::path d = fs::temp_directory_path() / "hoofimpact-run-bench-study";
    if (!fs::exists(d / "study.json")) {
      fs::remove_all(d);
      const std::string cmd = std::string(HOOF_CLI_PATH) + " synth --study --seed 2026 -o " +
                              d.string() + " > /dev/null";
      if (std::system(cmd.c_str()) != 0) throw std::runtime_error("rendering failed: " + cmd);
    }
    return d;
  }();
  return dir;
}

void BM_RunPaperStudy(benchmark::State& state) {
  const fs::path out = fs::temp_directory_path() / "hoofimpact-run-bench-out";
  const std::string cmd = std::string(HOOF_CLI_PATH) + " run " + Study().string() + " -o " +
                          out.string() + " > /dev/null";
  for (auto _ : state) {
    if (std::system(cmd.c_str()) != 0) state.SkipWithError("hoofimpact run failed");
  }
  state.counters["trials"] = 144;
}
BENCHMARK(BM_RunPaperStudy)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
