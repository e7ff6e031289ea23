// The discovery result around the workflow (fast, no rendering, no discovery run): a
// hand-built DiscoveryResult stored as /discovery tables and read back field by field, its
// figures, and the report's Discovery section on a small hand-built study file.
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "compare/study_comparison.h"
#include "discovery/discovery_tables.h"
#include "report/discovery_figures.h"
#include "report/html_report.h"
#include "studyfile/study_file.h"
#include "support/test_util.h"
#include "support/paper_specimen.h"

namespace hoof::report {
namespace {

namespace fs = std::filesystem;
using discovery::DiscoveryResult;
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

/// A discovery that named Hunt-Crossley damping in round 1 and found nothing more in round 2.
DiscoveryResult Result() {
  DiscoveryResult r;
  r.success = true;
  r.trials_used = 4;
  r.trials_skipped = 1;
  r.seconds = 12.5;
  r.simulations = 123456;
  r.verdict =
      "The missing effect is velocity-dependent damping.\n\nWith it in the model no significant "
      "disagreement remains.";
  r.baseline = {{"concrete", 0.21, 0.01, 0.5, 0.02, 4.75e7, 2},
                {"steel", 0.18, 0.01, 0.12, 0.01, 2.8e8, 2}};
  r.final_model = {{"concrete", 0.11, 0.02, 0.5, 0.02, 4.75e7, 2},
                   {"steel", 0.09, 0.02, 0.12, 0.01, 2.8e8, 2}};
  r.effects = {{"hunt_crossley", 0.75}};
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
  discovery::StructureTest t2{
      "w", "steel", "cells (angle x speed)", "lack-of-fit F", 1.1, 1.0, 2.0, 0.4,
      0.8, false,   "no structure"};
  round.tests = {t1, t2};
  discovery::CandidateResult hc;
  hc.key = "hunt_crossley";
  hc.name = "velocity-dependent (Hunt-Crossley) damping";
  hc.parameter = "c";
  hc.unit = "N s/m^2";
  hc.fitted = true;
  hc.estimate = 0.75;
  hc.se = 0.05;
  hc.lr_statistic = 40.0;
  hc.p_value = 2e-10;
  hc.delta_aic = -38.0;
  hc.delta_bic = -36.5;
  hc.cv_error = 0.95;
  hc.cv_error_current = 3.1;
  hc.cv_p = 1e-4;
  hc.identifiability = "identified";
  hc.significant = true;
  hc.rank = 1;
  discovery::CandidateResult oop;
  oop.key = "out_of_plane";
  oop.name = "out-of-plane rotation";
  oop.parameter = "tilt";
  oop.unit = "deg";
  oop.measurement_effect = true;
  oop.fitted = false;
  oop.message = "no marker ratio";
  oop.estimate = oop.se = std::nan("");
  oop.rank = 2;
  round.candidates = {hc, oop};
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
  f.status = "named";
  f.estimate = 0.75;
  f.se = 0.05;
  f.partner = "";
  f.separating_measurement = "impacts at more speeds";
  f.gap_shrink = 0.84;
  r.findings = {f};
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
  tables.push_back(discovery::DiscoveryOptionsTable(o));
  studyfile::WriteTables(h5, discovery::kDiscoveryGroup, "discovery (test)", tables);
}

TEST(DiscoveryTablesTest, TheResultReadsBackAsWritten) {
  const fs::path dir = FreshDir("discovery_report_test/tables");
  const fs::path h5 = StudyFile(dir);
  EXPECT_FALSE(discovery::HasDiscovery(h5));
  const DiscoveryResult w = Result();
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
  ASSERT_EQ(r.effects.count("hunt_crossley"), 1u);
  EXPECT_DOUBLE_EQ(r.effects.at("hunt_crossley"), 0.75);
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
  ASSERT_EQ(round.candidates.size(), 2u);
  EXPECT_EQ(round.candidates[0].unit, "N s/m^2");
  EXPECT_DOUBLE_EQ(round.candidates[0].delta_bic, -36.5);
  EXPECT_TRUE(round.candidates[0].significant);
  EXPECT_TRUE(round.candidates[1].measurement_effect);
  EXPECT_FALSE(round.candidates[1].fitted);
  EXPECT_EQ(round.candidates[1].message, "no marker ratio");
  EXPECT_TRUE(std::isnan(round.candidates[1].estimate));
  ASSERT_EQ(round.gap.size(), 4u);
  EXPECT_EQ(round.gap[3].id, "trial3");
  EXPECT_EQ(round.gap[3].fold, 1);
  EXPECT_DOUBLE_EQ(round.gap[3].residual_before.x(), 0.03);
  EXPECT_DOUBLE_EQ(round.gap[3].residual_after.y(), -0.004);
  EXPECT_TRUE(r.rounds[1].accepted.empty());
  EXPECT_TRUE(r.rounds[1].gap.empty());
  EXPECT_EQ(r.rounds[1].index, 2);
  ASSERT_EQ(r.findings.size(), 1u);
  EXPECT_EQ(r.findings[0].status, "named");
  EXPECT_EQ(r.findings[0].separating_measurement, "impacts at more speeds");
  EXPECT_TRUE(r.remaining.empty());
  ASSERT_EQ(r.residuals.size(), 4u);
  EXPECT_DOUBLE_EQ(r.residuals[2].baseline.y(), -0.01);
  EXPECT_TRUE(std::isnan(r.residuals[2].final_model.z()));
  // Units are recorded on the datasets.
  const auto gap = studyfile::ReadTable(h5, "/discovery/rounds/1/gap");
  EXPECT_EQ(gap.Get("speed_m_s").units, "m/s");
  EXPECT_EQ(gap.Get("residual_before_v_y").units, "1");
  const auto options = studyfile::ReadTable(h5, "/discovery/options");
  EXPECT_EQ(std::get<std::vector<std::string>>(options.Get("candidates").values)[0],
            "hunt_crossley,out_of_plane");
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
  // A result that could not run has nothing to draw.
  DiscoveryResult failed;
  failed.message = "too few trials";
  EXPECT_TRUE(WriteDiscoveryFigures(failed, dir / "none").empty());
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
  EXPECT_NE(html.find("The missing effect is named: velocity-dependent (Hunt-Crossley) damping."),
            std::string::npos);
  // The winning candidate's row: its estimate with unit, and the held-out error vs current.
  const auto row = html.find("<tr class=\"candidate accepted\" data-key=\"hunt_crossley\">");
  ASSERT_NE(row, std::string::npos);
  const std::string tr = html.substr(row, html.find("</tr>", row) - row);
  EXPECT_NE(tr.find("c = 0.75 &plusmn; 0.05 N s/m^2"), std::string::npos) << tr;
  EXPECT_NE(tr.find("0.95 vs 3.1"), std::string::npos) << tr;
  EXPECT_NE(tr.find("-38"), std::string::npos) << tr;
  EXPECT_NE(html.find("data-key=\"out_of_plane\""), std::string::npos);
  EXPECT_NE(html.find("no marker ratio"), std::string::npos);
  // The significant structure test of round 1 is listed, the insignificant one is not.
  EXPECT_NE(html.find("v_y residual falls 0.4 % per m/s"), std::string::npos);
  EXPECT_EQ(html.find("<td>no structure</td>"), std::string::npos);
  // The findings table and the settings.
  EXPECT_NE(html.find("impacts at more speeds"), std::string::npos);
  EXPECT_NE(html.find("hunt_crossley,out_of_plane"), std::string::npos);
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
