#pragma once
// Every round of a discovery result, a line per candidate with its evidence: what the discovery
// tests print (ctest --output-on-failure shows why a case failed) and bench/discovery_explore
// prints.
#include <ostream>

#include "discovery/discovery.h"

namespace hoof::testing {

inline void PrintDiscoveryRounds(std::ostream& os, const discovery::DiscoveryResult& r) {
  os << r.verdict << "\n";
  for (const auto& rd : r.rounds) {
    os << "round " << rd.index << ": " << rd.decision << "\n";
    for (const auto& c : rd.candidates)
      os << "   " << c.rank << " " << c.key << " " << c.estimate << " +- " << c.se << " LR "
         << c.lr_statistic << " p " << c.p_value << " held-out error " << c.cv_error_current
         << " -> " << c.cv_error << ", density " << c.cv_density_current << " -> " << c.cv_density
         << " (" << ToString(c.identifiability) << ", " << ToString(c.form) << ", "
         << ToString(c.outcome) << ", per-surface p " << c.p_per_surface << ", limit "
         << c.detection_limit << ")" << (c.significant ? " *" : "") << "\n";
  }
  os << r.seconds << " s, " << r.simulations << " simulations\n";
}

}  // namespace hoof::testing
