// End-to-end tests of `hoofimpact stats` on small CSV files written here, against R's
// published results for the same data (PlantGrowth, ToothGrowth; see the library tests).
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/csv.h"
#include "stats/grouping.h"
#include "stats/one_way_analysis.h"
#include "studyfile/study_file.h"
#include "support/run_command.h"

namespace hoof::cli {
namespace {

using hoof::testing::RunHoofimpact;

std::string Dir() {
  const std::string dir = std::string(HOOF_BINARY_DIR) + "/stats_command_test";
  std::filesystem::create_directories(dir);
  return dir;
}

std::string WritePlantGrowth() {
  const std::string path = Dir() + "/plant_growth.csv";
  std::ofstream out(path);
  out << "group,weight\n";
  const char* groups[] = {"ctrl", "trt1", "trt2"};
  const double w[3][10] = {{4.17, 5.58, 5.18, 6.11, 4.50, 4.61, 5.17, 4.53, 5.33, 5.14},
                           {4.81, 4.17, 4.41, 3.59, 5.87, 3.83, 6.03, 4.89, 4.32, 4.69},
                           {6.31, 5.12, 5.54, 5.50, 5.37, 5.29, 4.92, 6.15, 5.80, 5.26}};
  for (int g = 0; g < 3; ++g)
    for (int i = 0; i < 10; ++i) out << groups[g] << "," << w[g][i] << "\n";
  return path;
}

std::string WriteToothGrowth() {
  const std::string path = Dir() + "/tooth_growth.csv";
  std::ofstream out(path);
  out << "len,supp,dose\n";
  const double vc[3][10] = {{4.2, 11.5, 7.3, 5.8, 6.4, 10.0, 11.2, 11.2, 5.2, 7.0},
                            {16.5, 16.5, 15.2, 17.3, 22.5, 17.3, 13.6, 14.5, 18.8, 15.5},
                            {23.6, 18.5, 33.9, 25.5, 26.4, 32.5, 26.7, 21.5, 23.3, 29.5}};
  const double oj[3][10] = {{15.2, 21.5, 17.6, 9.7, 14.5, 10.0, 8.2, 9.4, 16.5, 9.7},
                            {19.7, 23.3, 23.6, 26.4, 20.0, 25.2, 25.8, 21.2, 14.5, 27.3},
                            {25.5, 26.4, 22.4, 24.5, 24.8, 30.9, 26.4, 27.3, 29.4, 23.0}};
  const char* dose[] = {"0.5", "1", "2"};
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 10; ++i) out << vc[j][i] << ",VC," << dose[j] << "\n";
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 10; ++i) out << oj[j][i] << ",OJ," << dose[j] << "\n";
  return path;
}

// R: F = 4.8461, p = 0.01591 (ANOVA); Bartlett K^2 = 2.8786, p = 0.2371; Welch F = 5.181,
// df2 = 17.128, p = 0.01739; LSD p 0.194, 0.088, 0.004 (pairwise.t.test, no adjustment).
TEST(StatsCommandTest, JsonMatchesRForPlantGrowth) {
  const auto r = RunHoofimpact("stats --csv " + WritePlantGrowth() +
                               " --response weight --factor group --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out).at("results");
  EXPECT_NEAR(j["anova"]["between"]["f"].get<double>(), 4.8461, 0.5e-4);
  EXPECT_NEAR(j["anova"]["between"]["p"].get<double>(), 0.01591, 0.5e-5);
  EXPECT_EQ(j["anova"]["within"]["df"].get<int>(), 27);
  EXPECT_NEAR(j["bartlett"]["k_squared"].get<double>(), 2.8786, 0.5e-4);
  EXPECT_FALSE(j["bartlett"]["rejects_equal_variances"].get<bool>());
  EXPECT_NEAR(j["welch"]["f"].get<double>(), 5.181, 0.5e-3);
  EXPECT_NEAR(j["welch"]["df2"].get<double>(), 17.128, 0.5e-3);
  ASSERT_TRUE(j["lsd"]["performed"].get<bool>());
  ASSERT_EQ(j["lsd"]["pairs"].size(), 3u);
  EXPECT_NEAR(j["lsd"]["pairs"][2]["p"].get<double>(), 0.0045, 0.5e-4);
  EXPECT_EQ(j["groups"][0]["label"], "ctrl");
  EXPECT_FALSE(j["transform"]["applied"].get<bool>());
  EXPECT_TRUE(j["two_way"].is_null());
}

// R: summary(aov(len ~ supp * factor(dose))): F 15.572, 92.000, 4.107 on 1, 2, 2 and 54 df.
TEST(StatsCommandTest, Factor2AddsTheTwoWayTableAndOutCsvWritesIt) {
  const std::string out_csv = Dir() + "/tables.csv";
  std::filesystem::remove(out_csv);
  const auto r =
      RunHoofimpact("stats --csv " + WriteToothGrowth() +
                    " --response len --factor supp --factor2 dose --json --out-csv " + out_csv);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out).at("results");
  const auto& rows = j["two_way"]["rows"];
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[0]["source"], "supp");
  EXPECT_NEAR(rows[0]["f"].get<double>(), 15.572, 0.5e-3);
  EXPECT_NEAR(rows[1]["f"].get<double>(), 92.000, 0.5e-3);
  EXPECT_NEAR(rows[2]["f"].get<double>(), 4.107, 0.5e-3);
  EXPECT_EQ(rows[3]["df"].get<int>(), 54);
  EXPECT_EQ(j["two_way"]["ss_type"], "Type III");
  EXPECT_TRUE(j["two_way"]["balanced"].get<bool>());

  const io::CsvTable t = io::CsvTable::Read(out_csv);
  EXPECT_EQ(t.header(), (std::vector<std::string>{"table", "row", "statistic", "value"}));
  bool found = false;
  for (std::size_t i = 0; i < t.rows(); ++i)
    if (t.Text(i, 0) == "two_way" && t.Text(i, 1) == "supp:dose" && t.Text(i, 2) == "f") {
      EXPECT_NEAR(t.Number(i, 3), 4.107, 0.5e-3);
      found = true;
    }
  EXPECT_TRUE(found);
}

