// Bartlett's test against R and closed forms.
#include "stats/bartlett.h"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "nist_dat.h"

namespace hoof::stats {
namespace {

// R 4.2: bartlett.test(resistance ~ factor(instrument)) on SiRstv gives
// "Bartlett's K-squared = 1.1481, df = 4, p-value = 0.8866" (quoted in SiRstv.dat).
TEST(BartlettTest, SiRstvMatchesR) {
  const auto f = testing::ReadNistAnova("SiRstv");
  const BartlettResult r = Bartlett(GroupByLabel(f.values, f.labels));
  EXPECT_NEAR(r.k_squared, 1.1481, 0.5e-4);
  EXPECT_EQ(r.df, 4u);
  EXPECT_NEAR(r.p, 0.8866, 0.5e-4);
  EXPECT_TRUE(r.note.empty());
}

// R: bartlett.test(weight ~ group, data = PlantGrowth) prints
// "Bartlett's K-squared = 2.8786, df = 2, p-value = 0.2371" (many published tutorials).
TEST(BartlettTest, PlantGrowthMatchesR) {
  const auto data = MakeGroups({"ctrl", "trt1", "trt2"},
                               {{4.17, 5.58, 5.18, 6.11, 4.50, 4.61, 5.17, 4.53, 5.33, 5.14},
                                {4.81, 4.17, 4.41, 3.59, 5.87, 3.83, 6.03, 4.89, 4.32, 4.69},
                                {6.31, 5.12, 5.54, 5.50, 5.37, 5.29, 4.92, 6.15, 5.80, 5.26}});
  const BartlettResult r = Bartlett(data);
  EXPECT_NEAR(r.k_squared, 2.8786, 0.5e-4);
  EXPECT_EQ(r.df, 2u);
  EXPECT_NEAR(r.p, 0.2371, 0.5e-4);
}

// Two groups of 3 with variances 1 and 4: s_p^2 = 2.5, C = 1 + (1/2 + 1/2 - 1/4) / 3 = 1.25,
// K^2 = (4 ln 2.5 - 2 ln 1 - 2 ln 4) / 1.25; with one df, p = P(chi2_1 >= K^2) =
// erfc(sqrt(K^2 / 2)).
TEST(BartlettTest, HandComputedTwoGroups) {
  const BartlettResult r = Bartlett(MakeGroups({"a", "b"}, {{0, 1, 2}, {10, 12, 14}}));
  const double k2 = (4.0 * std::log(2.5) - 2.0 * std::log(4.0)) / 1.25;
  EXPECT_NEAR(r.k_squared, k2, 1e-14);
  EXPECT_NEAR(r.p, std::erfc(std::sqrt(k2 / 2.0)), 1e-14);
  EXPECT_DOUBLE_EQ(r.pooled_variance, 2.5);
}

// Equal sample variances give K^2 = 0 exactly (the log terms cancel), and the statistic does
// not depend on the unit of the response.
TEST(BartlettTest, EqualVariancesAndScaleInvariance) {
  const BartlettResult same = Bartlett(MakeGroups({"a", "b"}, {{1, 2, 3}, {21, 22, 23}}));
  EXPECT_NEAR(same.k_squared, 0.0, 1e-14);
  EXPECT_NEAR(same.p, 1.0, 1e-12);
  // Variances 1 and 2/3: unequal, K^2 > 0; the same data in other units give the same K^2.
  const BartlettResult unequal = Bartlett(MakeGroups({"a", "b"}, {{1, 2, 3}, {11, 12, 13, 12}}));
  const BartlettResult scaled =
      Bartlett(MakeGroups({"a", "b"}, {{1e3, 2e3, 3e3}, {11e3, 12e3, 13e3, 12e3}}));
  EXPECT_GT(unequal.k_squared, 0.0);
  EXPECT_NEAR(scaled.k_squared, unequal.k_squared, 1e-13);
}

// One constant group: ln s^2 = -inf, so K^2 = inf and p = 0 (as R's bartlett.test); the note
// names the group. All groups constant: undefined, std::invalid_argument.
TEST(BartlettTest, ZeroVarianceGroups) {
  const BartlettResult r = Bartlett(MakeGroups({"a", "flat"}, {{1, 2, 3}, {5, 5, 5}}));
  EXPECT_TRUE(std::isinf(r.k_squared));
  EXPECT_EQ(r.p, 0.0);
  EXPECT_NE(r.note.find("group \"flat\" has zero variance"), std::string::npos) << r.note;
  try {
    Bartlett(MakeGroups({"a", "b"}, {{1, 1}, {2, 2}}));
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("every group is constant"), std::string::npos);
  }
  EXPECT_THROW(Bartlett(MakeGroups({"a", "b"}, {{1, 2}, {3}})), std::invalid_argument);
}

}  // namespace
}  // namespace hoof::stats
