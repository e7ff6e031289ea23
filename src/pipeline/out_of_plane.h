#pragma once
/// @file
/// Out-of-plane rotation of the specimen, and a trial re-measured with it (docs/tracking.md,
/// "5. Out-of-plane rotation").
///
/// A specimen that turns out of the plane of motion is seen foreshortened: its markers close up
/// (the projected marker distance falls), and markers on the face toward the camera, which lies
/// `thickness / 2` in front of the axis, slide sideways. A rotation that grows in time makes
/// that slide a velocity, which the flight fits take for the body's own. Given the motion, each
/// frame's pose can be fitted again with the marker layout as it then projects, and the impact
/// measured again: the velocities are then the body's.
///
/// The rotation is about the contact point C = (d_EC, 0, 0) in body coordinates: first roll
/// about x_B, then tilt about y_B (R = R_y(tilt) R_x(roll)); z_B points toward the camera.

#include <Eigen/Core>

#include "kinematics/impact_kinematics.h"
#include "pipeline/trial_analysis.h"

namespace hoof::pipeline {

/// Tilt and roll at the impact time, each growing at its rate: angle(t) = angle + rate (t - t*).
struct OutOfPlaneMotion {
  double tilt_rad = 0.0, roll_rad = 0.0;
  double tilt_rate_rad_s = 0.0, roll_rate_rad_s = 0.0;

  double TiltAt(double dt_s) const { return tilt_rad + tilt_rate_rad_s * dt_s; }
  double RollAt(double dt_s) const { return roll_rad + roll_rate_rad_s * dt_s; }
  bool IsZero() const {
    return tilt_rad == 0 && roll_rad == 0 && tilt_rate_rad_s == 0 && roll_rate_rad_s == 0;
  }
};

/// Body coordinates in the plane of motion at which the body point `p_B_m` is seen when the body
/// is tilted and rolled about C (orthographic view along z_B).
Eigen::Vector2d ProjectOutOfPlane(const Eigen::Vector3d& p_B_m, double tilt_rad, double roll_rad,
                                  double d_EC_m);

/// Projected over true distance of the specimen's first two markers (what
/// TrialAnalysis::marker_distance_ratio measures) at this tilt and roll; 1 with fewer than two
/// markers.
double MarkerDistanceRatio(const SpecimenSpec& specimen, double tilt_rad, double roll_rad);

/// `trial` re-measured as if the specimen had turned out of plane by `motion` (times from the
/// trial's measured impact time): every frame's pose fitted again to its tracked markers with the
/// layout as it then projects (markers on the face z_B = thickness / 2), the impact measured
/// again with `options`, and the marker distance ratio divided by the one the motion predicts,
/// so that what remains of it is what the motion leaves unexplained. A trial that failed is
/// returned as it was; one whose re-measurement fails comes back with success false and the
/// reason in `error`.
TrialAnalysis RemeasureOutOfPlane(const TrialAnalysis& trial, const OutOfPlaneMotion& motion,
                                  const kinematics::KinematicsOptions& options);

}  // namespace hoof::pipeline
