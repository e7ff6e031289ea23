#pragma once
/// @file
/// The input and output of `hoofimpact fit` as a library: normal impacts read from a CSV table
/// (a study's results.csv, or any table with approach and rebound speeds), kept by COL=VALUE
/// filters and grouped by a column; and each group's objective map and valley as CSV.
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "dynamics/contact_fit.h"

namespace hoof::study {

/// Which columns hold what, and which rows to keep.
struct NormalImpactColumns {
  std::string before = "v_before_m_s";  ///< approach speeds (m/s; the sign is ignored)
  std::string after = "v_after_m_s";    ///< rebound speeds (m/s; the sign is ignored)
  std::string group = "surface";        ///< splits the impacts into fits; ignored when absent
  /// COL=VALUE: keep only the rows whose COL holds VALUE (SameValue).
  std::vector<std::string> where;
};

/// The impacts of `csv_path` per group (the group column's text; "" without one), in file
/// order. Throws std::invalid_argument for a `where` that is not COL=VALUE, and
/// std::runtime_error naming the file (and the line) for a missing column, a speed that is
/// not > 0, no rows left, or rows whose rebound is faster than their approach (e > 1, which no
/// dissipative contact gives: most often swapped columns).
std::map<std::string, std::vector<dynamics::NormalImpact>> ReadNormalImpacts(
    const std::string& csv_path, const NormalImpactColumns& columns);

/// Whether a cell's text matches a filter value: the same text, or two numbers equal as
/// numbers ("0" and "0.0"). A text counts as a number only when all of it parses as one, so
/// that "steel" and "concrete" (both read by strtod as 0) are not taken for equal.
bool SameValue(const std::string& text, const std::string& value);

/// Each group's objective over the (k, b) grid and its valley, as CSV with the header
/// group,k_N_m,b_N_s_m,zeta,mpe_percent,on_valley.
std::string ValleyCsv(const std::vector<std::pair<std::string, dynamics::ContactFitSummary>>& fits,
                      double mass_kg);

}  // namespace hoof::study
