// The discovery result stored as /discovery tables and read back field by field (a hand-built
// result: no rendering, no discovery run), and the errors of a file that lacks a table.
#include "discovery/discovery_tables.h"

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/discovery_fixture.h"
#include "support/test_util.h"

namespace hoof::discovery {
namespace {

using namespace hoof::testing::discovery_fixture;
using hoof::testing::FreshDir;

TEST(DiscoveryTablesTest, TheResultReadsBackAsWritten) {
  const fs::path dir = FreshDir("discovery_tables_test/tables");
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

// The settings read back through their typed reader: as written, nothing from a file without
// them, and the later columns' defaults (the floor NaN) from a file written before they existed.
TEST(DiscoveryTablesTest, TheSettingsReadBackAsWritten) {
  const fs::path dir = FreshDir("discovery_tables_test/options");
  const fs::path h5 = StudyFile(dir);
  EXPECT_FALSE(discovery::ReadDiscoveryOptions(h5));
  AddDiscovery(h5, Result());
  const auto o = discovery::ReadDiscoveryOptions(h5);
  ASSERT_TRUE(o);
  EXPECT_EQ(o->candidates, (std::vector<std::string>{"hunt_crossley", "out_of_plane"}));
  EXPECT_FALSE(o->per_surface);
  EXPECT_EQ(o->measurement_floor, 2e-4);
  EXPECT_EQ(o->alpha, discovery::DiscoveryOptions{}.alpha);
  EXPECT_EQ(o->folds, discovery::DiscoveryOptions{}.folds);

  // The first version's columns only (alpha to relative_tolerance, without per_surface).
  studyfile::Table old = discovery::DiscoveryOptionsTable(discovery::DiscoveryOptions{});
  std::erase_if(old.columns, [](const studyfile::Column& c) {
    return c.name == "per_surface" || c.name == "marker_ratio_tolerance" ||
           c.name == "measurement_floor" || c.name == "replicate_tolerance";
  });
  ASSERT_EQ(old.columns.size(), 6u);
  studyfile::WriteTables(h5, "/discovery", "discovery (test)", {old});
  const auto first = discovery::ReadDiscoveryOptions(h5);
  ASSERT_TRUE(first);
  EXPECT_TRUE(first->per_surface);
  EXPECT_TRUE(first->candidates.empty());
  EXPECT_TRUE(std::isnan(first->measurement_floor));
  EXPECT_EQ(first->replicate_tolerance, discovery::DiscoveryOptions{}.replicate_tolerance);
}

TEST(DiscoveryTablesTest, AMissingTableIsNamedWithTheFile) {
  const fs::path dir = FreshDir("discovery_tables_test/missing");
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

}  // namespace
}  // namespace hoof::discovery
