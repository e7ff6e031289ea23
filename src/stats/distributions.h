#pragma once
/// @file
/// Tail probabilities and quantiles of the F, Student t and chi-squared distributions, from
/// Boost.Math (which evaluates them through the regularized incomplete beta and gamma
/// functions to near machine precision). Upper tails are computed directly, never as
/// 1 - cdf, so that small p-values keep their relative accuracy.
///
/// Degrees of freedom may be non-integer (Welch's df2). All functions throw
/// std::invalid_argument naming the argument when it is outside the domain below.

#include <utility>

namespace hoof::stats {

/// P(F >= f) for F ~ F(df1, df2). df1, df2 > 0 and finite; f >= 0 or +inf (p = 0); f = 0
/// gives 1.
double FUpperTail(double f, double df1, double df2);

/// Two-sided p-value P(|T| >= |t|) for T ~ t(df). df > 0 and finite; t finite or +-inf (p = 0).
double TTwoSided(double t, double df);

/// The q-quantile of t(df): P(T <= x) = q. 0 < q < 1, df > 0 and finite.
double TQuantile(double q, double df);

/// P(X >= x) for X ~ chi-squared(df). df > 0 and finite; x >= 0 or +inf (p = 0).
double ChiSquaredUpperTail(double x, double df);

/// The q-quantile of chi-squared(df). 0 < q < 1, df > 0 and finite.
double ChiSquaredQuantile(double q, double df);

/// Wilson's score interval of a binomial proportion, k successes in n trials, two-sided at
/// `confidence`: {low, high}. Used for rates measured over simulated studies (Boost.Math offers
/// the Clopper-Pearson and Jeffreys intervals, not Wilson's, which is closer to its nominal
/// coverage for the small n of such rates). n > 0, 0 <= k <= n, 0 < confidence < 1.
std::pair<double, double> WilsonInterval(int k, int n, double confidence = 0.95);

}  // namespace hoof::stats
