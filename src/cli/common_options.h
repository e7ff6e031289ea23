#pragma once
/// @file
/// Command-line options shared by several subcommands, and JSON helpers.

#include <cmath>
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
      return first != std::string::npos && text[first] == '-' ? std::string("must not be negative, got " + text)
                                                                : std::string();
    },
    "NOT NEGATIVE");

/// A number for JSON: null when NaN or infinite.
inline nlohmann::json JsonNumber(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}
/// A 2-vector for JSON as [x, y].
inline nlohmann::json JsonVector(const Eigen::Vector2d& v) {
  return nlohmann::json::array({JsonNumber(v.x()), JsonNumber(v.y())});
}

}  // namespace hoof::cli
