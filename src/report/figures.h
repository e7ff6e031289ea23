#pragma once
/// @file
/// Figures of a trial's measurement and of a study (the paper's Figures 3, 4 and 5, and the
/// out-of-plane check). Each figure NAME is written as NAME.png, NAME.svg, its data NAME.csv and
/// the gnuplot script NAME.gp that remakes the images from the data (report/gnuplot.h).

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "core/frames.h"
#include "pipeline/trial_analysis.h"
#include "studyfile/study_file.h"

namespace hoof::report {

/// The out-of-plane check as a figure: the projected marker distance over the layout distance,
/// per frame, with the fit windows shaded and the flag threshold drawn around the median, as
/// figure `name` in `dir`. Returns the files written (WriteFigure).
std::vector<std::filesystem::path> WriteOutOfPlaneFigure(const pipeline::TrialAnalysis& trial,
                                                         double threshold,
                                                         const std::filesystem::path& dir,
                                                         const std::string& name);

// ---- Figure 3: displacement and angle of one trial against time ---------------------------

/// Samples of one curve of Figure 3: time (ms since frame 0), the displacement of the centre
/// of mass C in the surface frame S (mm; x_S along the surface, down-slope, y_S its normal)
/// from C's position at the impact time (as the before-fit gives it), and the angle theta of
/// x_B from x_W (deg).
struct DisplacementSamples {
  std::vector<double> t_ms, x_S_mm, y_S_mm, theta_deg;
};

/// What Figure 3 shows.
struct DisplacementCurves {
  DisplacementSamples measured;  ///< one sample per frame with a valid pose
  /// The flight fits, sampled evenly (`samples_per_fit` points) from the outer end of each fit
  /// window to the impact time: p_WC(t) = p + v (t - t*) + g (t - t*)^2 / 2 with g = -9.81
  /// m/s^2 y_W, theta(t) = theta* + w (t - t*). Empty when the impact fit failed.
  DisplacementSamples fit_before, fit_after;
  bool has_fit = false;
  double impact_time_ms = 0.0;  ///< t*, when has_fit
};

/// Computes the curves of Figure 3 from `trial` (poses in W, C = E + d_EC (cos theta, sin
/// theta), surface axes x_S = (cos phi, -sin phi), y_S = (sin phi, cos phi) in W for the
/// trial's surface angle phi). `gravity_m_s2` as in kinematics::KinematicsOptions;
/// samples_per_fit >= 2. Displacements are relative to the first valid pose when the fit failed.
DisplacementCurves ComputeDisplacementCurves(const pipeline::TrialAnalysis& trial,
                                             int samples_per_fit = 60,
                                             double gravity_m_s2 = core::kStandardGravity_m_s2);

/// Figure 3 for one trial: (a) the displacement of C in S and (b) the angle against time, the
/// measured points with the fitted curves and the impact time, as two panels of one image
/// (figure `name` in `dir`; no error bars: a pose carries no standard error). Returns the files
/// written. Throws std::runtime_error naming the figure when the trial has no valid pose or
/// gnuplot fails.
std::vector<std::filesystem::path> WriteDisplacementFigure(const pipeline::TrialAnalysis& trial,
                                                           const std::filesystem::path& dir,
                                                           const std::string& name);

/// The height of C against time for a trial measured by its joint flight arcs (trial.arcs,
/// kinematics/flight_arcs.h): the measured heights along the fitted "up" above the contact line
/// (or above the lowest measured point where the line was not fitted), each fitted arc as a
/// curve, the frames left out (contact, outlier) marked apart, and each impact as a vertical
/// line labelled with its e to 3 digits (figure `name` in `dir`; the CSV holds the heights).
/// Returns the files written. Throws std::runtime_error naming the figure when the trial holds no
/// fitted arcs or gnuplot fails.
std::vector<std::filesystem::path> WriteHeightFigure(const pipeline::TrialAnalysis& trial,
                                                     const std::filesystem::path& dir,
                                                     const std::string& name);

// ---- Figures 4 and 5: e and mu_eff by surface, impact angle and speed ---------------------

/// The quantity a study figure shows.
enum class StudyQuantity {
  kRestitution,        ///< e, every successful trial
  kEffectiveFriction,  ///< mu_eff, successful oblique trials only (surface angle > 0)
};
/// The factor on a study figure's horizontal axis.
enum class StudyFactor {
  kImpactAngle,  ///< surface angle phi (°)
  kSpeed,        ///< nominal impact speed (m/s); trials without one are left out
};

/// Mean, standard deviation and standard error of one cell (surface x factor level).
struct CellSummary {
  std::string surface;
  double level = 0.0;  ///< the factor's value (° or m/s)
  std::size_t n = 0;   ///< trials in the cell
  double mean = 0.0;
  /// Sample standard deviation (divisor n - 1); NaN for a cell of one trial, where it is
  /// undefined.
  double sd = 0.0;
  /// Standard error of the mean, the figure's error bar: s.d. / sqrt(n); for a cell of one
  /// trial, that trial's own standard error (e_se or mu_eff_se), NaN when it has none (the
  /// figure then draws the mean without a bar).
  double se = 0.0;
};

/// Groups the trials that count for `quantity` (successful, finite value; for mu_eff also
/// surface angle > 0) by surface and by the exact value of `factor`, and returns each cell's
/// mean, s.d. and s.e.: surfaces in order of first appearance, levels ascending within a surface.
std::vector<CellSummary> SummarizeByCell(const std::vector<studyfile::TrialResult>& trials,
                                         StudyQuantity quantity, StudyFactor factor);

/// One study figure, `name` in `dir`: the cell means of `quantity` against `factor`, one series
/// per surface (nudged sideways by a few per cent of the level spacing so their error bars do
/// not overlap), error bars = ±1 s.e. of the mean (CellSummary::se); the CSV adds each cell's
/// level, n and s.d. Returns the files written, none when no trial counts. Throws
/// std::runtime_error naming the figure when gnuplot fails.
std::vector<std::filesystem::path> WriteStudyFigure(const studyfile::StudyResults& study,
                                                    StudyQuantity quantity, StudyFactor factor,
                                                    const std::filesystem::path& dir,
                                                    const std::string& name);

/// Writes `e_by_angle`, `e_by_speed`, `mu_eff_by_angle` and `mu_eff_by_speed` (.png, .svg,
/// .csv, .gp) into `dir` (created when missing); returns the files written (a figure without
/// data, such as mu_eff in a study of normal impacts only, is skipped).
std::vector<std::filesystem::path> WriteStudyFigures(const studyfile::StudyResults& study,
                                                     const std::filesystem::path& dir);

/// Writes into `dir` (nothing when `dir` is empty): the figure `<id>_out_of_plane` (the
/// out-of-plane check) when the trial is flagged, or always with `always`; and, with
/// `displacement`, `<id>_displacement` (the paper's Figure 3: C's displacement in S and the
/// angle against time with the fits) when the trial has a valid pose, and `<id>_height` (the
/// height of C against time with its arcs and impacts) when it was measured by its arcs; each
/// as .png, .svg, .csv and .gp. Returns the files written.
std::vector<std::string> WriteTrialFigures(const pipeline::TrialAnalysis& r,
                                           const pipeline::TrialAnalysisOptions& options,
                                           const std::string& dir, bool always, bool displacement);

}  // namespace hoof::report