TEST(StatsCommandTest, TextOutputShowsEveryPart) {
  const auto r =
      RunHoofimpact("stats --csv " + WritePlantGrowth() + " --response weight --factor group");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* part :
       {"ANOVA", "eta^2", "Bartlett", "Welch", "Transform:", "Fisher's LSD", "trt1 - trt2"})
    EXPECT_NE(r.out.find(part), std::string::npos) << part << "\n" << r.out;
}

TEST(StatsCommandTest, MissingColumnIsNamedWithNonZeroExit) {
  const auto r =
      RunHoofimpact("stats --csv " + WritePlantGrowth() + " --response wieght --factor group");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("\"wieght\""), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("plant_growth.csv"), std::string::npos) << r.err;
}

TEST(StatsCommandTest, BadValuesAndGroupsAreNamed) {
  const std::string path = Dir() + "/bad.csv";
  {
    std::ofstream out(path);
    out << "g,y\na,1\na,2\nb,x3\nb,4\n";
  }
  auto r = RunHoofimpact("stats --csv " + path + " --response y --factor g");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("bad.csv:4: column \"y\" value \"x3\""), std::string::npos) << r.err;
  {
    std::ofstream out(path);
    out << "g,y\na,1\na,2\nlonely,3\n";
  }
  r = RunHoofimpact("stats --csv " + path + " --response y --factor g");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("group \"lonely\" has 1 observation"), std::string::npos) << r.err;
  {
    std::ofstream out(path);
    out << "g,y\na,1\n,2\nb,3\n";
  }
  r = RunHoofimpact("stats --csv " + path + " --response y --factor g");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("bad.csv:3: column \"g\" is empty"), std::string::npos) << r.err;
}

// Rows whose response has no value (empty, or nan as results.csv writes what was not measured
// or is not defined, such as mu_eff of a normal impact) are left out, and the output names
// their lines; the analysis is that of the other rows. Every row without a value is an error.
TEST(StatsCommandTest, RowsWithoutAValueAreLeftOutAndNamed) {
  const std::string path = Dir() + "/no_value.csv";
  {
    std::ofstream out(path);
    out << "group,weight\n";
    const char* groups[] = {"ctrl", "trt1", "trt2"};
    const double w[3][10] = {{4.17, 5.58, 5.18, 6.11, 4.50, 4.61, 5.17, 4.53, 5.33, 5.14},
                             {4.81, 4.17, 4.41, 3.59, 5.87, 3.83, 6.03, 4.89, 4.32, 4.69},
                             {6.31, 5.12, 5.54, 5.50, 5.37, 5.29, 4.92, 6.15, 5.80, 5.26}};
    for (int g = 0; g < 3; ++g) {
      for (int i = 0; i < 10; ++i) out << groups[g] << "," << w[g][i] << "\n";
      out << groups[g] << (g == 1 ? ",\n" : ",nan\n");  // lines 12, 23, 34
    }
  }
  auto r = RunHoofimpact("stats --csv " + path + " --response weight --factor group --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out).at("results");
  EXPECT_EQ(j["input"]["observations"].get<int>(), 30);
  EXPECT_EQ(j["input"]["left_out_lines"], nlohmann::json({12, 23, 34}));
  // PlantGrowth's R results, as without the three rows.
  EXPECT_NEAR(j["anova"]["between"]["f"].get<double>(), 4.8461, 0.5e-4);
  EXPECT_EQ(j["anova"]["within"]["df"].get<int>(), 27);
  r = RunHoofimpact("stats --csv " + path + " --response weight --factor group");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("Left out: 3 row(s) without a value of weight (empty or nan), on line(s) "
                       "12, 23, 34"),
            std::string::npos)
      << r.out;
  {
    std::ofstream out(path);
    out << "group,weight\na,nan\nb,\n";
  }
  r = RunHoofimpact("stats --csv " + path + " --response weight --factor group");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("no row has a value of \"weight\""), std::string::npos) << r.err;
}

