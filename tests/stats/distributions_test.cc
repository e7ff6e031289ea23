// The distribution functions against closed forms:
//  t(1) is Cauchy: P(|T| >= t) = 1 - (2/pi) atan|t|.
//  t(2): P(|T| >= t) = 1 - |t| / sqrt(2 + t^2); its q-quantile is (2q - 1) / sqrt(2 q (1 - q)).
//  chi-squared(2) is exponential with mean 2: P(X >= x) = exp(-x/2), quantile -2 ln(1 - q).
//  F(2, m): P(F >= f) = (1 + 2 f / m)^(-m/2).
//  F(1, m) is the square of t(m).
// (Johnson, Kotz & Balakrishnan, Continuous Univariate Distributions, vol. 2, ch. 27-28.)
#include "stats/distributions.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include <gtest/gtest.h>

namespace hoof::stats {
namespace {

TEST(DistributionsTest, StudentTClosedForms) {
  for (double t : {0.1, 0.5, 1.0, 2.5, 10.0, 300.0}) {
    EXPECT_NEAR(TTwoSided(t, 1.0), 1.0 - 2.0 / std::numbers::pi * std::atan(t), 1e-14) << t;
    EXPECT_NEAR(TTwoSided(-t, 2.0), 1.0 - t / std::sqrt(2.0 + t * t), 1e-14) << t;
  }
  for (double q : {0.025, 0.5, 0.9, 0.975, 0.9995}) {
    const double x = (2.0 * q - 1.0) / std::sqrt(2.0 * q * (1.0 - q));
    EXPECT_NEAR(TQuantile(q, 2.0), x, 1e-12 * std::max(1.0, std::fabs(x))) << q;
  }
  EXPECT_EQ(TTwoSided(0.0, 7.0), 1.0);
  EXPECT_EQ(TTwoSided(INFINITY, 7.0), 0.0);
}

TEST(DistributionsTest, ChiSquaredClosedForms) {
  for (double x : {0.01, 1.0, 5.99, 40.0, 700.0}) {
    const double p = std::exp(-x / 2.0);
    EXPECT_NEAR(ChiSquaredUpperTail(x, 2.0), p, 1e-14 * p) << x;
  }
  for (double q : {0.05, 0.5, 0.95})
    EXPECT_NEAR(ChiSquaredQuantile(q, 2.0), -2.0 * std::log1p(-q), 1e-12);
  // chi2_{1, 0.95} = 1.959963984540054^2 (normal table): the Box-Cox interval uses it.
  EXPECT_NEAR(ChiSquaredQuantile(0.95, 1.0), 3.841458820694124, 1e-12);
  EXPECT_EQ(ChiSquaredUpperTail(0.0, 3.0), 1.0);
  EXPECT_EQ(ChiSquaredUpperTail(INFINITY, 3.0), 0.0);
}

TEST(DistributionsTest, FClosedForms) {
  for (double m : {1.0, 4.0, 27.0, 17.128}) {
    for (double f : {0.2, 1.0, 4.8461, 92.0}) {
      const double p = std::pow(1.0 + 2.0 * f / m, -m / 2.0);
      EXPECT_NEAR(FUpperTail(f, 2.0, m), p, 1e-13 * p) << f << " " << m;
      // F(1, m) at t^2 equals the two-sided t(m) p-value at t.
      EXPECT_NEAR(FUpperTail(f, 1.0, m), TTwoSided(std::sqrt(f), m), 1e-13) << f << " " << m;
    }
  }
  EXPECT_EQ(FUpperTail(0.0, 3.0, 5.0), 1.0);
  EXPECT_EQ(FUpperTail(INFINITY, 3.0, 5.0), 0.0);
}

// Small p-values keep their relative accuracy (upper tails are not 1 - cdf).
TEST(DistributionsTest, TinyUpperTailsAreAccurate) {
  const double p = std::pow(1.0 + 2.0 * 1e6 / 20.0, -10.0);  // about 1e-50
  EXPECT_NEAR(FUpperTail(1e6, 2.0, 20.0), p, 1e-12 * p);
}

TEST(DistributionsTest, BadArgumentsNameTheArgument) {
  EXPECT_THROW(FUpperTail(-1.0, 1.0, 2.0), std::invalid_argument);
  EXPECT_THROW(FUpperTail(1.0, 0.0, 2.0), std::invalid_argument);
  EXPECT_THROW(TTwoSided(std::nan(""), 2.0), std::invalid_argument);
  EXPECT_THROW(TQuantile(1.0, 2.0), std::invalid_argument);
  try {
    ChiSquaredUpperTail(1.0, -3.0);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("df = -3"), std::string::npos) << e.what();
  }
}

TEST(DistributionsTest, WilsonIntervalsMatchNewcombesTable) {
  // Newcombe (1998), Statistics in Medicine 17:857-872, Table II, method 3 (score interval
  // without continuity correction), to the four decimals printed there.
  struct Case {
    int k, n;
    double low, high;
  };
  for (const Case& c : {Case{81, 263, 0.2553, 0.3662}, Case{15, 148, 0.0624, 0.1605},
                        Case{0, 20, 0.0, 0.1611}, Case{1, 29, 0.0061, 0.1718}}) {
    const auto [low, high] = WilsonInterval(c.k, c.n);
    EXPECT_NEAR(low, c.low, 5e-5) << c.k << "/" << c.n;
    EXPECT_NEAR(high, c.high, 5e-5) << c.k << "/" << c.n;
  }
  EXPECT_THROW(WilsonInterval(3, 2), std::invalid_argument);
  EXPECT_THROW(WilsonInterval(0, 0), std::invalid_argument);
  EXPECT_THROW(WilsonInterval(1, 2, 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace hoof::stats
