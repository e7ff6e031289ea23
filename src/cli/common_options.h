#pragma once
/// @file
/// Command-line options shared by several subcommands, and JSON helpers.

#include <cmath>
#include <cstdlib>
#include <functional>
#include <map>
#include <sstream>
#include <string>

#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "dynamics/parameters.h"

namespace hoof::cli {

/// Adds --mass-kg, --inertia-kg-m2, --end-radius-m and --d-ec-m, defaulting to `specimen`.
void AddSpecimenOptions(CLI::App* app, dynamics::SpecimenParameters& specimen);

/// Adds the options of the effects beyond the paper's model (all 0, off, by default).
void AddExtensionOptions(CLI::App* app, dynamics::ContactExtensions& ext);

/// The extensions as JSON (field names as in ContactExtensions).
nlohmann::json ExtensionsJson(const dynamics::ContactExtensions& ext);

/// Refuses a value written with a minus sign before it is converted: an unsigned option would
/// wrap -1 to its largest value.
inline const CLI::Validator kNotNegative(
    [](std::string& text) {
      const auto first = text.find_first_not_of(" \t");
      return first != std::string::npos && text[first] == '-'
                 ? std::string("must not be negative, got " + text)
                 : std::string();
    },
    "NOT NEGATIVE");

/// Refuses NaN, infinities and numbers beyond a double (1e999). main() puts it on every
/// floating-point option of every command.
inline const CLI::Validator kFinite(
    [](std::string& text) {
      char* end = nullptr;
      const double value = std::strtod(text.c_str(), &end);
      return end != text.c_str() && !std::isfinite(value)
                 ? std::string("must be a finite number, got " + text)
                 : std::string();
    },
    "FINITE");

/// A bound as the user reads it: "0.0001", "80", "1e+12".
template <class T>
std::string BoundText(T value) {
  std::ostringstream os;
  os << value;
  return os.str();
}

/// Accepts a value in [lower, upper] (CLI::Range words its refusal with six decimals and no
/// unit): the refusal reads "must be in [0, 80] deg, got 95", the option's name before it.
/// `unit` may be empty.
template <class T>
CLI::Validator InRange(T lower, T upper, const std::string& unit = "") {
  const std::string range = "[" + BoundText(lower) + ", " + BoundText(upper) + "]" +
                            (unit.empty() ? std::string() : " " + unit);
  return CLI::Validator(
      [lower, upper, range](std::string& text) {
        T value{};
        const bool converted = CLI::detail::lexical_cast(text, value);
        return converted && value >= lower && value <= upper
                   ? std::string()
                   : "must be in " + range + ", got " + text;
      },
      "in " + range);
}

/// Puts kFinite on every floating-point option of `app`'s subcommands, and of theirs.
void RequireFiniteNumbers(CLI::App& app);

/// Runs `validate` (a library's options Validate()) and turns the std::invalid_argument it
/// throws into a command-line error (exit 2) in the user's words. The error names the option
/// of `cmd` whose field the message names: the field's own name with '-' for '_' (render.fps
/// -> --fps), or the option `fields` maps it to (relative_tolerance -> --rtol); else the
/// command. A library message "owner.field = value is invalid: why" becomes "why, got TEXT"
/// with the value as the user typed it (or the option's default), so no struct field name or
/// internal unit reaches the user.
void ValidateOptions(const CLI::App* cmd, const std::function<void()>& validate,
                     const std::map<std::string, std::string>& fields = {});

/// The message of a library's std::invalid_argument in the options of `cmd`, as
/// ValidateOptions words it, with the option it names (empty when it names none).
std::pair<std::string, std::string> OptionMessage(const CLI::App* cmd, const std::string& what,
                                                  const std::map<std::string, std::string>& fields);

/// A number for JSON: null when NaN or infinite.
inline nlohmann::json JsonNumber(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}
/// A 2-vector for JSON as [x, y].
inline nlohmann::json JsonVector(const Eigen::Vector2d& v) {
  return nlohmann::json::array({JsonNumber(v.x()), JsonNumber(v.y())});
}

}  // namespace hoof::cli
