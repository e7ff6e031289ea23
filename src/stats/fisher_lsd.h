#pragma once
/// @file
/// Fisher's least significant difference: all pairwise comparisons of group means with the
/// pooled error of the one-way ANOVA. "Protected" LSD runs them only after a significant
/// ANOVA F test; the caller decides that (OneWayAnalysis does). No multiplicity adjustment
/// is made: each pair is an ordinary two-sided t test at level alpha.
///
/// For groups a, b with means m_a, m_b and sizes n_a, n_b, MSE and df = N - k from the ANOVA:
///   d  = m_a - m_b
///   se = sqrt(MSE (1/n_a + 1/n_b))
///   t  = d / se,  p = P(|t(df)| >= |t|)
///   CI = d -+ t_{1 - alpha/2, df} se   (the half-width is the LSD for this pair)
/// These are R's pairwise.t.test(p.adjust.method = "none", pool.sd = TRUE) p-values.

#include <cstddef>
#include <string>
#include <vector>

#include "stats/grouping.h"

namespace hoof::stats {

/// One pairwise comparison.
struct PairComparison {
  std::string group_a;          ///< Earlier group (order of GroupedData::labels).
  std::string group_b;          ///< Later group.
  double difference = 0.0;      ///< mean(a) - mean(b), units of the response.
  double standard_error = 0.0;  ///< sqrt(MSE (1/n_a + 1/n_b)).
  double t = 0.0;               ///< difference / standard_error.
  std::size_t df = 0;           ///< N - k.
  double p = 1.0;               ///< Two-sided, unadjusted.
  double ci_low = 0.0;          ///< difference - t_{1-alpha/2, df} se.
  double ci_high = 0.0;         ///< difference + t_{1-alpha/2, df} se.
  bool significant = false;     ///< p < alpha.
};

/// Fisher's LSD for every pair (a before b), at level `alpha` in (0, 1) for the confidence
/// intervals and the `significant` flag. Throws std::invalid_argument for what OneWayAnova
/// rejects and for alpha outside (0, 1).
std::vector<PairComparison> FisherLsd(const GroupedData& data, double alpha);

}  // namespace hoof::stats
