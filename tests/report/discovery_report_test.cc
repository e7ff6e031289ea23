// The discovery result around the workflow (fast, no rendering, no discovery run): the figures,
// the text and JSON, and the report's Discovery section of a hand-built DiscoveryResult on a
// small hand-built study file (tests/support/discovery_fixture.h; its /discovery tables are
// tested in tests/discovery/discovery_tables_test.cc).
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
#include "support/discovery_fixture.h"
#include "support/paper_specimen.h"
#include "support/test_util.h"

namespace hoof::report {
namespace {

using namespace hoof::testing::discovery_fixture;
using hoof::testing::FreshDir;
using hoof::testing::ReadAll;

TEST(DiscoveryFiguresTest, GapPerAcceptedRoundAndResiduals) {
  const fs::path dir = FreshDir("discovery_report_test/figures");
  const auto written = WriteDiscoveryFigures(Result(), dir);
  std::vector<std::string> names;
  for (const auto& p : written) {
    names.push_back(p.filename().string());
    // An image with content; the data and the script, not empty.
    EXPECT_GT(fs::file_size(p), p.extension() == ".png" || p.extension() == ".svg" ? 1000u : 0u)
        << p;
  }
  // Round 2 added nothing: no gap figure for it.
  // Each figure with its data and gnuplot script (report/gnuplot.h).
  EXPECT_EQ(names, (std::vector<std::string>{"discovery_gap_round1.png", "discovery_gap_round1.svg",
                                             "discovery_gap_round1.csv", "discovery_gap_round1.gp",
                                             "discovery_residuals.png", "discovery_residuals.svg",
                                             "discovery_residuals.csv", "discovery_residuals.gp"}));
  // The aggregate gaps are in the gap figure's title (hoof::format, 4 significant digits).
  EXPECT_NE(ReadAll(dir / "discovery_gap_round1.svg").find("3.100 %"), std::string::npos);
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
  EXPECT_NE(tr.find("c = 0.750 &plusmn; 0.050 N s/m^2"), std::string::npos) << tr;
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
  EXPECT_NE(sf_tr.find("concrete: ds = 0.030 &plusmn; 0.010<br>steel: ds = 0.080 &plusmn; 0.020"),
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
                      "0.0200 % of the impact speed"),
            std::string::npos);
  // The noise model: per surface the scatter of zeta and mu, and the measurement error.
  const auto noise = html.find("<table class=\"data discovery-noise\">");
  ASSERT_NE(noise, std::string::npos);
  const std::string noise_table = html.substr(noise, html.find("</table>", noise) - noise);
  EXPECT_NE(noise_table.find("<td>concrete</td><td class=\"num\">0.0123</td><td "
                             "class=\"num\">0.00450</td>"),
            std::string::npos)
      << noise_table;
  EXPECT_NE(noise_table.find("<td>steel</td><td class=\"num\">0.0111</td><td "
                             "class=\"num\">n/a</td>"),
            std::string::npos)
      << noise_table;
  EXPECT_NE(html.find("<td class=\"num\">0.0250 %</td><td class=\"num\">0.0350 %</td><td "
                      "class=\"num\">0.0650 %</td>"),
            std::string::npos);
  // The figures are embedded as PNG data URIs.
  EXPECT_NE(html.find("<img alt=\"discovery_gap_round1\" src=\"data:image/png;base64,iVBOR"),
            std::string::npos);
  EXPECT_NE(html.find("<img alt=\"discovery_residuals\" src=\"data:image/png;base64,"),
            std::string::npos);
}

// A /stats group the report cannot read (a table without a column it needs) does not sink the
// report: the page and the summary's notes name the file, the table and the column, and the rest
// of the page is written.
TEST(HtmlReportStatisticsTest, AStatisticsTableThatCannotBeReadIsNamedAndThePageWritten) {
  const fs::path dir = FreshDir("discovery_report_test/bad_stats");
  const fs::path h5 = StudyFile(dir);
  using studyfile::Column;
  studyfile::WriteTables(
      h5, "/stats", "test",
      {{"excluded", "", {Column::Texts("id", "", {}), Column::Texts("reason", "", {})}},
       {"e/cells",
        "",
        {Column::Texts("cell", "", {"steel|0"}), Column::Texts("surface", "", {"steel"}),
         Column::Texts("angle_deg", "", {"0"}), Column::Numbers("n", "1", "", {2.0})}}});
  HtmlReportOptions no_replay;
  no_replay.replay_trials = 0;
  const auto summary = WriteHtmlReport(h5, dir / "report.html", no_replay);
  const std::string html = ReadAll(dir / "report.html");
  EXPECT_NE(html.find("The statistics tables cannot be read"), std::string::npos);
  EXPECT_NE(html.find("/stats/e/cells"), std::string::npos);
  EXPECT_NE(summary.notes.find(h5.string() + ":/stats/e/cells"), std::string::npos)
      << summary.notes;
  EXPECT_NE(summary.notes.find("column \"mean\""), std::string::npos) << summary.notes;
  EXPECT_NE(html.find("id=\"trials\""), std::string::npos);  // the rest of the page is there
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
