// The discovery result around the workflow (fast, no rendering, no discovery run): a
// hand-built DiscoveryResult stored as /discovery tables and read back field by field, its
// figures, and the report's Discovery section on a small hand-built study file.
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
#include "discovery/discovery_json.h"
#include "discovery/discovery_tables.h"
#include "report/discovery_figures.h"
#include "report/html_report.h"
#include "studyfile/study_file.h"
#include "support/paper_specimen.h"
#include "support/test_util.h"

namespace hoof::report {
namespace {

namespace fs = std::filesystem;
using discovery::CandidateOutcome;
using discovery::DiscoveryResult;
using discovery::EffectForm;
using discovery::EffectValue;
using discovery::FindingStatus;
using discovery::Identifiability;
using hoof::testing::FreshDir;
using hoof::testing::ReadAll;

/// A measured trial with known results (2 frames, 2 markers); no frames on disk.
pipeline::TrialAnalysis Trial(const std::string& id, const std::string& surface, double angle,
                              double speed, double e) {
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
void ExpectSameNumber(double got, double want, const std::string& what) {
  if (std::isnan(want))
    EXPECT_TRUE(std::isnan(got)) << what << ": " << got;
  else
    EXPECT_DOUBLE_EQ(got, want) << what;
}

void ExpectSameValues(const std::vector<EffectValue>& got, const std::vector<EffectValue>& want,
                      const std::string& what) {
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
DiscoveryResult Result() {
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
fs::path StudyFile(const fs::path& dir) {
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

void AddDiscovery(const fs::path& h5, const DiscoveryResult& r) {
  auto tables = discovery::DiscoveryTables(r);
  discovery::DiscoveryOptions o;
  o.candidates = {"hunt_crossley", "out_of_plane"};
  o.per_surface = false;
  o.measurement_floor = 2e-4;
  tables.push_back(discovery::DiscoveryOptionsTable(o));
  studyfile::WriteTables(h5, discovery::kDiscoveryGroup, "discovery (test)", tables);
}

TEST(DiscoveryTablesTest, TheResultReadsBackAsWritten) {
  const fs::path dir = FreshDir("discovery_report_test/tables");
  const fs::path h5 = StudyFile(dir);
  EXPECT_FALSE(discovery::HasDiscovery(h5));
  DiscoveryResult w = Result();
  // Per-surface values in the final model too (one with an undefined se): the `surface`
  // column must come back as written.
  w.effects.push_back({"static_friction", "steel", 0.08, 0.02});
  w.effects.push_back({"static_friction", "concrete", 0.03, std::nan("")});
  AddDiscovery(h5, w);
  ASSERT_TRUE(discovery::HasDiscovery(h5));
  const DiscoveryResult r = discovery::ReadDiscovery(h5);
  EXPECT_TRUE(r.success);
  EXPECT_EQ(r.trials_used, 4);
  EXPECT_EQ(r.trials_skipped, 1);
  EXPECT_EQ(r.simulations, 123456);
  EXPECT_DOUBLE_EQ(r.seconds, 12.5);
  EXPECT_EQ(r.verdict, w.verdict);
  EXPECT_FALSE(r.unexplained);
  ASSERT_EQ(r.baseline.size(), 2u);
  ASSERT_EQ(r.final_model.size(), 2u);
  EXPECT_EQ(r.final_model[1].surface, "steel");
  EXPECT_DOUBLE_EQ(r.final_model[1].zeta, 0.09);
  EXPECT_DOUBLE_EQ(r.baseline[0].k_N_m, 4.75e7);
  EXPECT_EQ(r.baseline[0].trials, 2);
  // The noise model.
  EXPECT_EQ(r.measurement_sd, w.measurement_sd);
  for (std::size_t i = 0; i < 2; ++i) {
    ExpectSameNumber(r.baseline[i].zeta_sd, w.baseline[i].zeta_sd, "baseline zeta_sd");
    ExpectSameNumber(r.baseline[i].mu_sd, w.baseline[i].mu_sd, "baseline mu_sd");
    ExpectSameNumber(r.final_model[i].zeta_sd, w.final_model[i].zeta_sd, "final zeta_sd");
    ExpectSameNumber(r.final_model[i].mu_sd, w.final_model[i].mu_sd, "final mu_sd");
    for (int c = 0; c < 3; ++c) {
      ExpectSameNumber(r.final_model[i].measurement_sd[c], w.final_model[i].measurement_sd[c],
                       "final measurement_sd");
      ExpectSameNumber(r.baseline[i].measurement_sd[c], w.baseline[i].measurement_sd[c],
                       "baseline measurement_sd");
    }
  }
  EXPECT_TRUE(std::isnan(r.final_model[1].mu_sd));
  // The effects, one row per value, with their surfaces.
  ExpectSameValues(r.effects, w.effects, "effects");
  ASSERT_EQ(r.rounds.size(), 2u);
  const auto& round = r.rounds[0];
  EXPECT_EQ(round.index, 1);
  EXPECT_EQ(round.accepted, "hunt_crossley");
  EXPECT_EQ(round.decision, w.rounds[0].decision);
  EXPECT_DOUBLE_EQ(round.gap_shrink, 0.84);
  ASSERT_EQ(round.tests.size(), 2u);
  EXPECT_EQ(round.tests[0].covariate, "speed");
  EXPECT_TRUE(round.tests[0].significant);
  EXPECT_TRUE(std::isnan(round.tests[0].df2));
  EXPECT_DOUBLE_EQ(round.tests[0].p_holm, 4e-5);
  ASSERT_EQ(round.candidates.size(), 3u);
  EXPECT_EQ(round.candidates[0].unit, "N s/m^2");
  EXPECT_DOUBLE_EQ(round.candidates[0].delta_bic, -36.5);
  EXPECT_TRUE(round.candidates[0].significant);
  EXPECT_TRUE(round.candidates[2].measurement_effect);
  EXPECT_FALSE(round.candidates[2].fitted);
  EXPECT_EQ(round.candidates[2].message, "no marker ratio");
  EXPECT_TRUE(std::isnan(round.candidates[2].estimate));
  // Every field of every candidate, the new ones included.
  for (std::size_t i = 0; i < w.rounds[0].candidates.size(); ++i) {
    const auto& want = w.rounds[0].candidates[i];
    const auto& got = round.candidates[i];
    const std::string what = "candidate " + want.key;
    EXPECT_EQ(got.rank, want.rank) << what;
    EXPECT_EQ(got.key, want.key) << what;
    EXPECT_EQ(got.name, want.name) << what;
    EXPECT_EQ(got.parameter, want.parameter) << what;
    EXPECT_EQ(got.unit, want.unit) << what;
    EXPECT_EQ(got.measurement_effect, want.measurement_effect) << what;
    EXPECT_EQ(got.fitted, want.fitted) << what;
    EXPECT_EQ(got.message, want.message) << what;
    EXPECT_EQ(got.form, want.form) << what;
    ExpectSameNumber(got.estimate, want.estimate, what + " estimate");
    ExpectSameNumber(got.se, want.se, what + " se");
    ExpectSameValues(got.values, want.values, what);
    ExpectSameNumber(got.lr_statistic, want.lr_statistic, what + " lr_statistic");
    EXPECT_EQ(got.df, want.df) << what;
    ExpectSameNumber(got.p_value, want.p_value, what + " p_value");
    ExpectSameNumber(got.p_per_surface, want.p_per_surface, what + " p_per_surface");
    ExpectSameNumber(got.delta_aic, want.delta_aic, what + " delta_aic");
    ExpectSameNumber(got.delta_bic, want.delta_bic, what + " delta_bic");
    ExpectSameNumber(got.cv_error, want.cv_error, what + " cv_error");
    ExpectSameNumber(got.cv_error_current, want.cv_error_current, what + " cv_error_current");
    ExpectSameNumber(got.cv_density, want.cv_density, what + " cv_density");
    ExpectSameNumber(got.cv_density_current, want.cv_density_current, what + " cv_density_current");
    ExpectSameNumber(got.cv_p, want.cv_p, what + " cv_p");
    EXPECT_EQ(got.identifiability, want.identifiability) << what;
    EXPECT_EQ(got.confounded_with, want.confounded_with) << what;
    EXPECT_EQ(got.significant, want.significant) << what;
    EXPECT_EQ(got.wald_clear, want.wald_clear) << what;
    EXPECT_EQ(got.influential_trial, want.influential_trial) << what;
    ExpectSameNumber(got.p_without_influential, want.p_without_influential,
                     what + " p_without_influential");
    EXPECT_EQ(got.outcome, want.outcome) << what;
    EXPECT_EQ(got.reason, want.reason) << what;
    ExpectSameNumber(got.detection_limit, want.detection_limit, what + " detection_limit");
  }
  EXPECT_EQ(round.candidates[1].form, EffectForm::kPerSurface);
  EXPECT_EQ(round.candidates[1].values.size(), 2u);
  EXPECT_EQ(round.candidates[1].identifiability, Identifiability::kConfounded);
  EXPECT_EQ(round.candidates[2].outcome, CandidateOutcome::kNotFitted);
  EXPECT_TRUE(round.candidates[2].values.empty());
  EXPECT_TRUE(r.rounds[1].candidates.empty());
  ASSERT_EQ(round.gap.size(), 4u);
  EXPECT_EQ(round.gap[3].id, "trial3");
  EXPECT_EQ(round.gap[3].fold, 1);
  EXPECT_DOUBLE_EQ(round.gap[3].residual_before.x(), 0.03);
  EXPECT_DOUBLE_EQ(round.gap[3].residual_after.y(), -0.004);
  EXPECT_TRUE(r.rounds[1].accepted.empty());
  EXPECT_TRUE(r.rounds[1].gap.empty());
  EXPECT_EQ(r.rounds[1].index, 2);
  ASSERT_EQ(r.findings.size(), 2u);
  EXPECT_EQ(r.findings[0].status, FindingStatus::kNamed);
  EXPECT_EQ(r.findings[0].separating_measurement, "impacts at more speeds");
  for (std::size_t i = 0; i < w.findings.size(); ++i) {
    const auto& want = w.findings[i];
    const auto& got = r.findings[i];
    const std::string what = "finding " + want.key;
    EXPECT_EQ(got.key, want.key) << what;
    EXPECT_EQ(got.name, want.name) << what;
    EXPECT_EQ(got.parameter, want.parameter) << what;
    EXPECT_EQ(got.unit, want.unit) << what;
    EXPECT_EQ(got.status, want.status) << what;
    EXPECT_EQ(got.form, want.form) << what;
    EXPECT_EQ(got.surfaces, want.surfaces) << what;
    ExpectSameNumber(got.estimate, want.estimate, what + " estimate");
    ExpectSameNumber(got.se, want.se, what + " se");
    ExpectSameValues(got.values, want.values, what);
    EXPECT_EQ(got.partner, want.partner) << what;
    EXPECT_EQ(got.separating_measurement, want.separating_measurement) << what;
    ExpectSameNumber(got.gap_shrink, want.gap_shrink, what + " gap_shrink");
  }
  EXPECT_TRUE(r.findings[0].surfaces.empty());
  EXPECT_EQ(r.findings[1].surfaces, (std::vector<std::string>{"steel", "concrete"}));
  EXPECT_TRUE(r.remaining.empty());
  ASSERT_EQ(r.residuals.size(), 4u);
  EXPECT_DOUBLE_EQ(r.residuals[2].baseline.y(), -0.01);
  EXPECT_TRUE(std::isnan(r.residuals[2].final_model.z()));
  // Units are recorded on the datasets.
  const auto gap = studyfile::ReadTable(h5, "/discovery/rounds/1/gap");
  EXPECT_EQ(gap.Get("speed_m_s").units, "m/s");
  EXPECT_EQ(gap.Get("residual_before_v_y").units, "1");
  const auto candidates = studyfile::ReadTable(h5, "/discovery/rounds/1/candidates");
  EXPECT_EQ(candidates.Get("cv_error").units, discovery::kHeldOutErrorUnit);
  EXPECT_EQ(candidates.Get("cv_error_current").units, discovery::kHeldOutErrorUnit);
  EXPECT_EQ(candidates.Get("cv_density").units, discovery::kHeldOutDensityUnit);
  EXPECT_EQ(candidates.Get("cv_density_current").units, discovery::kHeldOutDensityUnit);
  // Enums are stored as their text.
  EXPECT_EQ(std::get<std::vector<std::string>>(candidates.Get("outcome").values)[0],
            discovery::ToString(CandidateOutcome::kAdded));
  EXPECT_EQ(std::get<std::vector<std::string>>(candidates.Get("form").values)[1],
            discovery::ToString(EffectForm::kPerSurface));
  const auto findings = studyfile::ReadTable(h5, "/discovery/findings");
  EXPECT_EQ(std::get<std::vector<std::string>>(findings.Get("surfaces").values)[1],
            "steel,concrete");
  const auto options = studyfile::ReadTable(h5, "/discovery/options");
  EXPECT_EQ(std::get<std::vector<std::string>>(options.Get("candidates").values)[0],
            "hunt_crossley,out_of_plane");
  EXPECT_EQ(std::get<std::vector<std::int64_t>>(options.Get("per_surface").values)[0], 0);
  EXPECT_DOUBLE_EQ(std::get<std::vector<double>>(options.Get("measurement_floor").values)[0], 2e-4);
}

TEST(DiscoveryTablesTest, AMissingTableIsNamedWithTheFile) {
  const fs::path dir = FreshDir("discovery_report_test/missing");
  const fs::path h5 = StudyFile(dir);
  hoof::testing::ExpectErrorContaining([&] { discovery::ReadDiscovery(h5); }, h5.string());
  hoof::testing::ExpectErrorContaining([&] { discovery::ReadDiscovery(h5); }, "/discovery/summary");
  // Tables of a result with rounds, but round 2's candidates gone.
  auto tables = discovery::DiscoveryTables(Result());
  std::erase_if(tables, [](const auto& t) { return t.name == "rounds/2/candidates"; });
  studyfile::WriteTables(h5, "/discovery", "discovery (test)", tables);
  hoof::testing::ExpectErrorContaining([&] { discovery::ReadDiscovery(h5); },
                                       "/discovery/rounds/2/candidates");
  // Round 1's per-surface values gone.
  tables = discovery::DiscoveryTables(Result());
  std::erase_if(tables, [](const auto& t) { return t.name == "rounds/1/candidate_values"; });
  studyfile::WriteTables(h5, "/discovery", "discovery (test)", tables);
  hoof::testing::ExpectErrorContaining([&] { discovery::ReadDiscovery(h5); },
                                       "/discovery/rounds/1/candidate_values");
  // An outcome that is not one: the table and the column are named.
  tables = discovery::DiscoveryTables(Result());
  for (auto& t : tables)
    if (t.name == "rounds/1/candidates")
      for (auto& c : t.columns)
        if (c.name == "outcome") std::get<std::vector<std::string>>(c.values)[0] = "bogus";
  studyfile::WriteTables(h5, "/discovery", "discovery (test)", tables);
  hoof::testing::ExpectErrorContaining([&] { discovery::ReadDiscovery(h5); },
                                       "/discovery/rounds/1/candidates: column \"outcome\"");
}

TEST(DiscoveryFiguresTest, GapPerAcceptedRoundAndResiduals) {
  const fs::path dir = FreshDir("discovery_report_test/figures");
  const auto written = WriteDiscoveryFigures(Result(), dir);
  std::vector<std::string> names;
  for (const auto& p : written) {
    names.push_back(p.filename().string());
    EXPECT_GT(fs::file_size(p), 1000u) << p;
  }
  // Round 2 added nothing: no gap figure for it.
  EXPECT_EQ(names,
            (std::vector<std::string>{"discovery_gap_round1.png", "discovery_gap_round1.svg",
                                      "discovery_residuals.png", "discovery_residuals.svg"}));
  // The aggregate gaps are in the gap figure's title.
  EXPECT_NE(ReadAll(dir / "discovery_gap_round1.svg").find("3.1 %"), std::string::npos);
  // And which way it moved: 1 - 0.005 / 0.031 = 0.84 of it.
  EXPECT_NE(ReadAll(dir / "discovery_gap_round1.svg").find("84 % smaller"), std::string::npos);
  // A result that could not run has nothing to draw.
  DiscoveryResult failed;
  failed.message = "too few trials";
  EXPECT_TRUE(WriteDiscoveryFigures(failed, dir / "none").empty());
}

// A gap that grows is said to grow (it read "shrinks -2.35 %"): an effect lowers the held-out
// error, which weighs residuals by their predicted variance, and may still widen the unweighted
// gap that the per-trial scatter dominates.
TEST(DiscoveryTextTest, TheGapChangeSaysWhichWay) {
  EXPECT_EQ(discovery::GapChangeText(0.84), "84 % smaller");
  EXPECT_EQ(discovery::GapChangeText(1 - 5.34 / 5.21), "2.5 % larger");
  EXPECT_EQ(discovery::GapChangeText(1e-4), "unchanged");
  EXPECT_EQ(discovery::GapChangeText(std::nan("")), "n/a");
}

// The JSON a script reads holds what the decision used: each round's naming level, and each
// candidate's Wald condition and both held-out scores (null where not defined).
TEST(DiscoveryJsonTest, EachDecisionCanBeRetracedFromIt) {
  const DiscoveryResult r = Result();
  const nlohmann::json j = discovery::DiscoveryJson(r);
  ASSERT_EQ(j.at("rounds").size(), 2u);
  const auto& round = j.at("rounds").at(0);
  EXPECT_DOUBLE_EQ(round.at("naming_level").get<double>(), 4.45e-4);
  EXPECT_DOUBLE_EQ(round.at("bonferroni_level").get<double>(), 4.2e-4);
  EXPECT_EQ(round.at("hypotheses").get<int>(), 24);
  const auto& hc = round.at("candidates").at(0);
  EXPECT_EQ(hc.at("key"), "hunt_crossley");
  EXPECT_TRUE(hc.at("wald_clear").get<bool>());
  EXPECT_EQ(hc.at("influential_trial"), "asphalt_30deg_v4.00_r2");
  EXPECT_DOUBLE_EQ(hc.at("p_without_influential").get<double>(), 3e-9);
  EXPECT_DOUBLE_EQ(hc.at("cv_density").get<double>(), -10.5);
  EXPECT_DOUBLE_EQ(hc.at("cv_density_current").get<double>(), -8.25);
  EXPECT_DOUBLE_EQ(hc.at("cv_error").get<double>(), 0.95);
  const auto& oop = round.at("candidates").at(2);
  EXPECT_EQ(oop.at("key"), "out_of_plane");
  EXPECT_TRUE(oop.at("cv_density").is_null());
  EXPECT_TRUE(oop.at("p_without_influential").is_null()) << "not checked";
  EXPECT_EQ(j.at("held_out_density_unit"), discovery::kHeldOutDensityUnit);
}

// A contact effect is judged by its held-out density under its own noise model; an
// out-of-plane candidate (no density) by its held-out error. The text names the one used, with
// its unit.
TEST(DiscoveryTextTest, TheHeldOutScoreIsTheOneTheCandidateIsJudgedBy) {
  discovery::CandidateResult c;
  c.cv_error = 1.3;  // worse in the current model's units ...
  c.cv_error_current = 1.1;
  c.cv_density = -10.168;  // ... and better under its own noise model
  c.cv_density_current = -8.663;
  EXPECT_TRUE(discovery::JudgedOnDensity(c));
  EXPECT_TRUE(discovery::HeldOutFell(c));
  EXPECT_EQ(discovery::HeldOutText(c), std::string("held-out -log density -8.663 -> -10.168 (") +
                                           discovery::kHeldOutDensityUnit + ")");
  c.cv_density = -8.5;
  EXPECT_FALSE(discovery::HeldOutFell(c));
  discovery::CandidateResult tilt;
  tilt.cv_error = 0.978;
  tilt.cv_error_current = 46;
  EXPECT_FALSE(discovery::JudgedOnDensity(tilt));
  EXPECT_TRUE(discovery::HeldOutFell(tilt));
  EXPECT_EQ(discovery::HeldOutText(tilt),
            std::string("held-out error 46 -> 0.978 (") + discovery::kHeldOutErrorUnit + ")");
  tilt.cv_error = 50;
  EXPECT_FALSE(discovery::HeldOutFell(tilt));
}

TEST(HtmlReportDiscoveryTest, TheSectionShowsVerdictEvidenceAndFigures) {
  const fs::path dir = FreshDir("discovery_report_test/report");
  const fs::path h5 = StudyFile(dir);
  HtmlReportOptions no_replay;
  no_replay.replay_trials = 0;
  // Without /discovery the page has no Discovery section.
  const auto before = WriteHtmlReport(h5, dir / "before.html", no_replay);
  EXPECT_FALSE(before.discovery);
  const std::string plain = ReadAll(dir / "before.html");
  EXPECT_EQ(plain.find("id=\"discovery\""), std::string::npos);
  EXPECT_EQ(plain.find("#discovery"), std::string::npos);

  AddDiscovery(h5, Result());
  const auto after = WriteHtmlReport(h5, dir / "report.html", no_replay);
  EXPECT_TRUE(after.discovery);
  EXPECT_EQ(after.figures, before.figures + 2);  // the round-1 gap and the residuals
  const std::string html = ReadAll(dir / "report.html");
  EXPECT_NE(html.find("<section id=\"discovery\"><h2>Discovery</h2>"), std::string::npos);
  EXPECT_NE(html.find("<a href=\"#discovery\">Discovery</a>"), std::string::npos);
  // The verdict, in plain words.
  EXPECT_NE(html.find("<p>The missing effect is velocity-dependent damping.</p>"),
            std::string::npos);
  // Its lists as lists, escaped.
  EXPECT_NE(html.find("<p>What these trials could have missed:</p><ul><li>rolling resistance: rho "
                      "= 3e-06 m</li>"
                      "<li>Hertzian &lt;stiffness&gt;: p = 0.9</li></ul>"),
            std::string::npos);
  EXPECT_NE(html.find("The missing effect is named: velocity-dependent (Hunt-Crossley) damping."),
            std::string::npos);
  // The winning candidate's row: its estimate with unit, and the held-out score it is judged
  // by (a contact effect: the density under its own noise model) vs current.
  const auto row = html.find("<tr class=\"candidate accepted\" data-key=\"hunt_crossley\">");
  ASSERT_NE(row, std::string::npos);
  const std::string tr = html.substr(row, html.find("</tr>", row) - row);
  EXPECT_NE(tr.find("c = 0.75 &plusmn; 0.05 N s/m^2"), std::string::npos) << tr;
  EXPECT_NE(tr.find("-10.500 vs -8.250"), std::string::npos) << tr;
  EXPECT_NE(tr.find("-38"), std::string::npos) << tr;
  // Why it was added, in the "why" column, and the outcome as its text.
  EXPECT_NE(tr.find("<td>the strongest significant candidate; lowers the held-out error from 3.1 "
                    "to 0.95</td>"),
            std::string::npos)
      << tr;
  EXPECT_NE(tr.find(std::string(">") + discovery::ToString(CandidateOutcome::kAdded) + "</td>"),
            std::string::npos)
      << tr;
  // Both held-out units are in the caption of the candidate table.
  const auto caption = html.find("<table class=\"data discovery-candidates\"><caption>");
  ASSERT_NE(caption, std::string::npos);
  const std::string caption_text = html.substr(caption, html.find("</caption>", caption) - caption);
  EXPECT_NE(caption_text.find(discovery::kHeldOutErrorUnit), std::string::npos);
  EXPECT_NE(caption_text.find(discovery::kHeldOutDensityUnit), std::string::npos);
  // A per-surface candidate shows each surface's value, and why it was not added.
  const auto sf_row = html.find("data-key=\"static_friction\"");
  ASSERT_NE(sf_row, std::string::npos);
  const std::string sf_tr = html.substr(sf_row, html.find("</tr>", sf_row) - sf_row);
  EXPECT_NE(sf_tr.find("concrete: ds = 0.03 &plusmn; 0.01<br>steel: ds = 0.08 &plusmn; 0.02"),
            std::string::npos)
      << sf_tr;
  EXPECT_NE(
      sf_tr.find(std::string("<td>") + discovery::ToString(EffectForm::kPerSurface) + "</td>"),
      std::string::npos)
      << sf_tr;
  EXPECT_NE(sf_tr.find("fits as well as hunt_crossley (LR 39 against 40)"), std::string::npos)
      << sf_tr;
  EXPECT_NE(sf_tr.find("(absorbed by a changed mu)"), std::string::npos) << sf_tr;
  EXPECT_NE(html.find("data-key=\"out_of_plane\""), std::string::npos);
  EXPECT_NE(html.find("no marker ratio"), std::string::npos);
  // The significant structure test of round 1 is listed, the insignificant one is not.
  EXPECT_NE(html.find("v_y residual falls 0.4 % per m/s"), std::string::npos);
  EXPECT_EQ(html.find("<td>no structure</td>"), std::string::npos);
  // The findings table (status as its text, the per-surface finding's scope) and the settings.
  EXPECT_NE(html.find("impacts at more speeds"), std::string::npos);
  EXPECT_NE(html.find(std::string("<td class=\"ok\">") +
                      discovery::ToString(FindingStatus::kNamed) + "</td><td>all surfaces</td>"),
            std::string::npos);
  EXPECT_NE(
      html.find(std::string(discovery::ToString(FindingStatus::kIndistinguishable)) + "</td><td>" +
                discovery::ToString(EffectForm::kPerSurface) + ": found on steel, concrete</td>"),
      std::string::npos);
  EXPECT_NE(html.find("hunt_crossley,out_of_plane, shared values only, measurement floor "
                      "0.02 % of the impact speed"),
            std::string::npos);
  // The noise model: per surface the scatter of zeta and mu, and the measurement error.
  const auto noise = html.find("<table class=\"data discovery-noise\">");
  ASSERT_NE(noise, std::string::npos);
  const std::string noise_table = html.substr(noise, html.find("</table>", noise) - noise);
  EXPECT_NE(noise_table.find("<td>concrete</td><td class=\"num\">0.0123</td><td "
                             "class=\"num\">0.0045</td>"),
            std::string::npos)
      << noise_table;
  EXPECT_NE(noise_table.find("<td>steel</td><td class=\"num\">0.0111</td><td "
                             "class=\"num\">&ndash;</td>"),
            std::string::npos)
      << noise_table;
  EXPECT_NE(html.find("<td class=\"num\">0.025 %</td><td class=\"num\">0.035 %</td><td "
                      "class=\"num\">0.065 %</td>"),
            std::string::npos);
  // The figures are embedded as PNG data URIs.
  EXPECT_NE(html.find("<img alt=\"discovery_gap_round1\" src=\"data:image/png;base64,iVBOR"),
            std::string::npos);
  EXPECT_NE(html.find("<img alt=\"discovery_residuals\" src=\"data:image/png;base64,"),
            std::string::npos);
}

TEST(HtmlReportDiscoveryTest, AWorkflowThatCouldNotRunSaysWhy) {
  const fs::path dir = FreshDir("discovery_report_test/failed");
  const fs::path h5 = StudyFile(dir);
  DiscoveryResult failed;
  failed.message = "too few measured trials (4; at least 12 needed)";
  AddDiscovery(h5, failed);
  HtmlReportOptions no_replay;
  no_replay.replay_trials = 0;
  WriteHtmlReport(h5, dir / "report.html", no_replay);
  const std::string html = ReadAll(dir / "report.html");
  EXPECT_NE(html.find("The discovery workflow could not run: too few measured trials (4; at "
                      "least 12 needed)"),
            std::string::npos);
}

}  // namespace
}  // namespace hoof::report
