#pragma once
/// @file
/// The paper's Figures 6, 7 and 8 from a study file that `hoofimpact run` has filled
/// (/results and /comparison): measured against simulated velocities after normal and oblique
/// impacts, and the kinetic energy through an impact.

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "report/gnuplot.h"
#include "studyfile/study_file.h"

namespace hoof::compare {
struct TrialComparison;  // compare/trial_comparison.h
}

namespace hoof::report {

/// Velocities after impact by trial id, as /comparison/trials gives them.
using ComparedById = std::map<std::string, compare::TrialComparison>;

/// The plots of Figures 6 and 7 (the paper's), from the study's successful trials that have a
/// simulated velocity: `normal`, for each surface the measured (filled) and simulated (open)
/// normal velocity of C after each normal impact against the impact speed |v_C,y| before;
/// `oblique`, for each surface the measured against the simulated velocity after each oblique
/// impact, both components, with the line of equality. Every point carries ±1 s.e. bars on
/// both axes: the measured velocities' from their flight fits (TrialResult), the simulated
/// ones' propagated from the measured state before and the model (v_SC_after_sim_se), the
/// impact speed's from the flight fit before. A plot without a point has no series.
struct VelocityPlots {
  Plot normal, oblique;
};
VelocityPlots MakeVelocityPlots(const studyfile::StudyResults& study, const ComparedById& row);

/// Writes into `dir` (each figure as .png, .svg, its data .csv and its gnuplot script .gp):
/// - `velocity_normal`: normal velocity of C after each normal impact against the impact speed,
///   measured (filled) and simulated (open), one colour per surface, ±1 s.e. bars (paper
///   Figure 6);
/// - `velocity_oblique`: measured against simulated velocity of C after each oblique impact,
///   both components, with the line of equality, ±1 s.e. bars (paper Figure 7);
/// - `energy_<id>`: the simulated kinetic energy through the contact of one oblique trial per
///   surface, with the measured kinetic energy before and after (paper Figure 8; no bars: no
///   s.e. of an energy is stored).
/// Returns the files written (a figure without data is skipped). Throws std::runtime_error
/// naming the file when the study file lacks /comparison or gnuplot fails.
std::vector<std::filesystem::path> WriteComparisonFigures(const std::filesystem::path& study_h5,
                                                          const std::filesystem::path& dir);

}  // namespace hoof::report
