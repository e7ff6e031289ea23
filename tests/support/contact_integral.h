#pragma once
// Helpers shared by the simulator's tests: uniform sample times and integrals over a contact.
#include <cstddef>
#include <vector>

#include "dynamics/impact_simulator.h"

namespace hoof::testing {

/// Uniform times from t0 to t1 inclusive.
inline std::vector<double> Linspace(double t0, double t1, int n) {
  std::vector<double> t(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) t[static_cast<std::size_t>(i)] = t0 + (t1 - t0) * i / (n - 1);
  return t;
}

/// Integral over [0, t_end] of f(sample), by the composite Simpson rule on each piece between
/// located events, where the forces are smooth (friction jumps at a stick/slip switch).
template <class Fn>
double IntegrateOverContact(const dynamics::ImpactSimulator& sim,
                            const dynamics::ImpactConditions& ic, const dynamics::ImpactResult& r,
                            double t_end, Fn f) {
  std::vector<double> cuts = {0.0};
  for (const auto& e : r.events)
    if (e.t_s < t_end) cuts.push_back(e.t_s);
  cuts.push_back(t_end);
  double total = 0.0;
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
    const double a = cuts[k], b = cuts[k + 1];
    if (b - a < 1e-14) continue;
    // Nudge the ends inside the piece so each sample sees this piece's mode.
    const auto t = Linspace(a + 1e-16, b - 1e-16, 4001);
    const auto s = sim.Simulate(ic, t).samples;
    const double h = t[1] - t[0];
    double sum = f(s.front()) + f(s.back());
    for (std::size_t i = 1; i + 1 < s.size(); ++i) sum += (i % 2 ? 4.0 : 2.0) * f(s[i]);
    total += sum * h / 3.0;
  }
  return total;
}

}  // namespace hoof::testing
