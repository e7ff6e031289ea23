#include "cli/common_options.h"

#include <algorithm>
#include <cctype>
#include <regex>
#include <stdexcept>

namespace hoof::cli {

void AddSpecimenOptions(CLI::App* app, dynamics::SpecimenParameters& specimen) {
  // Bounds wide enough for any dropped body (a table-tennis ball to a hoof on a leg), narrow
  // enough that the integrator always finishes.
  app->add_option("--mass-kg", specimen.mass_kg, "Specimen mass m (kg; 1e-4 to 1e4)")
      ->check(InRange(1e-4, 1e4, "kg"))
      ->capture_default_str();
  app->add_option("--inertia-kg-m2", specimen.inertia_kg_m2,
                  "Moment of inertia I_C about the centre of mass (kg m^2; 1e-10 to 1e3)")
      ->check(InRange(1e-10, 1e3, "kg m^2"))
      ->capture_default_str();
  app->add_option("--end-radius-m", specimen.end_radius_m,
                  "Radius R of the round end (m; 1e-4 to 1)")
      ->check(InRange(1e-4, 1.0, "m"))
      ->capture_default_str();
  app->add_option("--d-ec-m", specimen.d_EC_m,
                  "Distance d from the end centre E to the centre of mass C (m; 0 to 2)")
      ->check(InRange(0.0, 2.0, "m"))
      ->capture_default_str();
}

void AddExtensionOptions(CLI::App* app, dynamics::ContactExtensions& ext) {
  const std::string group = "Effects beyond the paper's model (0 = off)";
  for (const auto& f : dynamics::ContactExtensionFields()) {
    CLI::Option* o = app->add_option(f.flag, ext.*f.member, f.help)
                         ->check(InRange(f.option_lower, f.option_upper))
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
  for (CLI::App* cmd : app.get_subcommands({})) {
    for (CLI::Option* option : cmd->get_options())
      if (option->get_type_name().rfind("FLOAT", 0) == 0) option->check(kFinite);
    RequireFiniteNumbers(*cmd);  // and the subcommands' own (synth footage)
  }
}

namespace {

/// The option of `cmd` that `what` names: "--name" written out, a field with the option's
/// name ('_' for '-') as a whole word, or a field of `fields`; nullptr when none.
const CLI::Option* NamedOption(const CLI::App* cmd, const std::string& what,
                               const std::map<std::string, std::string>& fields) {
  const auto part = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  const auto is_word = [&](std::size_t at, std::size_t size) {
    return (at == 0 || !part(what[at - 1])) && (at + size == what.size() || !part(what[at + size]));
  };
  for (const CLI::Option* option : cmd->get_options()) {
    for (const std::string& name : option->get_lnames()) {
      for (std::size_t at = what.find("--" + name); at != std::string::npos;
           at = what.find("--" + name, at + 1)) {
        const std::size_t after = at + 2 + name.size();
        if (after == what.size() || (!part(what[after]) && what[after] != '-')) return option;
      }
    }
  }
  for (const auto& [field, flag] : fields)
    for (std::size_t at = what.find(field); at != std::string::npos; at = what.find(field, at + 1))
      if (is_word(at, field.size())) return cmd->get_option_no_throw(flag);
  for (const CLI::Option* option : cmd->get_options()) {
    for (const std::string& name : option->get_lnames()) {
      std::string field = name;
      std::replace(field.begin(), field.end(), '-', '_');
      for (std::size_t at = what.find(field); at != std::string::npos;
           at = what.find(field, at + 1))
        if (field.size() > 1 && is_word(at, field.size())) return option;
    }
  }
  return nullptr;
}

/// What the user typed for `option` (the last value; of an option of N values, its last N
/// joined by ','), or its default.
std::string TypedValue(const CLI::Option* option) {
  const auto& results = option->results();
  if (results.empty()) return option->get_default_str();
  const auto n = static_cast<std::size_t>(std::max(1, option->get_items_expected_max()));
  if (n == 1 || n > results.size()) return results.back();
  std::string joined;
  for (std::size_t i = results.size() - n; i < results.size(); ++i)
    joined += (joined.empty() ? "" : ",") + results[i];
  return joined;
}

}  // namespace

std::pair<std::string, std::string> OptionMessage(
    const CLI::App* cmd, const std::string& what,
    const std::map<std::string, std::string>& fields) {
  const CLI::Option* option = NamedOption(cmd, what, fields);
  if (option == nullptr) return {"", what};
  const std::string name = option->get_name(/*positional=*/false, /*all_options=*/false);
  // "owner.field = 1.65806 is invalid: why" (dynamics, core, the renderer's Validate()):
  // the field and the value in the library's units say nothing to the user.
  // "HtmlReportOptions.replay_trials = 60: must be in 0..50" and "kinematics fit_frames must
  // be >= 3" likewise.
  static const std::regex library[] = {
      std::regex(R"(^[\w .]*?\w+(?: \([^)]*\))? = \S+ is invalid: ([\s\S]*)$)"),
      std::regex(R"(^[\w.]+ = \S+: (must [\s\S]*)$)"),
      std::regex(R"(^[\w.:]+ \w+ (must [\s\S]*)$)")};
  for (const std::regex& pattern : library) {
    std::smatch m;
    if (std::regex_match(what, m, pattern)) {
      const std::string typed = TypedValue(option);
      return {name, m[1].str() + (typed.empty() ? std::string() : ", got " + typed)};
    }
  }
  return {name, what};
}

void ValidateOptions(const CLI::App* cmd, const std::function<void()>& validate,
                     const std::map<std::string, std::string>& fields) {
  try {
    validate();
  } catch (const std::invalid_argument& e) {
    const auto [option, message] = OptionMessage(cmd, e.what(), fields);
    throw CLI::ValidationError(option.empty() ? cmd->get_name() : option, message);
  }
}

}  // namespace hoof::cli
