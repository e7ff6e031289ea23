#pragma once
/// @file
/// The discovery result as study-file tables (group `/discovery`, docs/hdf5-schema.md) and back.
///
/// Tables (names below `/discovery`):
///  - `summary`: one row: success, message, trials_used, trials_skipped, unexplained, seconds,
///    simulations, rounds (how many `rounds/<n>` follow), verdict, measurement_sd_{v_x,v_y,w}
///    (the final noise model's systematic measurement error);
///  - `surfaces`: the per-surface fits, baseline and final model (column `model`), with the
///    noise model's trial-to-trial scatter zeta_sd, mu_sd;
///  - `effects`: the final model's effect values, one row per value (key, surface (empty = all
///    surfaces), parameter, unit, value, se);
///  - `rounds/<n>/summary` (one row), `rounds/<n>/tests`, `rounds/<n>/candidates` (rank order),
///    `rounds/<n>/candidate_values` (every value of each candidate's chosen form: candidate (its
///    0-based row in `candidates`), key, surface, unit, value, se), `rounds/<n>/gap` (one row per
///    held-out trial; no rows when no effect was added), for n = 1, 2, ... in the order of
///    DiscoveryResult::rounds;
///  - `findings` (surfaces joined with ','), `finding_values` (as candidate_values, column
///    `finding`), `remaining` (the significant tests the final model leaves), `residuals` (per
///    trial, baseline and final model);
///  - `options` (optional, DiscoveryOptionsTable): the settings it ran with.
/// Enums (form, identifiability, outcome, status) are stored as their ToString() text and read
/// back with the FromString functions.
/// Residuals are fractions of the impact speed (units "1"); a parameter's estimate carries the
/// unit named in the row's `unit` column; the held-out errors carry kHeldOutErrorUnit.

#include <filesystem>
#include <optional>
#include <vector>

#include "discovery/discovery.h"
#include "studyfile/study_file.h"

namespace hoof::discovery {

/// The study-file group the tables go into.
inline constexpr const char* kDiscoveryGroup = "/discovery";

/// The result as tables for studyfile::WriteTables(path, kDiscoveryGroup, ...).
std::vector<studyfile::Table> DiscoveryTables(const DiscoveryResult& result);

/// The settings the workflow ran with, as the one-row table `options` (alpha, folds,
/// max_rounds, jobs, candidates joined with ',' (empty = all), per_surface, relative_tolerance,
/// marker_ratio_tolerance, measurement_floor); callers that know the options append it to
/// DiscoveryTables() (ReadDiscovery does not need it).
studyfile::Table DiscoveryOptionsTable(const DiscoveryOptions& options);

/// Reads the tables of `/discovery` back into a result (the inverse of DiscoveryTables: every
/// field stored is restored; CandidateResult::name etc. as written). Throws std::runtime_error
/// naming the file and the table (and the column) when one is missing or malformed.
DiscoveryResult ReadDiscovery(const std::filesystem::path& h5);

/// The settings of the table `/discovery/options` (DiscoveryOptionsTable), or nothing when the
/// file has none. A setting the file's version did not store keeps its default, except
/// measurement_floor, which is NaN. Throws std::runtime_error naming the file and the column
/// when the table is malformed.
std::optional<DiscoveryOptions> ReadDiscoveryOptions(const std::filesystem::path& h5);

/// The study-file group of the baseline's prediction z (PredictBaseline): tables `summary` (one
/// row: success, message, trials_skipped), `surfaces` (the baseline fit and its noise model, the
/// columns of /discovery/surfaces) and `trials` (TrialPrediction's fields).
inline constexpr const char* kPredictionGroup = "/prediction";

/// The predictions as tables for studyfile::WriteTables(path, kPredictionGroup, ...).
std::vector<studyfile::Table> PredictionTables(const BaselinePredictions& predictions);

/// Reads /prediction back, or nothing when the file has no such group. Throws
/// std::runtime_error naming the file and the table when a table is missing or malformed.
std::optional<BaselinePredictions> ReadPredictions(const std::filesystem::path& h5);

/// True when the study file `h5` has a `/discovery/summary` table (no exception for a file
/// without one; a missing or unreadable file is false too).
bool HasDiscovery(const std::filesystem::path& h5);

}  // namespace hoof::discovery
