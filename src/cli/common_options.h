#pragma once
/// @file
/// Command-line options shared by several subcommands, and JSON helpers.

#include <cmath>
#include <cstdlib>
#include <functional>
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

/// Puts kFinite on every floating-point option of `app`'s subcommands.
void RequireFiniteNumbers(CLI::App& app);

/// Runs `validate` (a library's options Validate()) and turns the std::invalid_argument it
/// throws into a command-line error (exit 2). The error names the option of `cmd` whose field
/// the message names (render.fps -> --fps), else the command.
void ValidateOptions(const CLI::App* cmd, const std::function<void()>& validate);

/// A number for JSON: null when NaN or infinite.
inline nlohmann::json JsonNumber(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}
/// A 2-vector for JSON as [x, y].
inline nlohmann::json JsonVector(const Eigen::Vector2d& v) {
  return nlohmann::json::array({JsonNumber(v.x()), JsonNumber(v.y())});
}

}  // namespace hoof::cli
