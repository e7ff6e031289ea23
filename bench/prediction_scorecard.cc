// The prediction-z scorecard (docs/discovery.md, "Prediction intervals"): renders studies with
// nothing hidden and the renderer's per-trial scatter of e and mu, measures them, and counts how
// often a trial's prediction |z| (discovery::PredictBaseline) exceeds 3, against the 0.27 % per
// component that a calibrated prediction interval allows. It shares the discovery scorecard's
// designs, seeds and cache (bench/scorecard.h), asserts nothing, and is neither a ctest test nor a
// Google Benchmark.
//   build/bench/prediction_scorecard --designs paper,unreplicated --seeds 10
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "discovery/discovery.h"
#include "scorecard.h"
#include "studyfile/study_file.h"

using namespace scorecard;

int main(int argc, char** argv) {
  CLI::App app{
      "Prediction-z scorecard: how often |prediction z| > 3 on studies with nothing "
      "hidden"};
  std::vector<std::string> designs = kDesigns;
  std::vector<double> scatters = {1.0};
  int seeds = 10, jobs = 0;
  bool verbose = false;
  std::string cache_dir = std::string(HOOF_BINARY_DIR) + "/scorecard-cache";
  app.add_option("--designs", designs, "paper, unreplicated, one_surface (comma-separated)")
      ->delimiter(',')
      ->check(CLI::IsMember(kDesigns))
      ->capture_default_str();
  app.add_option("--scatters", scatters, "Scatter scales (1 = the paper's spread)")
      ->delimiter(',')
      ->check(CLI::Range(0.0, 4.0))
      ->capture_default_str();
  app.add_option("--seeds", seeds, "Studies per design and scatter")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  app.add_option("--jobs", jobs, "Threads (0 = all cores)")->capture_default_str();
  app.add_option("--cache", cache_dir, "Folder of analysed studies")->capture_default_str();
  app.add_flag("--verbose", verbose, "Also print every trial beyond 3 (residuals, s.d.s, z)");
  CLI11_PARSE(app, argc, argv);
  fs::create_directories(cache_dir);
  RemoveLeftovers(cache_dir);

  const std::vector<Effect> effects = AllEffects();
  const Effect* null_effect = &effects.front();  // "null": nothing hidden
  std::printf("%-13s %7s %5s %7s %11s %9s %11s %9s %7s\n", "design", "scatter", "seed", "trials",
              "components", "|z|>3", "trials|z|>3", "max|z|", "status");
  long total_components = 0, total_over = 0, total_trials = 0, total_trials_over = 0;
  for (const std::string& design : designs)
    for (double scatter : scatters)
      for (int seed = 0; seed < seeds; ++seed) {
        StudyPoint p{design, scatter, null_effect, 0.0, seed};
        const Row row = RunStudy(p, cache_dir, jobs, /*only_render=*/true, false);
        if (!row.stage.empty() || !row.error.empty()) {
          std::printf("%-13s %7.2f %5d %7s %11s %9s %11s %9s %s: %s\n", design.c_str(), scatter,
                      seed, "-", "-", "-", "-", "-", row.stage.c_str(), row.error.c_str());
          continue;
        }
        hoof::discovery::DiscoveryOptions options;
        options.jobs = jobs;
        const auto trials = hoof::studyfile::ReadTrialAnalyses(row.cache_file);
        const auto pred = hoof::discovery::PredictBaseline(trials, options);
        if (!pred.success) {
          std::printf("%-13s %7.2f %5d no prediction: %s\n", design.c_str(), scatter, seed,
                      pred.message.c_str());
          continue;
        }
        int components = 0, over = 0, trials_over = 0;
        double worst = 0;
        for (const auto& t : pred.trials) {
          bool any = false;
          for (int c = 0; c < 3; ++c) {
            if (!std::isfinite(t.z[c])) continue;
            ++components;
            const double z = std::abs(t.z[c]);
            worst = std::max(worst, z);
            if (z > 3.0) ++over, any = true;
          }
          trials_over += any ? 1 : 0;
          if (any && verbose)
            std::printf(
                "    %s: residual %.4g %.4g %.4g  prediction s.d. %.4g %.4g %.4g  z %.3g "
                "%.3g %.3g\n",
                t.id.c_str(), t.residual[0], t.residual[1], t.residual[2], t.prediction_sd[0],
                t.prediction_sd[1], t.prediction_sd[2], t.z[0], t.z[1], t.z[2]);
        }
        total_components += components;
        total_over += over;
        total_trials += static_cast<long>(pred.trials.size());
        total_trials_over += trials_over;
        std::printf("%-13s %7.2f %5d %7zu %11d %9d %11d %9.2f %7s\n", design.c_str(), scatter, seed,
                    pred.trials.size(), components, over, trials_over, worst, "ok");
        std::fflush(stdout);
      }
  std::printf(
      "\nsummary: %ld of %ld trial components have |prediction z| > 3 (%.2f %%; a calibrated "
      "interval gives 0.27 %%); %ld of %ld trials have one (%.2f %%)\n",
      total_over, total_components,
      total_components
          ? 100.0 * static_cast<double>(total_over) / static_cast<double>(total_components)
          : NAN,
      total_trials_over, total_trials,
      total_trials
          ? 100.0 * static_cast<double>(total_trials_over) / static_cast<double>(total_trials)
          : NAN);
  return 0;
}
