#pragma once
/// @file
/// The scale from gravity (docs/tracking.md, "Scale"): a body in free flight follows a parabola
/// whose curvature, in px/s^2 at a known frame rate, is g over the scale. Fitting every
/// free-flight arc of a clip (the contacts between them left out) with one common acceleration
/// gives m/px = g / |a| and, from the fit's residuals, its standard error. The same function
/// serves `track` (trial.json `"camera": {"scale_from": "gravity"}`) and `init`.
///
/// Also here: carrying a scale's standard error into a measured impact's velocities and kinetic
/// energies (e and mu_eff are ratios of velocities and do not depend on the scale).

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/frames.h"
#include "kinematics/impact_kinematics.h"

namespace hoof::kinematics {

/// Settings of the gravity scale.
struct GravityScaleOptions {
  double gravity_m_s2 = core::kStandardGravity_m_s2;  ///< the local g; > 0
  /// A frame is a contact candidate when its second difference along gravity falls below the
  /// clip's median by more than this many robust standard deviations; > 0.
  double contact_sigmas = 8.0;
  /// Frames left out on each side of a contact, besides the frames that show it; >= 0.
  int contact_margin_frames = 1;
  /// An arc with fewer frames than this is left out; >= 3.
  int min_arc_frames = 4;
  /// The scale counts as measured only when |a| exceeds this many of its standard errors.
  double min_significance = 5.0;
};

/// One free-flight arc used by the fit (frame indices, inclusive).
struct GravityArc {
  int first_frame = -1, last_frame = -1, n = 0;
};

/// What the gravity fit found. `measured` false: `message` says why (too few frames, the
/// curvature not distinguishable from zero); the fitted values are still filled where a fit ran.
struct GravityScale {
  bool measured = false;
  std::string message;
  Eigen::Vector2d a_px_s2{0, 0};                    ///< the common acceleration (px/s^2)
  Eigen::Matrix2d cov_a = Eigen::Matrix2d::Zero();  ///< its covariance ((px/s^2)^2)
  double a_norm_px_s2 = core::kNaN, a_norm_se_px_s2 = core::kNaN;
  double m_per_px = core::kNaN, m_per_px_se = core::kNaN;
  /// Angle of the fitted acceleration from the stated gravity direction (deg, positive turning
  /// from the image's x toward its y).
  double direction_error_deg = core::kNaN;
  std::vector<GravityArc> arcs;
  std::vector<int> contact_frames;  ///< frames taken as contacts (left out)
  int frames_used = 0;
  double rms_residual_px = core::kNaN;  ///< of the positions about the fitted parabolas
};

/// The scale from the joint flight arcs (kinematics/flight_arcs.h) of the same positions, where
/// EstimateGravityScale's own segmentation does not hold (several short bounces, a hand): the
/// arcs fitted to `p_px` at `fps` (frames whose position equals the one before are repeated
/// images, no sample), g over their shared |a| in px/s^2, measured when |a| exceeds
/// `options.min_significance` of its standard errors. The message says which fit gave it.
GravityScale GravityScaleFromArcs(const std::vector<std::optional<Eigen::Vector2d>>& p_px,
                                  double fps, const GravityScaleOptions& options = {});

/// Fits the positions `p_px` (px, one per frame at `fps`, missing frames nullopt) of a body's
/// centre of mass with a parabola per free-flight arc and one acceleration common to all
/// arcs. `gravity_dir` is gravity's direction in the same frame (it finds the contacts: the
/// frames where the motion along it turns back abruptly); the acceleration itself is fitted in
/// both directions, so a camera's roll does not bias it. Throws std::invalid_argument for
/// invalid options or fps.
GravityScale EstimateGravityScale(const std::vector<std::optional<Eigen::Vector2d>>& p_px,
                                  double fps, const Eigen::Vector2d& gravity_dir,
                                  const GravityScaleOptions& options = {});

/// Carries a scale's relative standard error `rel_se` (m_per_px_se / m_per_px) into `k`: the
/// velocities' covariances and standard errors (v_SC_*_se) gain the fully correlated term
/// rel_se^2 v v^T, and the kinetic energies' standard errors are set from the velocity fits and
/// the scale. e, mu_eff and the spins are left as they are (the scale cancels in them). Call
/// once, on a successful measurement.
void AddScaleUncertainty(double rel_se, double surface_angle_deg,
                         const core::SpecimenParameters& body, ImpactKinematics& k);

}  // namespace hoof::kinematics
