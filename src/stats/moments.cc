#include "stats/moments.h"

#include <stdexcept>

#include "stats/accurate_sum.h"

namespace hoof::stats {

Moments ComputeMoments(const GroupedData& data) {
  if (data.observations() == 0) throw std::invalid_argument("ComputeMoments: no observations");
  Moments m;
  for (const auto& group : data.values) {
    if (!group.empty()) {
      m.shift = group.front();
      break;
    }
  }
  const long double c = m.shift;
  AccurateSum grand;
  for (const auto& group : data.values) {
    GroupMoments gm;
    gm.n = group.size();
    if (gm.n > 0) {
      AccurateSum sum;
      for (double y : group) sum.Add(static_cast<long double>(y) - c);
      gm.mean_offset = sum.Value() / static_cast<long double>(gm.n);
      AccurateSum squares, residual;
      for (double y : group) {
        const long double e = (static_cast<long double>(y) - c) - gm.mean_offset;
        squares.Add(e * e);
        residual.Add(e);
      }
      const long double r = residual.Value();
      gm.sum_sq = squares.Value() - r * r / static_cast<long double>(gm.n);
      if (gm.sum_sq < 0.0L) gm.sum_sq = 0.0L;
      grand.Add(gm.mean_offset * static_cast<long double>(gm.n));
    }
    m.total_n += gm.n;
    m.groups.push_back(gm);
  }
  m.grand_mean_offset = grand.Value() / static_cast<long double>(m.total_n);
  return m;
}

}  // namespace hoof::stats
