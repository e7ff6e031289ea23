#include "stats/welch_anova.h"

#include <stdexcept>
#include <vector>

#include "stats/accurate_sum.h"
#include "stats/distributions.h"
#include "stats/moments.h"

namespace hoof::stats {

WelchAnovaResult WelchAnova(const GroupedData& data) {
  ValidateOneWay(data);
  const Moments m = ComputeMoments(data);
  const std::size_t k = data.groups();
  std::vector<long double> w(k);
  AccurateSum total_weight, weighted_mean;
  for (std::size_t g = 0; g < k; ++g) {
    const GroupMoments& gm = m.groups[g];
    if (!(gm.sum_sq > 0.0L)) {
      throw std::invalid_argument("group \"" + data.labels[g] +
                                  "\" has zero variance; Welch's ANOVA weights each group by "
                                  "n/s^2 and is undefined then");
    }
    const long double n = static_cast<long double>(gm.n);
    w[g] = n / (gm.sum_sq / (n - 1.0L));
    total_weight.Add(w[g]);
    weighted_mean.Add(w[g] * gm.mean_offset);
  }
  const long double big_w = total_weight.Value();
  const long double m_w = weighted_mean.Value() / big_w;
  AccurateSum a_sum, lambda_sum;
  for (std::size_t g = 0; g < k; ++g) {
    const long double d = m.groups[g].mean_offset - m_w;
    a_sum.Add(w[g] * d * d);
    const long double h = 1.0L - w[g] / big_w;
    lambda_sum.Add(h * h / static_cast<long double>(m.groups[g].n - 1));
  }
  const long double kk = static_cast<long double>(k);
  const long double a = a_sum.Value() / (kk - 1.0L);
  const long double lambda = lambda_sum.Value();
  const long double b = 1.0L + 2.0L * (kk - 2.0L) * lambda / (kk * kk - 1.0L);
  WelchAnovaResult r;
  r.f = static_cast<double>(a / b);
  r.df1 = static_cast<double>(kk - 1.0L);
  r.df2 = static_cast<double>((kk * kk - 1.0L) / (3.0L * lambda));
  r.p = FUpperTail(r.f, r.df1, r.df2);
  return r;
}

}  // namespace hoof::stats
