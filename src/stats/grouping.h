#pragma once
/// @file
/// From a response column and a label column to groups: the input of every one-way procedure
/// in hoof::stats. Groups keep the order in which their labels first appear in the input, so
/// tables list them in the order of the data file (sort the input to get another order).

#include <cstddef>
#include <string>
#include <vector>

namespace hoof::stats {

/// Observations split into groups. Invariant (after GroupByLabel): labels.size() ==
/// values.size(), labels are distinct and non-empty, every group has at least one value and
/// every value is finite.
struct GroupedData {
  std::vector<std::string> labels;          ///< Group labels, in order of first appearance.
  std::vector<std::vector<double>> values;  ///< values[g]: group g's observations, input order.

  /// Number of groups k.
  std::size_t groups() const { return labels.size(); }
  /// Total number of observations N.
  std::size_t observations() const;
};

/// Descriptive statistics of one group.
struct GroupSummary {
  std::string label;
  std::size_t n = 0;
  double mean = 0.0;      ///< Arithmetic mean (units of the response).
  double variance = 0.0;  ///< Sample variance, divisor n - 1; 0 when n = 1.
  double sd = 0.0;        ///< sqrt(variance).
};

/// Splits `response` by `labels` (one label per observation). Throws std::invalid_argument
/// when the sizes differ, there is no observation, a label is empty, or a value is NaN or
/// infinite; the message names the observation (0-based index) and its group.
GroupedData GroupByLabel(const std::vector<double>& response,
                         const std::vector<std::string>& labels);

/// Builds groups from already separated samples, with the given labels (used by tests and
/// by callers that hold the groups apart). Same checks as GroupByLabel, plus distinct labels
/// and no empty group.
GroupedData MakeGroups(const std::vector<std::string>& labels,
                       const std::vector<std::vector<double>>& values);

/// Checks what every one-way procedure here needs and throws std::invalid_argument naming
/// the problem otherwise: at least 2 groups; at least 2 observations in every group (a
/// group of one has no variance, which Bartlett and Welch need); not all observations equal.
/// (Zero variance inside every group is rejected by OneWayAnova, which is where it matters.)
void ValidateOneWay(const GroupedData& data);

/// Mean and sample variance of each group, computed by the shifted two-pass method of
/// moments.h (accurate for data with many constant leading digits).
std::vector<GroupSummary> Summarize(const GroupedData& data);

}  // namespace hoof::stats
