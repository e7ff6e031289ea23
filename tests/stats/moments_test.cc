// The shifted, compensated moments against a 50-digit evaluation of the definitions, on the
// hardest NIST set as read (SmLs09: 18009 doubles near 1e12) and on seeded unbalanced data.
#include "stats/moments.h"

#include <map>
#include <random>

#include <gtest/gtest.h>
#include <boost/multiprecision/cpp_bin_float.hpp>

#include "nist_dat.h"

namespace hoof::stats {
namespace {

using Big = boost::multiprecision::cpp_bin_float_50;

void ExpectMomentsExact(const GroupedData& d) {
  const Moments m = ComputeMoments(d);
  ASSERT_EQ(m.groups.size(), d.groups());
  EXPECT_EQ(m.shift, d.values[0][0]);
  Big grand = 0;
  for (std::size_t g = 0; g < d.groups(); ++g) {
    Big sum = 0;
    for (double y : d.values[g]) sum += Big(y);
    const Big mean = sum / Big(static_cast<long long>(d.values[g].size()));
    Big ss = 0;
    for (double y : d.values[g]) ss += (Big(y) - mean) * (Big(y) - mean);
    grand += sum;
    const Big offset = mean - Big(m.shift);
    EXPECT_EQ(m.groups[g].n, d.values[g].size());
    // The offsets are long double (64-bit significand) and of order 0.1 here: 1e-17
    // relative plus 1e-18 absolute is well inside what double would give (1e-17 absolute).
    EXPECT_NEAR(static_cast<double>(m.groups[g].mean_offset), static_cast<double>(offset),
                1e-17 * std::fabs(static_cast<double>(offset)) + 1e-18);
    EXPECT_NEAR(static_cast<double>(m.groups[g].sum_sq), static_cast<double>(ss),
                1e-15 * static_cast<double>(ss));
  }
  const Big grand_offset = grand / Big(static_cast<long long>(d.observations())) - Big(m.shift);
  EXPECT_NEAR(static_cast<double>(m.grand_mean_offset), static_cast<double>(grand_offset),
              1e-17 * std::fabs(static_cast<double>(grand_offset)) + 1e-18);
  EXPECT_EQ(m.total_n, d.observations());
}

TEST(MomentsTest, SmLs09AsReadMatchesFiftyDigits) {
  const auto f = testing::ReadNistAnova("SmLs09");
  ExpectMomentsExact(GroupByLabel(f.values, f.labels));
}

TEST(MomentsTest, SeededUnbalancedDataMatchFiftyDigits) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> y;
  std::vector<std::string> labels;
  for (int g = 0; g < 4; ++g)
    for (int i = 0; i < 5 + 40 * g; ++i) {
      y.push_back(123456.789 + 1e-3 * g + 1e-4 * u(rng));
      labels.push_back(std::to_string(g));
    }
  ExpectMomentsExact(GroupByLabel(y, labels));
}

}  // namespace
}  // namespace hoof::stats
