#pragma once
/// @file
/// Figures of the discovery workflow (docs/discovery.md) from its result: the held-out gap
/// before and after each accepted effect, and the residuals after impact of the baseline and
/// the final model against the impact speed.

#include <filesystem>
#include <vector>

#include "discovery/discovery.h"

namespace hoof::report {

/// Writes into `dir` (created when missing; .png and .svg each):
/// - `discovery_gap_round<n>` for each round n (1, 2, ... in the order of `result.rounds`) that
///   accepted an effect and has held-out trials: each held-out trial's gap (root mean square
///   residual after impact, % of the impact speed) before (current model) and after adding the
///   round's effect, trials sorted by surface, angle and speed, the aggregate gaps and their
///   shrink in the title;
/// - `discovery_residuals`: the residuals after impact (v_y, v_x and w d_EC, % of the impact
///   speed; one panel each) against the impact speed, baseline and final model.
/// A figure without data is skipped (so a result that could not run gives none). Returns the
/// files written. Throws std::runtime_error naming the file when gnuplot fails.
std::vector<std::filesystem::path> WriteDiscoveryFigures(const discovery::DiscoveryResult& result,
                                                         const std::filesystem::path& dir);

}  // namespace hoof::report
