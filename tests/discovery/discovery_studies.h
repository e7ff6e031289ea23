#pragma once
/// @file
/// The studies of tests/discovery/discovery_test.cc, each by one function, and their catalog
/// (DiscoveryStudies), which the fixture `discovery_studies` renders before discovery_test runs
/// (tests/support/render_studies.h).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "dynamics/parameters.h"
#include "support/rendered_study.h"
#include "synth/options.h"
#include "synth/study.h"

namespace hoof::testing {

/// One surface, normal and oblique impacts at three speeds, two repetitions, the paper's
/// contact law in every trial (no per-trial scatter) and every camera effect on.
/// (bench/discovery_explore uses the same design by default: keep the two alike.)
inline constexpr const char* kDiscoveryDesign =
    "--surfaces steel --angles-deg 0,10,20,30 --speeds 1.5,2.75,4 --trials-per-cell 2 --no-scatter";

/// A study of `cells` (one trial each) rendered with `seed` and the synth options `extra`.
inline TestStudy CellsStudy(const std::string& name, const nlohmann::json& cells,
                            std::uint64_t seed, const std::string& extra) {
  return {"discovery-" + name, "--seed " + std::to_string(seed) + extra,
          nlohmann::json{{"cells", cells}, {"trials_per_cell", 1}}.dump(1)};
}

/// The design researchers often run: three surfaces, four angles, three trials per surface and
/// angle at speeds drawn uniformly in [1.5, 4] m/s (one trial per condition, 36 trials), with
/// the renderer's per-trial scatter of e and mu, and the synth options `extra` (a hidden
/// effect, say).
inline TestStudy UnreplicatedStudy(const std::string& name, std::uint64_t seed,
                                   const std::string& extra = "",
                                   const std::vector<std::string>& surfaces = {"steel", "concrete",
                                                                               "asphalt"}) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> speed(1.5, 4.0);
  nlohmann::json cells = nlohmann::json::array();
  for (const auto& s : surfaces) {
    for (double angle : {0.0, 10.0, 20.0, 30.0}) {
      std::vector<double> used;
      while (used.size() < 3) {
        // Trial ids carry the speed to 0.01 m/s: keep them distinct.
        const double v = std::round(speed(rng) * 100) / 100;
        if (std::find(used.begin(), used.end(), v) != used.end()) continue;
        used.push_back(v);
        cells.push_back({{"surface", s}, {"angle_deg", angle}, {"speed_m_s", v}});
      }
    }
  }
  return CellsStudy(name, cells, seed, extra);
}

/// A study of the scorecard's unreplicated design (bench/discovery_scorecard.cc), by the study
/// seed it prints: the same trials, speeds and trial seeds (synth::DrawUnreplicatedCells), with
/// the tangential spring at k/k_t = 0.02 hidden (twice the null studies' median limit).
inline TestStudy ScorecardSpringStudy(std::uint64_t study_seed) {
  synth::StudyDesign d;
  d.seed = study_seed;
  synth::DrawUnreplicatedCells(d);
  nlohmann::json cells = nlohmann::json::array();
  for (const auto& c : d.cells)
    cells.push_back({{"surface", dynamics::SurfaceName(c.surface)},
                     {"angle_deg", c.angle_deg},
                     {"speed_m_s", c.speed_m_s}});
  return CellsStudy("scorecard_spring_" + std::to_string(study_seed), cells, study_seed,
                    " --tangential-compliance-ratio 0.02");
}

/// A study of kDiscoveryDesign with `extra` synth options.
inline TestStudy DesignStudy(const std::string& name, const std::string& extra) {
  return {"discovery-" + name, std::string(kDiscoveryDesign) + " " + extra, ""};
}

/// One effect of the library hidden in kDiscoveryDesign at a realistic size.
struct HiddenEffect {
  std::string key;   // library key
  std::string flag;  // synth flag
  double truth;      // hidden value
  int seed;
};

// Readable test names in ctest's listing.
inline void PrintTo(const HiddenEffect& h, std::ostream* os) { *os << h.key << " = " << h.truth; }

