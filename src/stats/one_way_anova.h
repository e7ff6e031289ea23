#pragma once
/// @file
/// Classical one-way analysis of variance (fixed effects, unbalanced groups allowed).
///
/// Model y_gi = mu + tau_g + e_gi, e ~ N(0, sigma^2) with one sigma for all groups.
/// With k groups, n_g observations in group g, N = sum n_g, group means m_g, grand mean m:
///   SS_between = sum_g n_g (m_g - m)^2            df_between = k - 1
///   SS_within  = sum_g sum_i (y_gi - m_g)^2        df_within  = N - k
///   SS_total   = SS_between + SS_within            df_total   = N - 1
///   MS = SS / df,  F = MS_between / MS_within,  p = P(F(k-1, N-k) >= F)
///   eta^2 = SS_between / SS_total (the R^2 of the NIST StRD certificates).
/// The sums come from moments.h (shifted two-pass, compensated long double), so the NIST
/// StRD ANOVA sets are reproduced to the precision their input allows (docs/statistics.md).

#include <cstddef>

#include "stats/grouping.h"

namespace hoof::stats {

/// The one-way ANOVA table.
struct OneWayAnovaResult {
  std::size_t groups = 0;        ///< k.
  std::size_t observations = 0;  ///< N.
  std::size_t df_between = 0;    ///< k - 1.
  std::size_t df_within = 0;     ///< N - k.
  std::size_t df_total = 0;      ///< N - 1.
  double ss_between = 0.0;       ///< Units of the response squared.
  double ss_within = 0.0;
  double ss_total = 0.0;
  double ms_between = 0.0;
  double ms_within = 0.0;    ///< The pooled variance estimate (MSE).
  double f = 0.0;            ///< MS_between / MS_within.
  double p = 1.0;            ///< P(F(df_between, df_within) >= f).
  double eta_squared = 0.0;  ///< SS_between / SS_total, in [0, 1].
  double residual_sd = 0.0;  ///< sqrt(MS_within).
};

/// One-way ANOVA of `data`. Throws std::invalid_argument for what ValidateOneWay rejects
/// (fewer than 2 groups, a group of one, constant data) and when every group is constant
/// (SS_within = 0, where F would be infinite), naming the problem.
OneWayAnovaResult OneWayAnova(const GroupedData& data);

}  // namespace hoof::stats
