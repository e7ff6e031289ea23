#include "stats/one_way_anova.h"

#include <cmath>
#include <stdexcept>

#include "stats/accurate_sum.h"
#include "stats/distributions.h"
#include "stats/moments.h"

namespace hoof::stats {

OneWayAnovaResult OneWayAnova(const GroupedData& data) {
  ValidateOneWay(data);
  const Moments m = ComputeMoments(data);
  AccurateSum between, within;
  for (const GroupMoments& g : m.groups) {
    const long double d = g.mean_offset - m.grand_mean_offset;
    between.Add(static_cast<long double>(g.n) * d * d);
    within.Add(g.sum_sq);
  }
  const long double ss_b = between.Value();
  const long double ss_w = within.Value();
  if (!(ss_w > 0.0L)) {
    throw std::invalid_argument(
        "every group is constant (within-group sum of squares is 0), so the F ratio would be "
        "infinite; one-way ANOVA needs variation inside at least one group");
  }
  OneWayAnovaResult r;
  r.groups = data.groups();
  r.observations = m.total_n;
  r.df_between = r.groups - 1;
  r.df_within = r.observations - r.groups;
  r.df_total = r.observations - 1;
  const long double ms_b = ss_b / static_cast<long double>(r.df_between);
  const long double ms_w = ss_w / static_cast<long double>(r.df_within);
  r.ss_between = static_cast<double>(ss_b);
  r.ss_within = static_cast<double>(ss_w);
  r.ss_total = static_cast<double>(ss_b + ss_w);
  r.ms_between = static_cast<double>(ms_b);
  r.ms_within = static_cast<double>(ms_w);
  r.f = static_cast<double>(ms_b / ms_w);
  r.p = FUpperTail(r.f, static_cast<double>(r.df_between), static_cast<double>(r.df_within));
  r.eta_squared = static_cast<double>(ss_b / (ss_b + ss_w));
  r.residual_sd = std::sqrt(r.ms_within);
  return r;
}

}  // namespace hoof::stats
