#pragma once
// An independent one-way ANOVA for tests: the textbook two-pass formulas evaluated in 50
// significant decimal digits (Boost.Multiprecision cpp_bin_float_50). Every double converts
// exactly, and 50 digits leave far more than the 13 constant leading digits plus 15 digits
// of result that the NIST sets need, so this is the exact ANOVA of the given doubles to well
// beyond double precision. It shares no code with hoof::stats.
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include <boost/multiprecision/cpp_bin_float.hpp>

namespace hoof::stats::testing {

using Big = boost::multiprecision::cpp_bin_float_50;

struct ReferenceAnova {
  Big ss_between, ss_within, ms_between, ms_within, f, eta_squared;
};

/// Groups by label (any order: the ANOVA does not depend on it) and applies the definitions.
inline ReferenceAnova ComputeReferenceAnova(const std::vector<double>& y,
                                            const std::vector<std::string>& labels) {
  std::map<std::string, std::vector<Big>> groups;
  for (std::size_t i = 0; i < y.size(); ++i) groups[labels[i]].push_back(Big(y[i]));
  Big total = 0;
  for (const auto& [label, v] : groups)
    for (const Big& x : v) total += x;
  const Big n_total = Big(static_cast<long long>(y.size()));
  const Big grand = total / n_total;
  ReferenceAnova r;
  r.ss_between = 0;
  r.ss_within = 0;
  for (const auto& [label, v] : groups) {
    Big sum = 0;
    for (const Big& x : v) sum += x;
    const Big mean = sum / Big(static_cast<long long>(v.size()));
    r.ss_between += Big(static_cast<long long>(v.size())) * (mean - grand) * (mean - grand);
    for (const Big& x : v) r.ss_within += (x - mean) * (x - mean);
  }
  const Big k = Big(static_cast<long long>(groups.size()));
  r.ms_between = r.ss_between / (k - 1);
  r.ms_within = r.ss_within / (n_total - k);
  r.f = r.ms_between / r.ms_within;
  r.eta_squared = r.ss_between / (r.ss_between + r.ss_within);
  return r;
}

}  // namespace hoof::stats::testing