TEST(StatsCommandTest, UsageErrorsExitWithTwo) {
  EXPECT_EQ(RunHoofimpact("stats --response y --factor g").exit_code, 2);
  EXPECT_EQ(RunHoofimpact("stats --csv x.csv --response y").exit_code, 2);
  EXPECT_EQ(RunHoofimpact("stats --csv " + WritePlantGrowth() +
                          " --response weight --factor group --alpha 1.5")
                .exit_code,
            2);
  const auto help = RunHoofimpact("stats --help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("--factor2"), std::string::npos);
}

// ------------------------------------------------------------------------------------------
// Study mode: a study file written here with the PlantGrowth weights / 10 as e (the one-way F,
// Bartlett K^2 and LSD p are scale-free, so R's published numbers still hold), surfaces
// steel/concrete/asphalt for ctrl/trt1/trt2, angles 0 and 20 deg alternating, two speeds, and
// one failed trial.
// ------------------------------------------------------------------------------------------

struct PlantStudy {
  std::string path;
  std::vector<double> oblique_mu;  ///< mu_eff of the 20 deg trials, in order
  std::vector<std::string> oblique_surface;
};

PlantStudy WritePlantStudy(const std::string& name) {
  const double w[3][10] = {{4.17, 5.58, 5.18, 6.11, 4.50, 4.61, 5.17, 4.53, 5.33, 5.14},
                           {4.81, 4.17, 4.41, 3.59, 5.87, 3.83, 6.03, 4.89, 4.32, 4.69},
                           {6.31, 5.12, 5.54, 5.50, 5.37, 5.29, 4.92, 6.15, 5.80, 5.26}};
  const char* surfaces[] = {"steel", "concrete", "asphalt"};
  PlantStudy study;
  std::vector<pipeline::TrialAnalysis> trials;
  for (int g = 0; g < 3; ++g)
    for (int i = 0; i < 10; ++i) {
      pipeline::TrialAnalysis t;
      t.spec.id = std::string(surfaces[g]) + "_" + std::to_string(i);
      t.spec.surface = surfaces[g];
      t.spec.surface_angle_deg = i % 2 == 0 ? 0.0 : 20.0;
      t.spec.nominal_speed_m_s = i % 4 < 2 ? 2.0 : 4.0;
      t.spec.fps = 8000;
      t.success = t.impact.success = true;
      t.impact.e = w[g][i] / 10;
      // Normal impacts get an absurd mu_eff: it must never reach the mu_eff tables.
      t.impact.mu_eff = i % 2 == 0 ? 9.99 : 0.1 + 0.05 * g + 0.003 * i;
      if (i % 2 == 1) {
        study.oblique_mu.push_back(t.impact.mu_eff);
        study.oblique_surface.push_back(surfaces[g]);
      }
      trials.push_back(t);
    }
  pipeline::TrialAnalysis failed;
  failed.spec.id = "steel_broken";
  failed.spec.surface = "steel";
  failed.error = "steel_broken/frames/000003.png: frame 3 is missing";
  trials.push_back(failed);
  study.path = Dir() + "/" + name + ".h5";
  studyfile::StudyInfo info;
  info.name = "plant";
  studyfile::WriteStudyFile(study.path, info, trials);
  return study;
}

TEST(StatsCommandTest, StudyFileGivesRsNumbersAndStoresTheTables) {
  const PlantStudy study = WritePlantStudy("plant_study_json");
  const std::string out_csv = Dir() + "/study_tables.csv";
  const auto r = RunHoofimpact("stats " + study.path + " --json --out-csv " + out_csv);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out).at("results");
  ASSERT_EQ(j["excluded"].size(), 1u);
  EXPECT_EQ(j["excluded"][0]["id"], "steel_broken");
  EXPECT_NE(j["excluded"][0]["reason"].get<std::string>().find("000003.png"), std::string::npos);

  // e by surface: R's PlantGrowth numbers (see JsonMatchesRForPlantGrowth).
  const auto& e = j["responses"]["e"];
  EXPECT_EQ(e["observations"].get<int>(), 30);
  EXPECT_NEAR(e["by_surface"]["anova"]["between"]["f"].get<double>(), 4.8461, 0.5e-4);
  EXPECT_NEAR(e["by_surface"]["anova"]["between"]["p"].get<double>(), 0.01591, 0.5e-5);
  EXPECT_NEAR(e["by_surface"]["bartlett"]["k_squared"].get<double>(), 2.8786, 0.5e-4);
  ASSERT_TRUE(e["by_surface"]["lsd"]["performed"].get<bool>());
  EXPECT_NEAR(e["by_surface"]["lsd"]["pairs"][2]["p"].get<double>(), 0.0045, 0.5e-4);
  EXPECT_FALSE(e["by_angle"]["anova"].is_null());
  EXPECT_FALSE(e["by_speed"]["anova"].is_null());
  EXPECT_EQ(e["two_way"]["rows"][0]["source"], "surface");
  ASSERT_EQ(e["cells"].size(), 6u);
  EXPECT_EQ(e["cells"][0]["surface"], "steel");
  EXPECT_EQ(e["cells"][0]["angle_deg"], "0");
  EXPECT_EQ(e["cells"][0]["n"].get<int>(), 5);
  EXPECT_NEAR(e["cells"][0]["mean"].get<double>(), (4.17 + 5.18 + 4.50 + 5.17 + 5.33) / 50, 1e-12);

  // mu_eff: oblique trials only, and the library's F on exactly those values.
  const auto& mu = j["responses"]["mu_eff"];
  EXPECT_EQ(mu["observations"].get<int>(), 15);
  const auto expected =
      stats::AnalyzeOneWay(stats::GroupByLabel(study.oblique_mu, study.oblique_surface));
  EXPECT_DOUBLE_EQ(mu["by_surface"]["anova"]["between"]["f"].get<double>(),
                   expected.original.anova.f);
  EXPECT_FALSE(mu["by_angle"]["note"].get<std::string>().empty());  // one angle level

  // The same tables in the study file, and in the CSV.
  const studyfile::Table anova = studyfile::ReadTable(study.path, "/stats/e/by_surface/anova");
  EXPECT_NEAR(std::get<std::vector<double>>(anova.Get("f").values)[0], 4.8461, 0.5e-4);
  const studyfile::Table excluded = studyfile::ReadTable(study.path, "/stats/excluded");
  EXPECT_EQ(std::get<std::vector<std::string>>(excluded.Get("id").values),
            std::vector<std::string>{"steel_broken"});
  const io::CsvTable t = io::CsvTable::Read(out_csv);
  bool found = false;
  for (std::size_t i = 0; i < t.rows(); ++i)
    if (t.Text(i, 0) == "e/by_surface/lsd" && t.Text(i, 1) == "concrete - asphalt" &&
        t.Text(i, 2) == "p") {
      EXPECT_NEAR(t.Number(i, 3), 0.0045, 0.5e-4);
      found = true;
    }
  EXPECT_TRUE(found);
  // The trials are still there after /stats was added.
  EXPECT_EQ(studyfile::ReadStudyResults(study.path).trials.size(), 31u);
}

