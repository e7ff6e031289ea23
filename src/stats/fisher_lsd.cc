#include "stats/fisher_lsd.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "stats/distributions.h"
#include "stats/moments.h"
#include "stats/one_way_anova.h"

namespace hoof::stats {

std::vector<PairComparison> FisherLsd(const GroupedData& data, double alpha) {
  if (!(alpha > 0.0 && alpha < 1.0)) {
    std::ostringstream os;
    os << "LSD significance level alpha = " << alpha << " must be in (0, 1)";
    throw std::invalid_argument(os.str());
  }
  const OneWayAnovaResult anova = OneWayAnova(data);
  const Moments m = ComputeMoments(data);
  const double df = static_cast<double>(anova.df_within);
  const double t_crit = TQuantile(1.0 - alpha / 2.0, df);
  std::vector<PairComparison> out;
  for (std::size_t a = 0; a < data.groups(); ++a) {
    for (std::size_t b = a + 1; b < data.groups(); ++b) {
      PairComparison c;
      c.group_a = data.labels[a];
      c.group_b = data.labels[b];
      c.difference = static_cast<double>(m.groups[a].mean_offset - m.groups[b].mean_offset);
      const double inv_n =
          1.0 / static_cast<double>(m.groups[a].n) + 1.0 / static_cast<double>(m.groups[b].n);
      c.standard_error = std::sqrt(anova.ms_within * inv_n);
      c.t = c.difference / c.standard_error;
      c.df = anova.df_within;
      c.p = TTwoSided(c.t, df);
      c.ci_low = c.difference - t_crit * c.standard_error;
      c.ci_high = c.difference + t_crit * c.standard_error;
      c.significant = c.p < alpha;
      out.push_back(c);
    }
  }
  return out;
}

}  // namespace hoof::stats
