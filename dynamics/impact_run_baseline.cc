// The paper's model (ContactExtensions::Any() is false). A unit of its own: see impact_run.h.
#include "dynamics/impact_run.h"

namespace hoof::dynamics::internal {

ImpactResult RunBaseline(const SpecimenParameters& specimen, const ContactParameters& contact,
                         const SimulatorOptions& options, const ImpactConditions& conditions,
                         std::span<const double> sample_times_s) {
  return Run<Model<6, false>>(specimen, contact, options, conditions, sample_times_s);
}

}  // namespace hoof::dynamics::internal
