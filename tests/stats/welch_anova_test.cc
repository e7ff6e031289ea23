// Welch's ANOVA against R and against the two-sample Welch t-test written out by hand.
#include "stats/welch_anova.h"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

namespace hoof::stats {
namespace {

// R: oneway.test(weight ~ group, data = PlantGrowth) prints
// "F = 5.181, num df = 2.000, denom df = 17.128, p-value = 0.01739".
TEST(WelchAnovaTest, PlantGrowthMatchesR) {
  const auto data = MakeGroups({"ctrl", "trt1", "trt2"},
                               {{4.17, 5.58, 5.18, 6.11, 4.50, 4.61, 5.17, 4.53, 5.33, 5.14},
                                {4.81, 4.17, 4.41, 3.59, 5.87, 3.83, 6.03, 4.89, 4.32, 4.69},
                                {6.31, 5.12, 5.54, 5.50, 5.37, 5.29, 4.92, 6.15, 5.80, 5.26}});
  const WelchAnovaResult r = WelchAnova(data);
  EXPECT_NEAR(r.f, 5.181, 0.5e-3);
  EXPECT_DOUBLE_EQ(r.df1, 2.0);
  EXPECT_NEAR(r.df2, 17.128, 0.5e-3);
  EXPECT_NEAR(r.p, 0.01739, 0.5e-5);
}

// R: t.test(extra ~ group, data = sleep) (Welch) prints "t = -1.8608, df = 17.776,
// p-value = 0.07939". With k = 2 Welch's F is t^2 and df2 the Welch-Satterthwaite df.
TEST(WelchAnovaTest, SleepMatchesRsWelchTTest) {
  const auto data = MakeGroups({"1", "2"}, {{0.7, -1.6, -0.2, -1.2, -0.1, 3.4, 3.7, 0.8, 0.0, 2.0},
                                            {1.9, 0.8, 1.1, 0.1, -0.1, 4.4, 5.5, 1.6, 4.6, 3.4}});
  const WelchAnovaResult r = WelchAnova(data);
  EXPECT_NEAR(std::sqrt(r.f), 1.8608, 0.5e-4);
  EXPECT_NEAR(r.df2, 17.776, 0.5e-3);
  EXPECT_NEAR(r.p, 0.07939, 0.5e-5);
}

// k = 2 identity, unequal sizes: F = t^2 with t = (m1 - m2) / sqrt(v1/n1 + v2/n2) and
// df2 = (v1/n1 + v2/n2)^2 / ((v1/n1)^2/(n1-1) + (v2/n2)^2/(n2-1)) (Welch 1947).
TEST(WelchAnovaTest, TwoGroupsEqualTheWelchTTest) {
  // {1, 2, 3, 6}: mean 3, variance 14/3.  {10, 11}: mean 10.5, variance 1/2.
  const WelchAnovaResult r = WelchAnova(MakeGroups({"a", "b"}, {{1, 2, 3, 6}, {10, 11}}));
  const double a = (14.0 / 3.0) / 4.0, b = 0.5 / 2.0;
  const double t = (3.0 - 10.5) / std::sqrt(a + b);
  const double df = (a + b) * (a + b) / (a * a / 3.0 + b * b / 1.0);
  EXPECT_NEAR(r.f, t * t, 1e-12 * t * t);
  EXPECT_NEAR(r.df2, df, 1e-12 * df);
  EXPECT_DOUBLE_EQ(r.df1, 1.0);
}

TEST(WelchAnovaTest, ZeroVarianceGroupIsNamed) {
  try {
    WelchAnova(MakeGroups({"a", "flat"}, {{1, 2, 3}, {4, 4}}));
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("group \"flat\" has zero variance"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(WelchAnova(MakeGroups({"a"}, {{1, 2, 3}})), std::invalid_argument);
}

}  // namespace
}  // namespace hoof::stats
