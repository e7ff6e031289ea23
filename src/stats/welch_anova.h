#pragma once
/// @file
/// Welch's (1951) one-way ANOVA: equality of k means without assuming equal variances (what
/// R's oneway.test(var.equal = FALSE) reports). For k = 2 it is Welch's two-sample t-test,
/// with F = t^2.
///
/// With weights w_g = n_g / s_g^2, W = sum w_g, weighted mean m_w = sum w_g m_g / W:
///   A      = sum_g w_g (m_g - m_w)^2 / (k - 1)
///   Lambda = sum_g (1 - w_g / W)^2 / (n_g - 1)
///   F      = A / (1 + 2 (k - 2) Lambda / (k^2 - 1))
///   df1 = k - 1,  df2 = (k^2 - 1) / (3 Lambda),  p = P(F(df1, df2) >= F).

#include "stats/grouping.h"

namespace hoof::stats {

/// Result of Welch's ANOVA.
struct WelchAnovaResult {
  double f = 0.0;    ///< Welch's F (dimensionless).
  double df1 = 0.0;  ///< k - 1.
  double df2 = 0.0;  ///< (k^2 - 1) / (3 Lambda); not an integer in general.
  double p = 1.0;    ///< P(F(df1, df2) >= F).
};

/// Welch's ANOVA on `data`. Throws std::invalid_argument for what ValidateOneWay rejects and
/// when a group has zero variance (its weight n/s^2 would be infinite), naming the group.
WelchAnovaResult WelchAnova(const GroupedData& data);

}  // namespace hoof::stats