inline const std::vector<HiddenEffect>& HiddenEffects() {
  static const std::vector<HiddenEffect> effects = {
      {"hunt_crossley", "--hunt-crossley-n-s-m2", 2e7, 11},
      {"hertz_stiffness", "--stiffness-exponent-extra", 0.3, 13},
      {"tangential_compliance", "--tangential-compliance-ratio", 1.0, 14},
      {"rolling_resistance", "--rolling-resistance-m", 5e-4, 12}};
  return effects;
}

inline TestStudy HiddenEffectStudy(const HiddenEffect& h) {
  std::ostringstream args;
  args << "--seed " << h.seed << " " << h.flag << " " << h.truth;
  return DesignStudy(h.key, args.str());
}

/// kDiscoveryDesign with nothing hidden, seed 1000 + `seed`.
inline TestStudy NullStudy(int seed) {
  return DesignStudy("null_" + std::to_string(seed), "--seed " + std::to_string(1000 + seed));
}

/// The unreplicated design with nothing hidden.
inline TestStudy ScatterNullStudy(std::uint64_t seed) {
  return UnreplicatedStudy("scatter_null_" + std::to_string(seed), seed);
}

/// The named studies of discovery_test that are neither null nor a hidden effect of
/// HiddenEffects (the study seeds and sizes are explained by the tests that read them).
inline TestStudy NamedDiscoveryStudy(const std::string& name) {
  if (name == "unloading_normal")
    return {"discovery-unloading_normal",
            "--surfaces steel --angles-deg 0 --speeds 1.5,2.75,4 --trials-per-cell 3 --no-scatter "
            "--seed 16 --unloading-stiffness-ratio 0.5",
            ""};
  if (name == "friction_speed")
    return DesignStudy(name, "--seed 17 --friction-speed-slope-s-m 0.5");
  if (name == "tilt") return DesignStudy(name, "--seed 15 --tilt-deg 10");
  if (name == "scatter_rolling")
    return UnreplicatedStudy(name, 211, " --rolling-resistance-m 1e-4");
  if (name == "scatter_tangential_sticking_5")
    return {"discovery-" + name,
            "--angles-deg 0,10,20 --trials-per-cell 1 --seed 5 --tangential-compliance-ratio 0.064",
            ""};
  if (name == "scatter_tangential_253")
    return UnreplicatedStudy(name, 253, " --tangential-compliance-ratio 0.064");
  if (name == "scatter_out_of_plane_rate_231")
    return UnreplicatedStudy(name, 231, " --tilt-rate-deg-s 500");
  if (name == "scatter_out_of_plane_roll_rate_232")
    return UnreplicatedStudy(name, 232, " --roll-rate-deg-s -800");
  if (name == "scatter_sc")
    return UnreplicatedStudy(name, 221, " --scatter-scale 0.5", {"steel", "concrete"});
  if (name == "scatter_a_hc")
    return UnreplicatedStudy(name, 222, " --scatter-scale 0.5 --hunt-crossley-n-s-m2 3e8",
                             {"asphalt"});
  ADD_FAILURE() << "no discovery study is named " << name;
  return {};
}

/// The study seeds of the scorecard's unreplicated design that discovery_test reads.
inline constexpr std::uint64_t kScorecardSpringSeeds[] = {11268363779908301170ULL,
                                                          7047001918490356134ULL};

/// Every study discovery_test reads.
inline std::vector<TestStudy> DiscoveryStudies() {
  std::vector<TestStudy> all;
  for (const auto& h : HiddenEffects()) all.push_back(HiddenEffectStudy(h));
  for (int seed = 1; seed <= 20; ++seed) all.push_back(NullStudy(seed));
  for (std::uint64_t seed : {201, 202, 203}) all.push_back(ScatterNullStudy(seed));
  for (std::uint64_t seed : kScorecardSpringSeeds) all.push_back(ScorecardSpringStudy(seed));
  for (const char* name :
       {"unloading_normal", "friction_speed", "tilt", "scatter_rolling",
        "scatter_tangential_sticking_5", "scatter_tangential_253", "scatter_out_of_plane_rate_231",
        "scatter_out_of_plane_roll_rate_232", "scatter_sc", "scatter_a_hc"})
    all.push_back(NamedDiscoveryStudy(name));
  return all;
}

}  // namespace hoof::testing
