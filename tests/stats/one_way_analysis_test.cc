// The one-way workflow: which steps run, on which scale, for data whose answers are known
// (SiRstv and PlantGrowth from R; multiplicative groups whose log-scale spreads are equal).
#include "stats/one_way_analysis.h"

#include <array>
#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "nist_dat.h"

namespace hoof::stats {
namespace {

GroupedData PlantGrowth() {
  return MakeGroups({"ctrl", "trt1", "trt2"},
                    {{4.17, 5.58, 5.18, 6.11, 4.50, 4.61, 5.17, 4.53, 5.33, 5.14},
                     {4.81, 4.17, 4.41, 3.59, 5.87, 3.83, 6.03, 4.89, 4.32, 4.69},
                     {6.31, 5.12, 5.54, 5.50, 5.37, 5.29, 4.92, 6.15, 5.80, 5.26}});
}

// SiRstv (R: ANOVA p = 0.34945, Bartlett p = 0.8866): nothing is significant, so no
// transform and no LSD; Welch is reported.
TEST(OneWayAnalysisTest, SiRstvNeedsNeitherTransformNorLsd) {
  const auto f = testing::ReadNistAnova("SiRstv");
  const OneWayAnalysis a = AnalyzeOneWay(GroupByLabel(f.values, f.labels));
  EXPECT_NEAR(a.original.anova.p, 0.34945, 0.5e-5);
  EXPECT_NEAR(a.original.bartlett.p, 0.8866, 0.5e-4);
  EXPECT_FALSE(a.transform.considered);
  EXPECT_FALSE(a.transform.applied);
  EXPECT_FALSE(a.transform.rerun.has_value());
  EXPECT_NE(a.transform.reason.find("no transform"), std::string::npos) << a.transform.reason;
  EXPECT_FALSE(a.original.lsd_performed);
  EXPECT_TRUE(a.original.lsd.empty());
  EXPECT_NE(a.original.lsd_note.find("not performed"), std::string::npos);
  ASSERT_TRUE(a.original.welch.has_value());
  ASSERT_EQ(a.original.groups.size(), 5u);
  EXPECT_EQ(a.original.groups[0].label, "1");
}

// PlantGrowth (R: ANOVA p = 0.01591, Bartlett p = 0.2371): LSD runs, no transform.
TEST(OneWayAnalysisTest, PlantGrowthRunsLsdWithoutTransform) {
  const OneWayAnalysis a = AnalyzeOneWay(PlantGrowth());
  EXPECT_TRUE(a.original.lsd_performed);
  EXPECT_EQ(a.original.lsd.size(), 3u);
  EXPECT_FALSE(a.transform.considered);
  EXPECT_NEAR(a.original.welch->f, 5.181, 0.5e-3);
  // At alpha = 0.01 the ANOVA is no longer significant: the LSD gate closes.
  OneWayAnalysisOptions strict;
  strict.alpha = 0.01;
  EXPECT_FALSE(AnalyzeOneWay(PlantGrowth(), strict).original.lsd_performed);
}

// Groups m * exp(z) (m = 1, 5, 25; the same z in each): standard deviations in the ratio
// 1 : 5 : 25, so Bartlett rejects; on the log scale the groups differ only in location, so
// the rerun has identical group variances and Bartlett's K^2 is exactly 0.
TEST(OneWayAnalysisTest, MultiplicativeGroupsAreLogTransformed) {
  const std::array<double, 8> z = {-0.4, -0.25, -0.1, 0.0, 0.05, 0.2, 0.3, 0.45};
  std::vector<std::vector<double>> g(3);
  const std::array<double, 3> m = {1.0, 5.0, 25.0};
  for (std::size_t i = 0; i < 3; ++i)
    for (double zi : z) g[i].push_back(m[i] * std::exp(zi));
  const OneWayAnalysis a = AnalyzeOneWay(MakeGroups({"low", "mid", "high"}, g));
  EXPECT_LT(a.original.bartlett.p, 1e-6);
  ASSERT_TRUE(a.transform.considered);
  ASSERT_TRUE(a.transform.applied);
  EXPECT_EQ(a.transform.box_cox->lambda, 0.0);  // see BoxCoxTest.RulePicksTheNearest...
  EXPECT_EQ(a.transform.formula, "ln(y)");
  ASSERT_TRUE(a.transform.rerun.has_value());
  const auto& rerun = *a.transform.rerun;
  EXPECT_NEAR(rerun.bartlett.k_squared, 0.0, 1e-10);
  EXPECT_NEAR(rerun.bartlett.p, 1.0, 1e-9);
  // Log-scale group means are ln m + mean(z), so differences are ln 5 and ln 25.
  EXPECT_NEAR(rerun.groups[1].mean - rerun.groups[0].mean, std::log(5.0), 1e-13);
  EXPECT_NEAR(rerun.groups[2].mean - rerun.groups[0].mean, std::log(25.0), 1e-13);
  EXPECT_TRUE(rerun.lsd_performed);
}

// A constant group: Welch is undefined and says why, naming the group; Bartlett is infinite.
TEST(OneWayAnalysisTest, ConstantGroupIsANoteNotAFailure) {
  const OneWayAnalysis a =
      AnalyzeOneWay(MakeGroups({"a", "flat"}, {{1.0, 2.0, 3.0, 2.5}, {5.0, 5.0, 5.0}}));
  EXPECT_FALSE(a.original.welch.has_value());
  EXPECT_NE(a.original.welch_note.find("\"flat\""), std::string::npos) << a.original.welch_note;
  EXPECT_TRUE(std::isinf(a.original.bartlett.k_squared));
  EXPECT_TRUE(a.transform.considered);
}

TEST(OneWayAnalysisTest, BadOptionsAndDataAreRejected) {
  OneWayAnalysisOptions o;
  o.alpha = 1.5;
  try {
    AnalyzeOneWay(PlantGrowth(), o);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("alpha = 1.5"), std::string::npos) << e.what();
  }
  EXPECT_THROW(AnalyzeOneWay(MakeGroups({"a", "b"}, {{1, 2}, {3}})), std::invalid_argument);
  EXPECT_THROW(AnalyzeOneWay(MakeGroups({"a"}, {{1, 2}})), std::invalid_argument);
}

}  // namespace
}  // namespace hoof::stats
