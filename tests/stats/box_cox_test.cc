// Box-Cox lambda against an independent evaluation: the profile log-likelihood written from
// its definition in 50-digit arithmetic (y^lambda itself, no shift or log1p tricks) and
// maximized by golden-section search in this file; plus invariances that hold exactly.
#include "stats/box_cox.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>
#include <boost/multiprecision/cpp_bin_float.hpp>

namespace hoof::stats {
namespace {

using Big = boost::multiprecision::cpp_bin_float_50;

/// l(lambda) = -(N/2) ln(SS_within(lambda) / N) + (lambda - 1) sum ln y, from the definition.
Big ProfileLogLikelihood(const std::vector<std::vector<double>>& groups, const Big& lambda) {
  Big ss = 0, log_sum = 0;
  long long n = 0;
  for (const auto& g : groups) {
    std::vector<Big> t;
    for (double y : g) {
      const Big yb(y);
      t.push_back(lambda == 0 ? Big(log(yb)) : Big((pow(yb, lambda) - 1) / lambda));
      log_sum += log(yb);
      ++n;
    }
    Big mean = 0;
    for (const Big& x : t) mean += x;
    mean /= Big(static_cast<long long>(t.size()));
    for (const Big& x : t) ss += (x - mean) * (x - mean);
  }
  return -Big(n) / 2 * log(ss / Big(n)) + (lambda - 1) * log_sum;
}

/// Maximizer of ProfileLogLikelihood on [lo, hi]: grid of 601 points, then golden section.
double IndependentLambdaMl(const std::vector<std::vector<double>>& g, double lo, double hi) {
  int best = 0;
  Big best_l = ProfileLogLikelihood(g, Big(lo));
  for (int i = 1; i <= 600; ++i) {
    const Big l = ProfileLogLikelihood(g, Big(lo + (hi - lo) * i / 600.0));
    if (l > best_l) {
      best_l = l;
      best = i;
    }
  }
  Big a = lo + (hi - lo) * std::max(best - 1, 0) / 600.0;
  Big b = lo + (hi - lo) * std::min(best + 1, 600) / 600.0;
  const Big r = (sqrt(Big(5)) - 1) / 2;
  for (int i = 0; i < 120; ++i) {
    const Big c = b - r * (b - a), d = a + r * (b - a);
    if (ProfileLogLikelihood(g, c) > ProfileLogLikelihood(g, d)) {
      b = d;
    } else {
      a = c;
    }
  }
  return static_cast<double>((a + b) / 2);
}

/// Groups whose spread grows with their level: group g is m_g * exp(z) for one set z.
/// On the log scale all three groups have exactly the same spread.
std::vector<std::vector<double>> Multiplicative() {
  const std::array<double, 8> z = {-0.4, -0.25, -0.1, 0.0, 0.05, 0.2, 0.3, 0.45};
  std::vector<std::vector<double>> g(3);
  const std::array<double, 3> m = {1.0, 5.0, 25.0};
  for (std::size_t i = 0; i < 3; ++i)
    for (double zi : z) g[i].push_back(m[i] * std::exp(zi));
  return g;
}

/// Four groups of four positive values with no particular structure (the likelihood has an
/// interior maximum with an interval inside the search range).
std::vector<std::vector<double>> Skewed() {
  return {{0.31, 0.45, 0.46, 0.43},
          {0.82, 1.10, 0.88, 0.72},
          {0.43, 0.45, 0.63, 0.76},
          {0.45, 0.71, 0.66, 0.62}};
}

GroupedData Make(const std::vector<std::vector<double>>& g) {
  std::vector<std::string> labels;
  for (std::size_t i = 0; i < g.size(); ++i)
    labels.push_back(std::string("g").append(std::to_string(i)));
  return MakeGroups(labels, g);
}

TEST(BoxCoxTest, MaximumLikelihoodMatchesIndependentSearch) {
  for (const auto& g : {Multiplicative(), Skewed()}) {
    const BoxCoxResult r = EstimateBoxCox(Make(g));
    const double independent = IndependentLambdaMl(g, -3.0, 3.0);
    EXPECT_NEAR(r.lambda_ml, independent, 1e-6);
    EXPECT_NEAR(r.log_likelihood_ml, static_cast<double>(ProfileLogLikelihood(g, Big(independent))),
                1e-9);
    EXPECT_EQ(r.shift, 0.0);
  }
}

// The interval ends are where l has dropped by chi2_{1, 0.95} / 2 = 3.841458820694124 / 2.
TEST(BoxCoxTest, IntervalEndsAreOnTheLikelihoodThreshold) {
  for (const auto& g : {Multiplicative(), Skewed()}) {
    const BoxCoxResult r = EstimateBoxCox(Make(g));
    const Big top = ProfileLogLikelihood(g, Big(r.lambda_ml));
    ASSERT_FALSE(r.ci_low_at_limit);
    ASSERT_FALSE(r.ci_high_at_limit);
    EXPECT_LT(r.ci_low, r.lambda_ml);
    EXPECT_GT(r.ci_high, r.lambda_ml);
    EXPECT_NEAR(static_cast<double>(top - ProfileLogLikelihood(g, Big(r.ci_low))),
                3.841458820694124 / 2, 1e-8);
    EXPECT_NEAR(static_cast<double>(top - ProfileLogLikelihood(g, Big(r.ci_high))),
                3.841458820694124 / 2, 1e-8);
  }
}

// Rule 4: the simple lambda nearest lambda_ML inside the interval. For the multiplicative
// groups the independent search puts lambda_ML nearer 0 than any other simple value, with 0
// inside the interval, so the rule must pick the log.
TEST(BoxCoxTest, RulePicksTheNearestSimpleLambdaInsideTheInterval) {
  const auto g = Multiplicative();
  const double ml = IndependentLambdaMl(g, -3.0, 3.0);
  ASSERT_LT(std::fabs(ml), 0.25);
  const BoxCoxResult r = EstimateBoxCox(Make(g));
  ASSERT_LE(r.ci_low, 0.0);
  ASSERT_GE(r.ci_high, 0.0);
  EXPECT_EQ(r.lambda, 0.0);
  EXPECT_NE(r.rule.find("simple lambda 0"), std::string::npos) << r.rule;

  BoxCoxOptions exact;
  exact.prefer_simple = false;
  EXPECT_EQ(EstimateBoxCox(Make(g), exact).lambda, EstimateBoxCox(Make(g), exact).lambda_ml);
}

// Exact invariances of the profile likelihood: a change of unit (y -> c y) adds a constant to
// l, so lambda_ML is unchanged; y -> 1/y maps l(lambda) to l(-lambda) + const, so lambda_ML
// changes sign.
TEST(BoxCoxTest, ScaleAndReciprocalInvariance) {
  const auto g = Skewed();
  const double base = EstimateBoxCox(Make(g)).lambda_ml;
  auto scaled = g, inverted = g;
  for (auto& grp : scaled)
    for (double& y : grp) y *= 37.5;
  for (auto& grp : inverted)
    for (double& y : grp) y = 1.0 / y;
  EXPECT_NEAR(EstimateBoxCox(Make(scaled)).lambda_ml, base, 1e-6);
  EXPECT_NEAR(EstimateBoxCox(Make(inverted)).lambda_ml, -base, 1e-6);
}

TEST(BoxCoxTest, ShiftRuleForNonPositiveData) {
  // min -2, max 8: shift = 0.01 * 10 + 2 = 2.1, so the smallest value becomes 0.1.
  const auto d = MakeGroups({"a", "b"}, {{-2.0, 0.0, 1.0}, {3.0, 8.0, 5.0}});
  EXPECT_DOUBLE_EQ(BoxCoxShift(d), 2.1);
  const BoxCoxResult r = EstimateBoxCox(d);
  EXPECT_DOUBLE_EQ(r.shift, 2.1);
  EXPECT_NE(r.rule.find("shifted by 2.1"), std::string::npos) << r.rule;
  EXPECT_EQ(BoxCoxShift(MakeGroups({"a", "b"}, {{0.5, 1.0}, {2.0, 3.0}})), 0.0);
}

TEST(BoxCoxTest, TransformValues) {
  const auto d = MakeGroups({"a", "b"}, {{1.0, 4.0}, {9.0, std::exp(1.0)}});
  const auto log_t = ApplyBoxCox(d, 0.0, 0.0);
  EXPECT_DOUBLE_EQ(log_t.values[0][1], std::log(4.0));
  EXPECT_NEAR(log_t.values[1][1], 1.0, 1e-15);
  const auto sqrt_t = ApplyBoxCox(d, 0.5, 0.0);  // (y^0.5 - 1) / 0.5
  EXPECT_NEAR(sqrt_t.values[0][1], 2.0, 1e-15);
  EXPECT_NEAR(sqrt_t.values[1][0], 4.0, 1e-14);
  const auto inv_t = ApplyBoxCox(d, -1.0, 1.0);  // (1 - 1/(y + 1))
  EXPECT_NEAR(inv_t.values[0][0], 0.5, 1e-15);
  EXPECT_EQ(log_t.labels, d.labels);
  EXPECT_EQ(DescribeBoxCox(0.0, 0.0), "ln(y)");
  EXPECT_EQ(DescribeBoxCox(0.0, 2.5), "ln(y + 2.5)");
  EXPECT_EQ(DescribeBoxCox(-1.0, 0.0), "1 - 1/y");
  EXPECT_EQ(DescribeBoxCox(0.37, 0.0), "(y^0.37 - 1)/0.37");
}

TEST(BoxCoxTest, BadInputIsRejected) {
  const auto d = MakeGroups({"a", "neg"}, {{1.0, 2.0}, {-3.0, 4.0}});
  try {
    ApplyBoxCox(d, 0.5, 0.0);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("group \"neg\" value -3"), std::string::npos) << e.what();
  }
  BoxCoxOptions o;
  o.lambda_min = 2.0;
  o.lambda_max = 1.0;
  EXPECT_THROW(o.Validate(), std::invalid_argument);
  o = BoxCoxOptions{};
  o.confidence = 1.0;
  EXPECT_THROW(EstimateBoxCox(Make(Skewed()), o), std::invalid_argument);
  EXPECT_THROW(EstimateBoxCox(MakeGroups({"a", "b"}, {{1, 1}, {2, 2}})), std::invalid_argument);
  EXPECT_THROW(EstimateBoxCox(MakeGroups({"a", "b"}, {{1, 2}, {2}})), std::invalid_argument);
}

}  // namespace
}  // namespace hoof::stats
