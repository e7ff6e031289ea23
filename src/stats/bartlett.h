#pragma once
/// @file
/// Bartlett's test that k normal populations have equal variances (Bartlett 1937; the
/// statistic R's bartlett.test reports).
///
/// With group variances s_g^2 (divisor n_g - 1), pooled s_p^2 = sum (n_g - 1) s_g^2 / (N - k):
///   K^2 = [ (N - k) ln s_p^2 - sum_g (n_g - 1) ln s_g^2 ] / C,
///   C   = 1 + ( sum_g 1/(n_g - 1) - 1/(N - k) ) / (3 (k - 1)),
/// approximately chi-squared with k - 1 df under equal variances; p = P(chi2(k-1) >= K^2).
/// The test is sensitive to non-normality: a small p can mean heavy tails as well as unequal
/// variances.

#include <cstddef>
#include <string>

#include "stats/grouping.h"

namespace hoof::stats {

/// Result of Bartlett's test.
struct BartlettResult {
  double k_squared = 0.0;        ///< K^2 (dimensionless); +inf when some but not all groups are
                                 ///< constant (see `note`).
  std::size_t df = 0;            ///< k - 1.
  double p = 1.0;                ///< P(chi2(df) >= K^2); 0 when K^2 = +inf.
  double pooled_variance = 0.0;  ///< s_p^2 (units of the response squared).
  /// Empty, or why the result is a limit: "group "B" has zero variance: K^2 = inf, p = 0"
  /// (as R's bartlett.test, whose log(0) makes the statistic infinite).
  std::string note;
};

/// Bartlett's test on `data`. Throws std::invalid_argument for what ValidateOneWay rejects,
/// and when every group is constant (all variances 0: the statistic is 0/0).
BartlettResult Bartlett(const GroupedData& data);

}  // namespace hoof::stats
