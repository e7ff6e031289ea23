#include "stats/bartlett.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "stats/accurate_sum.h"
#include "stats/distributions.h"
#include "stats/moments.h"

namespace hoof::stats {

BartlettResult Bartlett(const GroupedData& data) {
  ValidateOneWay(data);
  const Moments m = ComputeMoments(data);
  const std::size_t k = data.groups();
  const long double df_within = static_cast<long double>(m.total_n - k);
  AccurateSum pooled_ss, log_terms, inverse_df;
  std::string zero_groups;
  std::size_t zero_count = 0;
  for (std::size_t g = 0; g < k; ++g) {
    const GroupMoments& gm = m.groups[g];
    const long double df = static_cast<long double>(gm.n - 1);
    pooled_ss.Add(gm.sum_sq);
    inverse_df.Add(1.0L / df);
    if (gm.sum_sq > 0.0L) {
      log_terms.Add(df * std::log(gm.sum_sq / df));
    } else {
      zero_groups += (zero_groups.empty() ? "\"" : ", \"") + data.labels[g] + "\"";
      ++zero_count;
    }
  }
  const long double pooled = pooled_ss.Value() / df_within;
  if (!(pooled > 0.0L)) {
    throw std::invalid_argument(
        "every group is constant (all group variances are 0); Bartlett's statistic is "
        "undefined");
  }
  BartlettResult r;
  r.df = k - 1;
  r.pooled_variance = static_cast<double>(pooled);
  if (!zero_groups.empty()) {
    r.k_squared = std::numeric_limits<double>::infinity();
    r.p = 0.0;
    r.note = (zero_count == 1 ? "group " : "groups ") + zero_groups +
             (zero_count == 1 ? " has" : " have") +
             " zero variance, so ln s^2 = -inf: K^2 = inf and p = 0 (equal variances are "
             "rejected, as R's bartlett.test does)";
    return r;
  }
  const long double c =
      1.0L + (inverse_df.Value() - 1.0L / df_within) / (3.0L * static_cast<long double>(k - 1));
  const long double numerator = df_within * std::log(pooled) - log_terms.Value();
  r.k_squared = static_cast<double>(numerator / c);
  if (r.k_squared < 0.0) r.k_squared = 0.0;  // Jensen: numerator >= 0; only rounding goes below.
  r.p = ChiSquaredUpperTail(r.k_squared, static_cast<double>(r.df));
  return r;
}

}  // namespace hoof::stats