TEST(StatsCommandTest, StudyTextOutputAndUsageErrors) {
  const PlantStudy study = WritePlantStudy("plant_study_text");
  const auto r = RunHoofimpact("stats " + study.path);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* part :
       {"mean (s.d., n) per surface x angle", "e by surface: F(2, 27)", "excluded steel_broken",
        "Fisher's LSD", "Two-way ANOVA", "mu_eff (successful oblique trials", "under /stats"})
    EXPECT_NE(r.out.find(part), std::string::npos) << part << "\n" << r.out;
  EXPECT_EQ(RunHoofimpact("stats " + study.path + " --csv " + study.path).exit_code, 2);
  EXPECT_EQ(RunHoofimpact("stats " + study.path + " --response e").exit_code, 2);
  EXPECT_EQ(RunHoofimpact("stats " + Dir() + "/no_such.h5").exit_code, 2);
  const std::string text = Dir() + "/not_a_study.h5";
  std::ofstream(text) << "group,weight\n";
  const auto not_h5 = RunHoofimpact("stats " + text);
  EXPECT_EQ(not_h5.exit_code, 1);
  EXPECT_NE(not_h5.err.find("not_a_study.h5"), std::string::npos) << not_h5.err;
}

}  // namespace
}  // namespace hoof::cli
