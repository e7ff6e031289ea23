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
  for (const auto& s : surfaces) {
    // A surface whose fit throws has no model; the other surfaces still get theirs.
    try {
      out.surfaces[s] = FitSurfaceModel(s, trials, std::max(1, jobs));
    } catch (const std::exception& e) {
      SurfaceModel m;
      m.surface = s;
      m.message = "the fit failed: " + std::string(e.what());
      out.surfaces[s] = m;
    }
  }
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

MassGaps MassGapsOf(const StudyComparison& comparison) {
  MassGaps g;
  for (const auto& t : comparison.trials) {
    if (!t.success || t.mass_known) continue;
    ++g.without_mass;
    g.inertia_assumed += t.inertia_assumed ? 1 : 0;
  }
  return g;
}

std::string MassGaps::Text() const {
  if (without_mass == 0) return "";
  std::string s =
      std::to_string(without_mass) +
      " trial(s) of a ball of unknown mass (no ball specimen with a mass_kg in study.json): their "
      "velocities, e and mu_eff are compared, as none depends on the mass; their "
      "kinetic energies and the contact law's k and b need the mass and are not "
      "given";
  if (inertia_assumed > 0)
    s += "; " + std::to_string(inertia_assumed) +
         " of them simulated as a solid sphere (I = 2/5 m R^2), which only the tangential "
         "velocity after a contact that sticks depends on (a ball specimen with its \"inertia\" "
         "gives another)";
  return s;
}

}  // namespace hoof::compare
