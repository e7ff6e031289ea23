// The naming level's Monte Carlo (src/discovery/multiplicity.cc) against closed forms: for
// hypotheses that are one test repeated, opposite one-sided tests, or independent tests, the
// level at which the smallest p falls below it with probability alpha is known exactly.
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <boost/math/distributions/normal.hpp>

#include "discovery/internal.h"

namespace hoof::discovery::internal {
namespace {

constexpr double kAlpha = 0.05;
constexpr int kDraws = 20000;

/// One surface, `n` obs of one used component each, whitened to the identity, and no
/// sensitivity to zeta or mu (nothing is projected out).
struct Design {
  Workspace ws;
  std::vector<Sensitivity> sens;
  std::vector<TrialCovariance> ref;
  explicit Design(int n, int surfaces = 1) {
    for (int s = 0; s < surfaces; ++s)
      ws.surfaces.push_back(std::string(1, static_cast<char>('a' + s)));
    for (int i = 0; i < n; ++i) {
      Obs o;
      o.surface = i % surfaces;
      o.used = {false, true, false};
      ws.obs.push_back(o);
      sens.push_back(Sensitivity::Zero());
      TrialCovariance t;
      t.components = {1};
      t.cov = t.whiten = Eigen::MatrixXd::Identity(1, 1);
      ref.push_back(t);
    }
  }
  /// A change of `value[i]` in obs i's v_y.
  std::vector<Eigen::Vector3d> Change(const std::vector<double>& value) const {
    std::vector<Eigen::Vector3d> d;
    for (double v : value) d.emplace_back(0.0, v, 0.0);
    return d;
  }
};

/// Standard error of the Monte Carlo alpha-quantile of min p, whose density there is `density`.
double QuantileSe(double density) { return std::sqrt(kAlpha * (1 - kAlpha) / kDraws) / density; }

TEST(NamingLevelTest, OneTestRepeatedIsOneTest) {
  const Design d(8);
  const auto c = d.Change({1, 2, 0, -1, 3, 0, 1, 1});
  const NamingLevel l =
      CalibrateNamingLevel(d.ws, {c, c, c, c}, d.sens, d.ref, false, 0, kAlpha, kDraws);
  EXPECT_EQ(l.hypotheses, 4);
  EXPECT_DOUBLE_EQ(l.bonferroni, kAlpha / 4);
  // min p is the one p, uniform: its alpha-quantile is alpha.
  EXPECT_NEAR(l.level, kAlpha, 4 * QuantileSe(1.0));
}

TEST(NamingLevelTest, OppositeOneSidedTestsAddUp) {
  const Design d(8);
  const auto c = d.Change({1, 2, 0, -1, 3, 0, 1, 1});
  const auto minus = d.Change({-1, -2, 0, 1, -3, 0, -1, -1});
  const NamingLevel l =
      CalibrateNamingLevel(d.ws, {c, minus}, d.sens, d.ref, false, 0, kAlpha, kDraws);
  // At most one of the two is positive: P(min p < x) = 2 x, so the level is alpha / 2, which
  // is Bonferroni's.
  EXPECT_NEAR(l.level, kAlpha / 2, 4 * QuantileSe(2.0));
  EXPECT_GE(l.level, l.bonferroni);
}

TEST(NamingLevelTest, ARayOfTheChangeAtAnotherSizeIsATestOfItsOwn) {
  // One candidate whose change at other sizes points the opposite way, at every multiple (an
  // effect whose change swings in sign): a fit that searches the sizes takes whichever side the
  // noise favours, so the one hypothesis is two one-sided tests and its level is alpha / 2.
  const Design d(8);
  const auto c = d.Change({1, 2, 0, -1, 3, 0, 1, 1});
  const auto minus = d.Change({-1, -2, 0, 1, -3, 0, -1, -1});
  const NamingLevel without = CalibrateNamingLevel(d.ws, {c}, d.sens, d.ref, false, 0, kAlpha);
  EXPECT_EQ(without.hypotheses, 1);
  EXPECT_DOUBLE_EQ(without.level, kAlpha);
  const double inf = std::numeric_limits<double>::infinity();
  const NamingLevel with = CalibrateNamingLevel(d.ws, {c}, d.sens, d.ref, false, 0, kAlpha, kDraws,
                                                {{LadderRay{minus, 0.0, inf}}});
  EXPECT_EQ(with.hypotheses, 1);
  EXPECT_DOUBLE_EQ(with.bonferroni, kAlpha / 2);
  EXPECT_NEAR(with.level, kAlpha / 2, 4 * QuantileSe(2.0));
}

TEST(NamingLevelTest, ARayTheSizesReachAtOnePointOnlyGainsLess) {
  // The ray on obs of its own (an independent score g ~ N(0, 1)), reached only at the change
  // itself, of length 4: its likelihood ratio is 2 (4 g) - 16, so p < x when
  // g > (z_x^2 + 16) / 8.
  // With the secant's own test (p uniform) the level x solves 1 - (1 - x) (1 - P(x)) = alpha.
  const Design d(8);
  const auto first = d.Change({1, 2, 0, 0, 0, 0, 0, 0});
  const auto other = d.Change({0, 0, 0, 0, 0, 4, 0, 0});
  const NamingLevel l = CalibrateNamingLevel(d.ws, {first}, d.sens, d.ref, false, 0, kAlpha, kDraws,
                                             {{LadderRay{other, 1.0, 1.0}}});
  const boost::math::normal z;
  auto family = [&](double x) {
    const double zx = boost::math::quantile(boost::math::complement(z, x));
    const double p_point = boost::math::cdf(boost::math::complement(z, (zx * zx + 16) / 8));
    return 1 - (1 - x) * (1 - p_point);
  };
  double lo = 1e-6, hi = kAlpha;
  for (int i = 0; i < 100; ++i) (family(0.5 * (lo + hi)) < kAlpha ? lo : hi) = 0.5 * (lo + hi);
  // Between alpha / 2 (a ray at every multiple) and alpha (no ray).
  EXPECT_GT(lo, 1.05 * kAlpha / 2);
  EXPECT_LT(lo, 0.95 * kAlpha);
  EXPECT_NEAR(l.level, lo, 4 * QuantileSe(1.0));
}

TEST(NamingLevelTest, IndependentTestsGiveSidaksLevel) {
  const Design d(8);
  // Changes on disjoint obs: independent scores.
  const NamingLevel l =
      CalibrateNamingLevel(d.ws,
                           {d.Change({1, 1, 0, 0, 0, 0, 0, 0}), d.Change({0, 0, 1, 2, 0, 0, 0, 0}),
                            d.Change({0, 0, 0, 0, 5, 0, 0, 0})},
                           d.sens, d.ref, false, 2, kAlpha, kDraws);
  EXPECT_EQ(l.hypotheses, 5);
  const double sidak = 1 - std::pow(1 - kAlpha, 1.0 / 5);
  EXPECT_NEAR(l.level, sidak, 4 * QuantileSe(5 * std::pow(1 - sidak, 4)));
}

TEST(NamingLevelTest, WhatZetaAndMuTakeUpIsNoTest) {
  Design d(6);
  // The first candidate's change is exactly d prediction / d zeta: it is projected out and
  // leaves one hypothesis.
  for (int i = 0; i < 6; ++i) d.sens[static_cast<std::size_t>(i)](1, 0) = i + 1.0;
  const NamingLevel l =
      CalibrateNamingLevel(d.ws, {d.Change({1, 2, 3, 4, 5, 6}), d.Change({1, -1, 1, -1, 1, -1})},
                           d.sens, d.ref, false, 0, kAlpha, kDraws);
  EXPECT_EQ(l.hypotheses, 1);
  EXPECT_DOUBLE_EQ(l.level, kAlpha);
}

TEST(NamingLevelTest, SameStudySameLevel) {
  const Design d(8, 2);
  const auto c = d.Change({1, 2, 0, -1, 3, 0, 1, 1});
  const auto e = d.Change({0, 1, 1, 0, 2, 1, 0, 0});
  const NamingLevel a = CalibrateNamingLevel(d.ws, {c, e}, d.sens, d.ref, true, 1, kAlpha, kDraws);
  const NamingLevel b = CalibrateNamingLevel(d.ws, {c, e}, d.sens, d.ref, true, 1, kAlpha, kDraws);
  EXPECT_EQ(a.hypotheses, 5);  // two candidates x two forms, and one independent
  EXPECT_EQ(a.level, b.level);
  EXPECT_GE(a.level, a.bonferroni);
  EXPECT_LE(a.level, kAlpha);
}

}  // namespace
}  // namespace hoof::discovery::internal
