// The statistics' text, JSON and long CSV (study/statistics_text.h), read without running the
// command, on a one-way layout whose ANOVA is known in closed form: groups {1, 2, 3} and
// {4, 5, 6} have means 2 and 5, SS between 2 * 3 * 1.5^2 = 13.5 on 1 df, SS within 4 on 4 df,
// so F = 13.5 / 1 = 13.5.
#include "study/statistics_text.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
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

}  // namespace
}  // namespace hoof::study
