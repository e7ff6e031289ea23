// AccurateSum against sums whose exact value is known by construction.
#include "stats/accurate_sum.h"

#include <cmath>

#include <gtest/gtest.h>

namespace hoof::stats {
namespace {

// 1 + 1000 * 1e-20 - 1 = 1e-17 exactly (in real arithmetic). A plain long double loop loses
// every 1e-20 (half an ulp of 1 is 5.4e-20) and returns 0.
TEST(AccurateSumTest, RecoversTermsBelowTheLastPlace) {
  AccurateSum s;
  s.Add(1.0L);
  for (int i = 0; i < 1000; ++i) s.Add(1e-20L);
  s.Add(-1.0L);
  EXPECT_NEAR(static_cast<double>(s.Value()), 1e-17, 1e-17 * 1e-12);
  long double plain = 1.0L;
  for (int i = 0; i < 1000; ++i) plain += 1e-20L;
  plain -= 1.0L;
  EXPECT_EQ(plain, 0.0L);  // the failure AccurateSum exists to avoid
}

// Neumaier's branch: a large term arriving after small ones, 1e30 + 1 - 1e30 = 1.
TEST(AccurateSumTest, LargeTermAfterSmallOnes) {
  AccurateSum s;
  s.Add(1.0L);
  s.Add(1e30L);
  s.Add(-1e30L);
  EXPECT_EQ(s.Value(), 1.0L);
}

TEST(AccurateSumTest, EmptySumIsZero) { EXPECT_EQ(AccurateSum().Value(), 0.0L); }

}  // namespace
}  // namespace hoof::stats
