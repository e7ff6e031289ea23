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
  const std::string group = "Effects beyond the paper's model (0 = off)";
  for (const auto& f : dynamics::ContactExtensionFields()) {
    CLI::Option* o = app->add_option(f.flag, ext.*f.member, f.help)
                         ->check(CLI::Range(f.option_lower, f.option_upper))
                         ->group(group);
    if (!f.effect) o->capture_default_str();  // a shape parameter has a default worth showing
  }
}

nlohmann::json ExtensionsJson(const dynamics::ContactExtensions& ext) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& f : dynamics::ContactExtensionFields()) j[f.key] = ext.*f.member;
  return j;
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
