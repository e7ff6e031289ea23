// End-to-end tests of `hoofimpact stats` on small CSV files written here, against R's
// published results for the same data (PlantGrowth, ToothGrowth; see the library tests).
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/csv.h"
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
  const auto j = nlohmann::json::parse(r.out);
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
  const auto j = nlohmann::json::parse(r.out);
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

}  // namespace
}  // namespace hoof::cli
