#pragma once
/// @file
/// A hand-built discovery result and a small study file to store it in, shared by the tests of
/// the /discovery tables (tests/discovery/discovery_tables_test.cc) and of the report's
/// Discovery section (tests/report/discovery_report_test.cc). No rendering, no discovery run.
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <variant>
#include <vector>

#include <gtest/gtest.h>

#include "compare/comparison_tables.h"
#include "compare/study_comparison.h"
#include "discovery/discovery.h"
#include "discovery/discovery_tables.h"
#include "studyfile/study_file.h"
#include "support/paper_specimen.h"
#include "support/test_util.h"

namespace hoof::testing::discovery_fixture {

namespace fs = std::filesystem;
using discovery::CandidateOutcome;
using discovery::DiscoveryResult;
using discovery::EffectForm;
using discovery::EffectValue;
using discovery::FindingStatus;
using discovery::Identifiability;

using discovery::CandidateOutcome;
using discovery::DiscoveryResult;
using discovery::EffectForm;
using discovery::EffectValue;
using discovery::FindingStatus;
using discovery::Identifiability;
using hoof::testing::FreshDir;
using hoof::testing::ReadAll;

/// A measured trial with known results (2 frames, 2 markers); no frames on disk.
inline pipeline::TrialAnalysis Trial(const std::string& id, const std::string& surface,
                                     double angle, double speed, double e) {
  pipeline::TrialAnalysis r;
  r.spec.id = id;
  r.spec.dir = "/nonexistent/" + id;
  r.spec.specimen_id = "A";
  r.spec.specimen = hoof::testing::PaperSpecimenSpec();
  r.spec.surface = surface;
  r.spec.surface_angle_deg = angle;
  r.spec.fps = 8000.0;
  r.spec.nominal_speed_m_s = speed;
  r.spec.frames.pattern = "frames/%06d.png";
  r.spec.frames.count = 2;
  r.spec.camera.m_per_px = 2e-4;
  r.success = true;
  r.tracks.names = {"M1", "M2"};
  for (int f = 0; f < 2; ++f) {
    std::vector<tracking::MarkerObservation> row(2);
    for (int m = 0; m < 2; ++m) {
      row[m].found = true;
      row[m].p_I = {100.0 + 10 * m, 50.0 + 2.0 * f};
      row[m].quality = 20.0;
      row[m].radius_px = 4.0;
      row[m].status = "ok";
    }
    r.tracks.frames.push_back(row);
    tracking::BodyPose pose;
    pose.valid = true;
    pose.p_WE = {0.02, 0.05 - 0.0004 * f};
    pose.theta_W_rad = 1.5;
    pose.markers_used = 2;
    pose.marker_distance_m = 0.018;
    r.poses.push_back(pose);
  }
  r.marker_distance_ratio = {1.0, 1.0};
  auto& k = r.impact;
  k.success = true;
  k.impact_time_s = 0.0001;
  k.impact_frame = 1;
  k.v_SC_before = {angle > 0 ? 1.0 : 0.0, -speed};
  k.v_SC_after = {angle > 0 ? 0.4 : 0.0, e * speed};
  k.e = e;
  k.e_se = 1e-3;
  k.mu_eff = angle > 0 ? 0.2 : std::numeric_limits<double>::quiet_NaN();
  k.mu_eff_se = 1e-3;
  r.m_per_px_used = 2e-4;
  return r;
}

/// Doubles equal, NaN equal to NaN (undefined values must come back undefined).
inline void ExpectSameNumber(double got, double want, const std::string& what) {
  if (std::isnan(want))
    EXPECT_TRUE(std::isnan(got)) << what << ": " << got;
  else
    EXPECT_DOUBLE_EQ(got, want) << what;
}

inline void ExpectSameValues(const std::vector<EffectValue>& got,
                             const std::vector<EffectValue>& want, const std::string& what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  for (std::size_t i = 0; i < want.size(); ++i) {
    const std::string at = what + " value " + std::to_string(i);
    EXPECT_EQ(got[i].key, want[i].key) << at;
    EXPECT_EQ(got[i].surface, want[i].surface) << at;
    ExpectSameNumber(got[i].value, want[i].value, at + " value");
    ExpectSameNumber(got[i].se, want[i].se, at + " se");
  }
}

/// A discovery that named Hunt-Crossley damping in round 1 (shared by the surfaces), found a
/// per-surface static-friction excess that fits as well, and nothing more in round 2.
inline DiscoveryResult Result() {
  DiscoveryResult r;
  r.success = true;
  r.trials_used = 4;
  r.trials_skipped = 1;
  r.seconds = 12.5;
  r.simulations = 123456;
  r.verdict =
      "The missing effect is velocity-dependent damping.\n\nWith it in the model no significant "
      "disagreement remains.\n\nWhat these trials could have missed:\n  - rolling resistance: rho "
      "= 3e-06 m\n"
      "  - Hertzian <stiffness>: p = 0.9\n";
  r.baseline = {{"concrete", 0.21, 0.01, 0.5, 0.02, 4.75e7, 2, 0.031, 0.012},
                {"steel", 0.18, 0.01, 0.12, 0.01, 2.8e8, 2, 0.027, std::nan("")}};
  r.final_model = {{"concrete", 0.11, 0.02, 0.5, 0.02, 4.75e7, 2, 0.0123, 0.0045},
                   {"steel", 0.09, 0.02, 0.12, 0.01, 2.8e8, 2, 0.0111, std::nan("")}};
  r.final_model[0].measurement_sd = {2.5e-4, 3.5e-4, 6.5e-4};
  r.final_model[1].measurement_sd = {std::nan(""), 1.5e-4, std::nan("")};
  r.measurement_sd = {2.5e-4, 3.5e-4, 6.5e-4};
  r.effects = {{"hunt_crossley", "", 0.75, 0.05}};
  discovery::Round round;
  round.index = 1;
  discovery::StructureTest t1{"v_y",
                              "all",
                              "speed",
                              "slope t",
                              -6.2,
                              2.0,
                              std::nan(""),
                              1e-5,
                              4e-5,
                              true,
                              "v_y residual falls 0.4 % per m/s"};
  discovery::StructureTest t2{"w", "steel",      "speed",       "slope z",
                              1.1, std::nan(""), std::nan(""),  0.27,
                              0.8, false,        "no structure"};
  round.tests = {t1, t2};
  discovery::CandidateResult hc;
  hc.key = "hunt_crossley";
  hc.name = "velocity-dependent (Hunt-Crossley) damping";
  hc.parameter = "c";
  hc.unit = "N s/m^2";
  hc.fitted = true;
  hc.form = EffectForm::kShared;
  hc.estimate = 0.75;
  hc.se = 0.05;
  hc.values = {{"hunt_crossley", "", 0.75, 0.05}};
  hc.lr_statistic = 40.0;
  hc.df = 1;
  hc.p_value = 2e-10;
  hc.p_per_surface = 0.42;
  hc.delta_aic = -38.0;
  hc.delta_bic = -36.5;
  hc.cv_error = 0.95;
  hc.cv_error_current = 3.1;
  hc.cv_density = -10.5;
  hc.cv_density_current = -8.25;
  hc.cv_p = 1e-4;
  hc.identifiability = Identifiability::kIdentified;
  hc.significant = true;
  hc.wald_clear = true;
  hc.influential_trial = "asphalt_30deg_v4.00_r2";
  hc.p_without_influential = 3e-9;
  hc.outcome = CandidateOutcome::kAdded;
  hc.reason = "the strongest significant candidate; lowers the held-out error from 3.1 to 0.95";
  hc.detection_limit = 0.12;
  hc.rank = 1;
  discovery::CandidateResult sf;
  sf.key = "static_friction";
  sf.name = "static friction above sliding friction";
  sf.parameter = "ds";
  sf.unit = "1";
  sf.fitted = true;
  sf.form = EffectForm::kPerSurface;
  sf.estimate = 0.08;
  sf.se = 0.02;
  sf.values = {{"static_friction", "concrete", 0.03, 0.01},
               {"static_friction", "steel", 0.08, 0.02}};
  sf.lr_statistic = 39.0;
  sf.df = 2;
  sf.p_value = 5e-9;
  sf.p_per_surface = 3e-3;
  sf.delta_aic = -35.0;
  sf.delta_bic = -32.0;
  sf.cv_error = 0.97;
  sf.cv_error_current = 3.1;
  sf.cv_density = -10.25;
  sf.cv_density_current = -8.25;
  sf.cv_p = 2e-4;
  sf.identifiability = Identifiability::kConfounded;
  sf.confounded_with = "a changed mu";
  sf.significant = true;
  sf.outcome = CandidateOutcome::kIndistinguishable;
  sf.reason = "fits as well as hunt_crossley (LR 39 against 40)";
  sf.detection_limit = 0.02;
  sf.rank = 2;
  discovery::CandidateResult oop;
  oop.key = "out_of_plane";
  oop.name = "out-of-plane rotation";
  oop.parameter = "tilt";
  oop.unit = "deg";
  oop.measurement_effect = true;
  oop.fitted = false;
  oop.message = "no marker ratio";
  oop.estimate = oop.se = std::nan("");
  oop.lr_statistic = oop.p_value = oop.p_per_surface = std::nan("");
  oop.df = 0;
  oop.identifiability = Identifiability::kNotTested;
  oop.outcome = CandidateOutcome::kNotFitted;
  oop.reason = "the fit did not run";
  oop.detection_limit = std::nan("");
  oop.rank = 3;
  round.candidates = {hc, sf, oop};
  round.accepted = "hunt_crossley";
  round.decision = "Added hunt_crossley: significant and lowers the held-out error.";
  for (int i = 0; i < 4; ++i) {
    discovery::GapTrial g;
    g.id = "trial" + std::to_string(i);
    g.surface = i < 2 ? "steel" : "concrete";
    g.angle_deg = i % 2 ? 20.0 : 0.0;
    g.speed_m_s = 2.5 + 0.5 * i;
    g.fold = i % 2;
    g.residual_before = {0.01 * i, -0.03, 0.005};
    g.residual_after = {0.002 * i, -0.004, 0.001};
    g.gap_before = 0.03 + 0.001 * i;
    g.gap_after = 0.005;
    round.gap.push_back(g);
  }
  round.gap_before = 0.031;
  round.gap_after = 0.005;
  round.gap_shrink = 0.84;
  round.naming_level = 4.45e-4;
  round.bonferroni_level = 4.2e-4;
  round.hypotheses = 24;
  discovery::Round second;
  second.index = 2;
  second.tests = {t2};
  second.decision = "Nothing significant remains: stop.";
  r.rounds = {round, second};
  discovery::Finding f;
  f.key = "hunt_crossley";
  f.name = hc.name;
  f.parameter = "c";
  f.unit = "N s/m^2";
  f.status = FindingStatus::kNamed;
  f.form = EffectForm::kShared;
  f.estimate = 0.75;
  f.se = 0.05;
  f.values = hc.values;
  f.partner = "";
  f.separating_measurement = "impacts at more speeds";
  f.gap_shrink = 0.84;
  discovery::Finding g;
  g.key = sf.key;
  g.name = sf.name;
  g.parameter = sf.parameter;
  g.unit = sf.unit;
  g.status = FindingStatus::kIndistinguishable;
  g.form = EffectForm::kPerSurface;
  g.surfaces = {"steel", "concrete"};
  g.estimate = 0.08;
  g.se = 0.02;
  g.values = sf.values;
  g.partner = "hunt_crossley";
  g.separating_measurement = "oblique impacts at more angles";
  g.gap_shrink = std::nan("");
  r.findings = {f, g};
  for (int i = 0; i < 4; ++i) {
    discovery::TrialResiduals t;
    t.id = "trial" + std::to_string(i);
    t.surface = i < 2 ? "steel" : "concrete";
    t.angle_deg = i % 2 ? 20.0 : 0.0;
    t.speed_m_s = 2.5 + 0.5 * i;
    t.baseline = {0.01, -0.03 + 0.01 * i, 0.002};
    t.final_model = {0.001, -0.002, std::nan("")};
    t.marker_ratio = 1.0;
    r.residuals.push_back(t);
  }
  return r;
}

/// A study file with four measured trials and a (not fitted) /comparison, as `run` leaves it.
inline fs::path StudyFile(const fs::path& dir) {
  std::vector<pipeline::TrialAnalysis> trials = {
      Trial("steel_0deg_r1", "steel", 0.0, 2.5, 0.6),
      Trial("steel_20deg_r1", "steel", 20.0, 3.0, 0.62),
      Trial("concrete_0deg_r1", "concrete", 0.0, 3.5, 0.5),
      Trial("concrete_20deg_r1", "concrete", 20.0, 4.0, 0.52)};
  studyfile::StudyInfo info;
  info.name = "discovery-report-study";
  info.study_dir = dir;
  info.created_utc = "2024-05-01T12:00:00Z";
  info.specimens["A"] = hoof::testing::PaperSpecimenSpec();
  const fs::path h5 = dir / "study.h5";
  studyfile::WriteStudyFile(h5, info, trials);
  compare::StudyComparison cmp;
  cmp.trials.resize(trials.size());
  for (auto& c : cmp.trials) c.message = "not compared in this test";
  studyfile::WriteTables(h5, "/comparison", "test", compare::ComparisonTables(trials, cmp));
  return h5;
}

inline void AddDiscovery(const fs::path& h5, const DiscoveryResult& r) {
  auto tables = discovery::DiscoveryTables(r);
  discovery::DiscoveryOptions o;
  o.candidates = {"hunt_crossley", "out_of_plane"};
  o.per_surface = false;
  o.measurement_floor = 2e-4;
  tables.push_back(discovery::DiscoveryOptionsTable(o));
  studyfile::WriteTables(h5, discovery::kDiscoveryGroup, "discovery (test)", tables);
}

}  // namespace hoof::testing::discovery_fixture
