// The marker-free scorecard (docs/performance.md, "Marker-free e over seeds"): renders trials of
// a ball or an unmarked specimen with the synth library (8000 fps, the renderer's default noise,
// blur and scatter of e and mu), measures each with the pipeline's trial analysis (the
// silhouette tracker, as `hoofimpact track` does), and counts per condition how often
// |e - e_truth| < --e-tol (issue 16: "marker-free e within 0.01 of the truth at 8000 fps") and
// |mu_eff - mu_eff_truth| < --mu-tol, naming the worst trials. It asserts nothing, and is neither
// a ctest test nor a Google Benchmark.
//   nice -n 10 build/bench/silhouette_scorecard --seeds 20 --jobs 2
//
// A condition is body x lighting x surface x angle; seed k of every condition renders with
// TrialSpec::seed = k (scene drawings from the same seed). Trials are rendered into --dir and
// removed once scored (--keep keeps them). The result does not depend on --jobs.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "core/parallel.h"
#include "dynamics/parameters.h"
#include "pipeline/study_format.h"
#include "pipeline/trial_analysis.h"
#include "synth/options.h"
#include "synth/renderer.h"
#include "synth/study_config.h"
#include "synth/trial_files.h"

namespace fs = std::filesystem;
using namespace hoof;

namespace {

struct Condition {
  synth::Body body;
  synth::Lighting lighting;
  dynamics::Surface surface;
  double angle_deg;
  std::string Name() const {
    char angle[16];
    std::snprintf(angle, sizeof angle, "%g", angle_deg);
    return std::string(synth::ToString(body)) + "/" + synth::ToString(lighting) + "/" +
           dynamics::SurfaceName(surface) + "/" + angle + "deg";
  }
  std::string Folder() const {
    std::string name = Name();
    std::replace(name.begin(), name.end(), '/', '_');
    return name;
  }
};

struct Outcome {
  std::string error;  ///< empty when scored
  double e = NAN, e_truth = NAN, mu = NAN, mu_truth = NAN;
};

Outcome RunOne(const Condition& c, int seed, const fs::path& dir, bool keep) {
  Outcome out;
  synth::SpecimenGeometry geometry;
  geometry.body = c.body;
  synth::RenderOptions render;
  render.lighting = c.lighting;
  synth::TrialSpec spec;
  spec.surface = c.surface;
  spec.angle_deg = c.angle_deg;
  spec.seed = static_cast<std::uint64_t>(seed);
  spec.id = "seed" + std::to_string(seed);
  const fs::path trial = dir / spec.id;
  try {
    const synth::SceneAssets assets =
        synth::BuildSceneAssets(geometry, render, {spec.surface}, spec.seed);
    synth::RenderTrial(spec, geometry, render, assets, trial, /*overwrite=*/true);
    const pipeline::TrialAnalysis a = pipeline::AnalyzeTrial(pipeline::ReadTrial(trial));
    // truth.json's e and mu_eff (pipeline::ReadTruth wants markers' positions; these bodies
    // have none).
    const auto truth = nlohmann::json::parse(std::ifstream(trial / "truth.json"));
    out.e_truth = truth.at("e").get<double>();
    out.mu_truth = truth.at("mu_eff").is_number() ? truth.at("mu_eff").get<double>() : NAN;
    if (!a.success) {
      out.error = a.error;
    } else {
      out.e = a.impact.e;
      out.mu = a.impact.mu_eff;
    }
  } catch (const std::exception& e) {
    out.error = e.what();
  }
  if (!keep) {
    std::error_code ec;
    fs::remove_all(trial, ec);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Marker-free scorecard: e and mu_eff of rendered ball and unmarked trials"};
  std::vector<std::string> bodies = {"ball", "unmarked"}, lightings = {"front", "backlit"};
  std::vector<std::string> surfaces = {"steel", "concrete", "asphalt"};
  std::vector<double> angles = {0, 20, 40};
  int seeds = 20, first_seed = 1, jobs = 0;
  double e_tol = 0.01, mu_tol = 0.01;
  bool keep = false;
  std::string dir = std::string(HOOF_BINARY_DIR) + "/silhouette-scorecard";
  app.add_option("--bodies", bodies, "ball, unmarked")
      ->delimiter(',')
      ->check(CLI::IsMember({"ball", "unmarked"}))
      ->capture_default_str();
  app.add_option("--lightings", lightings, "front, backlit")
      ->delimiter(',')
      ->check(CLI::IsMember({"front", "backlit"}))
      ->capture_default_str();
  app.add_option("--surfaces", surfaces, "steel, concrete, asphalt")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--angles-deg", angles, "Surface angles (deg)")
      ->delimiter(',')
      ->check(CLI::Range(0.0, 60.0))
      ->capture_default_str();
  app.add_option("--seeds", seeds, "Trials per condition")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  app.add_option("--first-seed", first_seed, "Seed of the first trial")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  app.add_option("--e-tol", e_tol, "Tolerance on e")->capture_default_str();
  app.add_option("--mu-tol", mu_tol, "Tolerance on mu_eff")->capture_default_str();
  app.add_option("--jobs", jobs, "Threads (0 = all cores)")->capture_default_str();
  app.add_option("--dir", dir, "Folder for the rendered trials")->capture_default_str();
  app.add_flag("--keep", keep, "Keep the rendered trials");
  CLI11_PARSE(app, argc, argv);

  std::vector<Condition> conditions;
  try {
    for (const auto& b : bodies)
      for (const auto& l : lightings)
        for (const auto s : synth::ParseSurfaces(surfaces, "--surfaces"))
          for (double a : angles)
            conditions.push_back({synth::ParseBody(b), synth::ParseLighting(l), s, a});
  } catch (const std::exception& e) {
    std::fprintf(stderr, "silhouette_scorecard: %s\n", e.what());
    return 2;
  }
  // Each condition's folder holds its specimen's study.json, as a rendered study does.
  std::vector<std::string> ids;
  for (int k = 0; k < seeds; ++k) ids.push_back("seed" + std::to_string(first_seed + k));
  for (const Condition& c : conditions) {
    synth::SpecimenGeometry geometry;
    geometry.body = c.body;
    const fs::path folder = fs::path(dir) / c.Folder();
    fs::create_directories(folder);
    std::ofstream(folder / "study.json") << synth::StudyJson(c.Folder(), geometry, ids).dump(2);
  }
  const std::size_t n = conditions.size() * static_cast<std::size_t>(seeds);
  std::vector<Outcome> outcomes(n);
  core::ParallelFor(n, jobs, [&](std::size_t i) {
    const Condition& c = conditions[i / static_cast<std::size_t>(seeds)];
    const int seed = first_seed + static_cast<int>(i % static_cast<std::size_t>(seeds));
    outcomes[i] = RunOne(c, seed, fs::path(dir) / c.Folder(), keep);
    std::fprintf(stderr, "%s seed %d: %s\n", c.Name().c_str(), seed,
                 outcomes[i].error.empty() ? "scored" : outcomes[i].error.c_str());
  });

  std::printf("%-32s %6s %6s %9s %10s %9s %10s  %s\n", "condition", "trials", "failed", "e<tol",
              "max|de|", "mu<tol", "max|dmu|", "worst e (seed: e vs truth)");
  int all = 0, all_failed = 0, all_e = 0, all_mu = 0, all_mu_n = 0;
  for (std::size_t c = 0; c < conditions.size(); ++c) {
    int failed = 0, e_ok = 0, mu_ok = 0, mu_n = 0, worst = -1;
    double max_de = 0, max_dmu = 0;
    for (int k = 0; k < seeds; ++k) {
      const Outcome& o =
          outcomes[c * static_cast<std::size_t>(seeds) + static_cast<std::size_t>(k)];
      if (!o.error.empty()) {
        ++failed;
        continue;
      }
      const double de = std::abs(o.e - o.e_truth);
      if (de < e_tol) ++e_ok;
      if (!(de <= max_de)) max_de = de, worst = k;
      if (std::isfinite(o.mu_truth) && std::isfinite(o.mu)) {
        ++mu_n;
        const double dmu = std::abs(o.mu - o.mu_truth);
        if (dmu < mu_tol) ++mu_ok;
        max_dmu = std::max(max_dmu, dmu);
      }
    }
    const int scored = seeds - failed;
    char worst_text[96] = "-";
    if (worst >= 0) {
      const Outcome& o =
          outcomes[c * static_cast<std::size_t>(seeds) + static_cast<std::size_t>(worst)];
      std::snprintf(worst_text, sizeof worst_text, "%d: %.4f vs %.4f", first_seed + worst, o.e,
                    o.e_truth);
    }
    std::printf("%-32s %6d %6d %4d/%-4d %10.4f %4d/%-4d %10.4f  %s\n", conditions[c].Name().c_str(),
                seeds, failed, e_ok, scored, max_de, mu_ok, mu_n, max_dmu, worst_text);
    for (int k = 0; k < seeds; ++k) {
      const Outcome& o =
          outcomes[c * static_cast<std::size_t>(seeds) + static_cast<std::size_t>(k)];
      if (!o.error.empty())
        std::printf("    seed %d failed: %s\n", first_seed + k, o.error.c_str());
    }
    all += seeds;
    all_failed += failed;
    all_e += e_ok;
    all_mu += mu_ok;
    all_mu_n += mu_n;
  }
  std::printf(
      "\nsummary: %d trials, %d failed; |e - truth| < %g in %d of %d scored (%.1f %%); "
      "|mu_eff - truth| < %g in %d of %d with a mu_eff (%.1f %%)\n",
      all, all_failed, e_tol, all_e, all - all_failed,
      all > all_failed ? 100.0 * all_e / (all - all_failed) : NAN, mu_tol, all_mu, all_mu_n,
      all_mu_n ? 100.0 * all_mu / all_mu_n : NAN);
  return 0;
}
