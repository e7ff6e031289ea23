// With a tangential spring at T (tangential_compliance_ratio > 0 and mu > 0). A unit of its own:
// see impact_run.h.
#include "dynamics/impact_run.h"

namespace hoof::dynamics::internal {

ImpactResult RunCompliant(const SpecimenParameters& specimen, const ContactParameters& contact,
                          const SimulatorOptions& options, const ImpactConditions& conditions,
                          std::span<const double> sample_times_s) {
  return Run<Model<7, true>>(specimen, contact, options, conditions, sample_times_s);
}

}  // namespace hoof::dynamics::internal
