#pragma once
/// @file
/// Every impact of a clip where neighbouring flight arcs of the joint fit meet
/// (kinematics/flight_arcs.h; docs/tracking.md, "Joint arcs"), and the contact line through the
/// meeting points.
///
/// With one shared acceleration the difference of two arcs' heights along the surface normal
/// n is linear in t, so they meet at one time t*. The velocities before and after are the
/// arcs' at t*; e = -(v_T,after . n) / (v_T,before . n) for the body point T at the contact (a
/// ball's centre velocity along n), mu_eff = |dv_t / dv_n| of C; n is the surface at
/// trial.json's angle from gravity's perpendicular, gravity's direction the fitted one. Every
/// standard error comes from the fit's covariance by the delta method, t* included.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/frames.h"
#include "core/specimen.h"
#include "kinematics/flight_arcs.h"
#include "kinematics/impact_kinematics.h"

namespace hoof::kinematics {

/// The surface line through the contact points of the measured impacts, in W.
struct ContactLine {
  bool measured = false;
  std::string message;  ///< why not
  int impacts = 0;      ///< impacts it is fitted to
  /// The impacts' mean contact point (m, W): a point of the line.
  Eigen::Vector2d p_W{core::kNaN, core::kNaN};
  /// Height of that point along the fitted "up" from W's origin (m), and its s.e.
  double level_m = core::kNaN, level_se_m = core::kNaN;
  /// The line's angle from gravity's perpendicular (deg, positive descending toward +x, as
  /// trial.json's surface_angle_deg) and its s.e., fitted when two or more impacts lie apart
  /// along it by more than 10 s.e. of their positions; else NaN and `angle_measured` false
  /// (the line is then taken at the stated angle).
  bool angle_measured = false;
  double angle_deg = core::kNaN, angle_se_deg = core::kNaN;
  /// Rms distance of the contact points from the line (m), from two impacts on with the stated
  /// angle or three on with a fitted one; NaN otherwise.
  double rms_residual_m = core::kNaN;
};

/// A clip's impacts from its joint arc fit.
struct ArcImpacts {
  FlightArcs arcs;
  /// One per contact the fit found, in time order (index 0 first): measured, or found but
  /// not measured (success false, `message` says why, `limits` what limited it).
  std::vector<ImpactKinematics> impacts;
  ContactLine contact_line;
};

/// Fits the flight arcs of `poses` (FitFlightArcs) and measures every impact where two of them
/// meet, for a surface at `surface_angle_deg` from gravity's perpendicular and the body `body`
/// (d_EC_m places C from E, end_radius_m the contact point T below E). Uses options.arcs and
/// options.confidence (Student's t with the fit's degrees of freedom). Invalid options throw
/// std::invalid_argument.
ArcImpacts MeasureArcImpacts(const std::vector<PoseSample>& poses, double surface_angle_deg,
                             const core::SpecimenParameters& body,
                             const KinematicsOptions& options = {});

}  // namespace hoof::kinematics
