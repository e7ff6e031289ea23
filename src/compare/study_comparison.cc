#include "compare/study_comparison.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "core/frames.h"
#include "core/parallel.h"

namespace hoof::compare {
StudyComparison CompareStudy(const std::vector<pipeline::TrialAnalysis>& trials, int jobs) {
  StudyComparison out;
  std::set<std::string> surfaces;
  for (const auto& t : trials)
    if (t.success) surfaces.insert(t.spec.surface);
  for (const auto& s : surfaces) out.surfaces[s] = FitSurfaceModel(s, trials, std::max(1, jobs));
  out.trials.resize(trials.size());
  core::ParallelFor(trials.size(), std::max(1, jobs), [&](std::size_t i) {
    const auto& t = trials[i];
    if (!t.success) {
      out.trials[i].message = "not measured: " + t.error;
      return;
    }
    const SurfaceModel& m = out.surfaces.at(t.spec.surface);
    if (!m.success) {
      out.trials[i].message = "no model for " + t.spec.surface + ": " + m.message;
      return;
    }
    dynamics::ContactParameters c = m.Contact();
    if (std::isnan(c.mu)) c.mu = 0.0;  // no oblique trials on this surface: frictionless
    // One trial that cannot be simulated is recorded as such; it never sinks the study (nor,
    // thrown from a worker, the program).
    try {
      out.trials[i] = CompareTrial(t, c, Uncertainty(m));
    } catch (const std::exception& e) {
      out.trials[i] = {};
      out.trials[i].message = std::string("cannot be compared: ") + e.what();
    }
  });
  return out;
}

}  // namespace hoof::compare
