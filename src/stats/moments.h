#pragma once
/// @file
/// The numerical core of every sum of squares in hoof::stats: group means and centred sums
/// of squares, accurate for data with many constant leading digits.
///
/// Method (two-pass with a common shift and compensated extended-precision sums):
///  1. shift c = the first observation. d = y - c is formed in long double; for data that
///     share their leading digits (NIST SmLs07-09: 1000000000000.4 etc.) d is exact.
///  2. m_g = (sum of d over group g) / n_g, with AccurateSum.
///  3. S_g = sum (d - m_g)^2 - (sum (d - m_g))^2 / n_g (the corrected two-pass formula of
///     Chan, Golub & LeVeque 1983; the second term removes the first-order error of m_g).
/// Means are kept as long double offsets from c, so differences of means (which is what
/// between-group sums of squares and pairwise comparisons use) do not cancel.

#include <cstddef>
#include <vector>

#include "stats/grouping.h"

namespace hoof::stats {

/// Moments of one group, relative to Moments::shift.
struct GroupMoments {
  std::size_t n = 0;
  long double mean_offset = 0.0L;  ///< mean - shift.
  long double sum_sq = 0.0L;       ///< sum over the group of (y - mean)^2.
};

/// Moments of all groups, sharing one shift.
struct Moments {
  double shift = 0.0;                    ///< c: the first observation of the data.
  std::vector<GroupMoments> groups;      ///< In the order of GroupedData::labels.
  std::size_t total_n = 0;               ///< N.
  long double grand_mean_offset = 0.0L;  ///< (sum_g n_g m_g) / N, i.e. grand mean - shift.
};

/// Computes the moments of `data` (see the file comment). `data` must hold at least one
/// observation; values are assumed finite (GroupByLabel checks both).
Moments ComputeMoments(const GroupedData& data);

}  // namespace hoof::stats
