#pragma once
/// @file
/// The paper's Figures 6, 7 and 8 from a study file that `hoofimpact run` has filled
/// (/results and /comparison): measured against simulated velocities after normal and oblique
/// impacts, and the kinetic energy through an impact.

#include <filesystem>
#include <vector>

namespace hoof::report {

/// Writes into `dir` (.png and .svg each):
/// - `velocity_normal`: normal velocity of C after each normal impact against the impact speed,
///   measured (filled) and simulated (open), one colour per surface (paper Figure 6);
/// - `velocity_oblique`: measured against simulated velocity of C after each oblique impact,
///   both components, with the line of equality (paper Figure 7);
/// - `energy_<id>`: the simulated kinetic energy through the contact of one oblique trial per
///   surface, with the measured kinetic energy before and after (paper Figure 8).
/// Returns the files written (a figure without data is skipped). Throws std::runtime_error
/// naming the file when the study file lacks /comparison or gnuplot fails.
std::vector<std::filesystem::path> WriteComparisonFigures(const std::filesystem::path& study_h5,
                                                          const std::filesystem::path& dir);

}  // namespace hoof::report
