// With the effects of ContactExtensions and rigid stick. A unit of its own: see impact_run.h.
#include "dynamics/impact_run.h"

namespace hoof::dynamics::internal {

ImpactResult RunExtended(const SpecimenParameters& specimen, const ContactParameters& contact,
                         const SimulatorOptions& options, const ImpactConditions& conditions,
                         std::span<const double> sample_times_s) {
  return Run<Model<6, true>>(specimen, contact, options, conditions, sample_times_s);
}

}  // namespace hoof::dynamics::internal
