#include "cli/common_options.h"

#include <algorithm>
#include <cctype>
#include <stdexcept>

namespace hoof::cli {

void AddSpecimenOptions(CLI::App* app, dynamics::SpecimenParameters& specimen) {
  // Bounds wide enough for any dropped body (a table-tennis ball to a hoof on a leg), narrow
  // enough that the integrator always finishes.
  app->add_option("--mass-kg", specimen.mass_kg, "Specimen mass m (kg; 1e-4 to 1e4)")
      ->check(CLI::Range(1e-4, 1e4))
      ->capture_default_str();
  app->add_option("--inertia-kg-m2", specimen.inertia_kg_m2,
                  "Moment of inertia I_C about the centre of mass (kg m^2; 1e-10 to 1e3)")
      ->check(CLI::Range(1e-10, 1e3))
      ->capture_default_str();
  app->add_option("--end-radius-m", specimen.end_radius_m,
                  "Radius R of the round end (m; 1e-4 to 1)")
      ->check(CLI::Range(1e-4, 1.0))
      ->capture_default_str();
  app->add_option("--d-ec-m", specimen.d_EC_m,
                  "Distance d from the end centre E to the centre of mass C (m; 0 to 2)")
      ->check(CLI::Range(0.0, 2.0))
      ->capture_default_str();
}

void AddExtensionOptions(CLI::App* app, dynamics::ContactExtensions& ext) {
  // Each bound is far beyond what a hoof, a ball or a specimen shows, and inside what the
  // integrator finishes; a value outside is a command-line error (exit 2).
  const std::string group = "Effects beyond the paper's model (0 = off)";
  app->add_option(
         "--hunt-crossley-n-s-m2", ext.hunt_crossley_N_s_m2,
         "Hunt-Crossley damping c: P gains -c |delta| delta' in compression (N s/m^2; 0 to 1e11)")
      ->check(CLI::Range(0.0, 1e11))
      ->group(group);
  app->add_option("--stiffness-exponent-extra", ext.stiffness_exponent_extra,
                  "p in k |delta| (|delta|/delta_ref)^p; 0.5 is Hertzian (0 to 1)")
      ->check(CLI::Range(0.0, 1.0))
      ->group(group);
  app->add_option("--stiffness-reference-depth-m", ext.stiffness_reference_depth_m,
                  "delta_ref of the nonlinear stiffness (m; 1e-9 to 10)")
      ->check(CLI::Range(1e-9, 10.0))
      ->group(group)
      ->capture_default_str();
  app->add_option("--unloading-stiffness-ratio", ext.unloading_stiffness_ratio,
                  "r: plastic unloading with stiffness k (1 + r) (0 to 1e6)")
      ->check(CLI::Range(0.0, 1e6))
      ->group(group);
  app->add_option("--static-friction-excess", ext.static_friction_excess,
                  "mu_static - mu: stick holds up to (mu + this) P (0 to 100)")
      ->check(CLI::Range(0.0, 100.0))
      ->group(group);
  app->add_option("--tangential-compliance-ratio", ext.tangential_compliance_ratio,
                  "k / k_t of a tangential spring at T (0 = rigid stick; up to 100)")
      ->check(CLI::Range(0.0, 100.0))
      ->group(group);
  app->add_option("--rolling-resistance-m", ext.rolling_resistance_m,
                  "rho: rolling-resistance torque -rho P w / (|w| + 1 rad/s) (m; 0 to 1)")
      ->check(CLI::Range(0.0, 1.0))
      ->group(group);
  app->add_option(
         "--friction-speed-slope-s-m", ext.friction_speed_slope_s_m,
         "s: sliding friction mu (1 + s |v_T|) P (s/m; 0 to 100); not in the discovery library")
      ->check(CLI::Range(0.0, 100.0))
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

void RequireFiniteNumbers(CLI::App& app) {
  for (CLI::App* cmd : app.get_subcommands({}))
    for (CLI::Option* option : cmd->get_options())
      if (option->get_type_name().rfind("FLOAT", 0) == 0) option->check(kFinite);
}

void ValidateOptions(const CLI::App* cmd, const std::function<void()>& validate) {
  try {
    validate();
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    const auto is_word = [&](std::size_t at, std::size_t size) {
      const auto part = [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
      };
      return (at == 0 || !part(what[at - 1])) &&
             (at + size == what.size() || !part(what[at + size]));
    };
    for (const CLI::Option* option : cmd->get_options()) {
      for (const std::string& name : option->get_lnames()) {
        for (std::size_t at = what.find("--" + name); at != std::string::npos;
             at = what.find("--" + name, at + 1)) {
          const std::size_t after = at + 2 + name.size();
          if (after == what.size() || (!std::isalnum(static_cast<unsigned char>(what[after])) &&
                                       what[after] != '_' && what[after] != '-'))
            throw CLI::ValidationError("--" + name, what);
        }
        std::string field = name;
        std::replace(field.begin(), field.end(), '-', '_');
        for (std::size_t at = what.find(field); at != std::string::npos;
             at = what.find(field, at + 1))
          if (field.size() > 1 && is_word(at, field.size()))
            throw CLI::ValidationError("--" + name, what);
      }
    }
    throw CLI::ValidationError(cmd->get_name(), what);
  }
}

}  // namespace hoof::cli
