// Fisher's LSD against R and against a case small enough for closed forms.
#include "stats/fisher_lsd.h"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

namespace hoof::stats {
namespace {

// R: pairwise.t.test(PlantGrowth$weight, PlantGrowth$group, p.adjust.method = "none")
// prints p = 0.194 (ctrl-trt1), 0.088 (ctrl-trt2), 0.004 (trt1-trt2). The trt1-trt2
// contrast with the pooled MSE has F = t^2 = 9.6273, p = 0.0045 (scipy stats.f.sf, in a
// published worked example). Mean differences are exact: means 5.032, 4.661, 5.526.
TEST(FisherLsdTest, PlantGrowthMatchesR) {
  const auto data = MakeGroups({"ctrl", "trt1", "trt2"},
                               {{4.17, 5.58, 5.18, 6.11, 4.50, 4.61, 5.17, 4.53, 5.33, 5.14},
                                {4.81, 4.17, 4.41, 3.59, 5.87, 3.83, 6.03, 4.89, 4.32, 4.69},
                                {6.31, 5.12, 5.54, 5.50, 5.37, 5.29, 4.92, 6.15, 5.80, 5.26}});
  const auto pairs = FisherLsd(data, 0.05);
  ASSERT_EQ(pairs.size(), 3u);
  EXPECT_EQ(pairs[0].group_a, "ctrl");
  EXPECT_EQ(pairs[0].group_b, "trt1");
  EXPECT_NEAR(pairs[0].difference, 0.371, 1e-13);
  EXPECT_NEAR(pairs[1].difference, -0.494, 1e-13);
  EXPECT_NEAR(pairs[2].difference, -0.865, 1e-13);
  EXPECT_NEAR(pairs[0].p, 0.194, 0.5e-3);
  EXPECT_NEAR(pairs[1].p, 0.088, 0.5e-3);
  EXPECT_NEAR(pairs[2].p, 0.0045, 0.5e-4);
  EXPECT_NEAR(pairs[2].t * pairs[2].t, 9.6273, 0.5e-4);
  EXPECT_FALSE(pairs[0].significant);
  EXPECT_FALSE(pairs[1].significant);
  EXPECT_TRUE(pairs[2].significant);
  for (const auto& c : pairs) EXPECT_EQ(c.df, 27u);
}

// Groups {0, 2} and {3, 7}: means 1 and 5, SS_within = 2 + 8 = 10, df = 2, MSE = 5,
// se = sqrt(5 (1/2 + 1/2)) = sqrt 5, t = -4 / sqrt 5. With 2 df the t distribution has closed
// forms: p = 1 - |t| / sqrt(2 + t^2) = 1 - 4 / sqrt 26, and the 0.975 quantile is
// 0.95 / sqrt(2 * 0.975 * 0.025).
TEST(FisherLsdTest, TwoDegreesOfFreedomClosedForm) {
  const auto pairs = FisherLsd(MakeGroups({"a", "b"}, {{0, 2}, {3, 7}}), 0.05);
  ASSERT_EQ(pairs.size(), 1u);
  const auto& c = pairs[0];
  EXPECT_DOUBLE_EQ(c.difference, -4.0);
  EXPECT_NEAR(c.standard_error, std::sqrt(5.0), 1e-15);
  EXPECT_NEAR(c.t, -4.0 / std::sqrt(5.0), 1e-15);
  EXPECT_EQ(c.df, 2u);
  EXPECT_NEAR(c.p, 1.0 - 4.0 / std::sqrt(26.0), 1e-14);
  const double half = 0.95 / std::sqrt(2.0 * 0.975 * 0.025) * std::sqrt(5.0);
  EXPECT_NEAR(c.ci_low, -4.0 - half, 1e-12);
  EXPECT_NEAR(c.ci_high, -4.0 + half, 1e-12);
  EXPECT_FALSE(c.significant);
}

TEST(FisherLsdTest, BadAlphaAndBadDataAreRejected) {
  const auto data = MakeGroups({"a", "b"}, {{0, 2}, {3, 7}});
  EXPECT_THROW(FisherLsd(data, 0.0), std::invalid_argument);
  EXPECT_THROW(FisherLsd(data, 1.0), std::invalid_argument);
  EXPECT_THROW(FisherLsd(MakeGroups({"a", "b"}, {{1, 1}, {2, 2}}), 0.05), std::invalid_argument);
}

}  // namespace
}  // namespace hoof::stats
