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

void AddExtensionOptions(CLI::App* app, dynamics::ContactExtensions& ext) {
  const std::string group = "Effects beyond the paper's model (0 = off)";
  app->add_option("--hunt-crossley-n-s-m2", ext.hunt_crossley_N_s_m2,
                  "Hunt-Crossley damping c: P gains -c |delta| delta' in compression (N s/m^2)")
      ->group(group);
  app->add_option("--stiffness-exponent-extra", ext.stiffness_exponent_extra,
                  "p in k |delta| (|delta|/delta_ref)^p; 0.5 is Hertzian")
      ->group(group);
  app->add_option("--stiffness-reference-depth-m", ext.stiffness_reference_depth_m,
                  "delta_ref of the nonlinear stiffness (m)")
      ->group(group)
      ->capture_default_str();
  app->add_option("--unloading-stiffness-ratio", ext.unloading_stiffness_ratio,
                  "r: plastic unloading with stiffness k (1 + r)")
      ->group(group);
  app->add_option("--static-friction-excess", ext.static_friction_excess,
                  "mu_static - mu: stick holds up to (mu + this) P")
      ->group(group);
  app->add_option("--tangential-compliance-ratio", ext.tangential_compliance_ratio,
                  "k / k_t of a tangential spring at T (0 = rigid stick)")
      ->group(group);
  app->add_option("--rolling-resistance-m", ext.rolling_resistance_m,
                  "rho: rolling-resistance torque -rho P w / (|w| + 1 rad/s) (m)")
      ->group(group);
  app->add_option("--friction-speed-slope-s-m", ext.friction_speed_slope_s_m,
                  "s: sliding friction mu (1 + s |v_T|) P (s/m); not in the discovery library")
      ->group(group);
}

nlohmann::json ExtensionsJson(const dynamics::ContactExtensions& ext) {
  return {{"hunt_crossley_N_s_m2", ext.hunt_crossley_N_s_m2},
          {"stiffness_exponent_extra", ext.stiffness_exponent_extra},
          {"stiffness_reference_depth_m", ext.stiffness_reference_depth_m},
          {"unloading_stiffness_ratio", ext.unloading_stiffness_ratio},
          {"static_friction_excess", ext.static_friction_excess},
          {"tangential_compliance_ratio", ext.tangential_compliance_ratio},
          {"rolling_resistance_m", ext.rolling_resistance_m},
          {"friction_speed_slope_s_m", ext.friction_speed_slope_s_m}};
}

}  // namespace hoof::cli
