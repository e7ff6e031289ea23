#include "cli/common_options.h"

namespace hoof::cli {

void AddSpecimenOptions(CLI::App* app, dynamics::SpecimenParameters& specimen) {
  app->add_option("--mass-kg", specimen.mass_kg, "Specimen mass m (kg)")->capture_default_str();
  app->add_option("--inertia-kg-m2", specimen.inertia_kg_m2,
                  "Moment of inertia I_C about the centre of mass (kg m^2)")
      ->capture_default_str();
  app->add_option("--end-radius-m", specimen.end_radius_m, "Radius R of the round end (m)")
      ->capture_default_str();
  app->add_option("--d-ec-m", specimen.d_EC_m,
                  "Distance d from the end centre E to the centre of mass C (m)")
      ->capture_default_str();
}

}  // namespace hoof::cli
