// The statistics' text, JSON and long CSV (study/statistics_text.h), read without running the
// command, on a one-way layout whose ANOVA is known in closed form: groups {1, 2, 3} and
// {4, 5, 6} have means 2 and 5, SS between 2 * 3 * 1.5^2 = 13.5 on 1 df, SS within 4 on 4 df,
// so F = 13.5 / 1 = 13.5.
#include "study/statistics_text.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "stats/grouping.h"

namespace hoof::study {
namespace {

stats::OneWayAnalysis TwoGroups() {
  const std::vector<double> y{1, 2, 3, 4, 5, 6};
  const std::vector<std::string> g{"a", "a", "a", "b", "b", "b"};
  return stats::AnalyzeOneWay(stats::GroupByLabel(y, g), {});
}

TEST(StatisticsTextTest, TheJsonCarriesTheClosedFormAnova) {
  const auto s = TwoGroups();
  const nlohmann::json j = OneWayJson(s.original, s.alpha);
  EXPECT_EQ(j["anova"]["between"]["df"], 1);
  EXPECT_NEAR(j["anova"]["between"]["ss"].get<double>(), 13.5, 1e-12);
  EXPECT_NEAR(j["anova"]["within"]["ss"].get<double>(), 4.0, 1e-12);
  EXPECT_EQ(j["anova"]["within"]["df"], 4);
  EXPECT_NEAR(j["anova"]["between"]["f"].get<double>(), 13.5, 1e-12);
  ASSERT_EQ(j["groups"].size(), 2U);
  EXPECT_EQ(j["groups"][0]["label"], "a");
  EXPECT_NEAR(j["groups"][1]["mean"].get<double>(), 5.0, 1e-12);
}

TEST(StatisticsTextTest, TheLongCsvHasOneRowPerStatistic) {
  const auto s = TwoGroups();
  const auto path = std::filesystem::temp_directory_path() / "statistics_text_test.csv";
  WriteLongCsv(path.string(), s, std::nullopt);
  std::ifstream in(path);
  std::vector<std::string> rows;
  for (std::string line; std::getline(in, line);) rows.push_back(line);
  std::filesystem::remove(path);
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows[0], "table,row,statistic,value");
  const auto has = [&](const std::string& prefix) {
    for (const auto& r : rows)
      if (r.rfind(prefix, 0) == 0) return true;
    return false;
  };
  EXPECT_TRUE(has("anova,between,ss,13.5"));
  EXPECT_TRUE(has("anova,within,df,4"));
  EXPECT_TRUE(has("groups,a,mean,2"));
  EXPECT_TRUE(has("groups,b,n,3"));
}

TEST(StatisticsTextTest, TheTextNamesTheResponseTheFactorAndTheSource) {
  const auto s = TwoGroups();
  std::ostringstream os;
  WriteOneWayAnalysisText(os, "e", "surface", "table.csv", 6, s, std::nullopt);
  const std::string text = os.str();
  EXPECT_EQ(text.rfind("One-way analysis of e by surface (table.csv, 6 observations", 0), 0U)
      << text;
  EXPECT_NE(text.find("13.5"), std::string::npos);
}

// F = 13.5 on (1, 4) df gives p = 0.021 < 0.05, so the LSD runs and separates the groups:
// b (mean 5) gets the letter a, a (mean 2) the letter b.
TEST(StatisticsTextTest, TheGroupTableCarriesTheLsdLetters) {
  const auto s = TwoGroups();
  ASSERT_TRUE(s.original.lsd_performed);
  std::ostringstream os;
  WriteOneWayText(os, s.original, s.alpha);
  const std::string text = os.str();
  EXPECT_NE(text.find("  LSD\n"), std::string::npos) << text;
  std::istringstream lines(text);
  int found = 0;
  for (std::string line; std::getline(lines, line);) {
    for (const auto& [group, letter] : {std::pair{"a", "  b"}, std::pair{"b", "  a"}})
      if (line.rfind(std::string("    ") + group + std::string(19, ' '), 0) == 0) {  // setw(20)
        EXPECT_EQ(line.substr(line.size() - 3), letter) << line;
        ++found;
      }
  }
  EXPECT_EQ(found, 2) << text;
}

// The s.d. of a cell of one trial is undefined: "n/a", as the report prints it (it read "-").
TEST(StatisticsTextTest, AOneTrialCellHasNoStandardDeviation) {
  StudyStatistics st;
  st.path = "study.h5";
  ResponseAnalysis r;
  r.response = "e";
  r.selection = "every measured trial";
  r.values = {0.80, 0.85, 0.90};
  r.surface = {"steel", "steel", "asphalt"};
  r.angle = {"0", "0", "20"};
  r.speed = {"3", "3", "3"};
  r.cells = {{"steel|0", 2, 0.825, 0.00125, 0.0353553}, {"asphalt|20", 1, 0.9, 0.0, 0.0}};
  r.two_way_note = "too few trials";
  st.responses = {r};
  std::ostringstream os;
  WriteStudyStatisticsText(os, st);
  const std::string text = os.str();
  EXPECT_NE(text.find("0.9000 (n/a, 1)"), std::string::npos) << text;
  EXPECT_NE(text.find("0.8250 (0.03536, 2)"), std::string::npos) << text;
  EXPECT_EQ(text.find("(-, 1)"), std::string::npos) << text;
}

}  // namespace
}  // namespace hoof::study
