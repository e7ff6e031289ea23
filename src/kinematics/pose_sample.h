#pragma once
/// @file
/// One frame's body pose, the input of every impact measurement (kinematics/impact_kinematics.h,
/// kinematics/flight_arcs.h).

#include <Eigen/Core>

#include "core/frames.h"

namespace hoof::kinematics {

/// One frame's body pose in the world frame W (from tracking).
struct PoseSample {
  double t_s = 0.0;            ///< frame time since frame 0 (s)
  bool valid = false;          ///< false when too few markers were found
  Eigen::Vector2d p_WE{0, 0};  ///< centre of the round end (m)
  double theta_W_rad = 0.0;    ///< angle of x_B from x_W (rad)
  /// Covariance of p_WE (m^2); zero when not known. It weights the joint arc fit
  /// (kinematics/flight_arcs.h), which takes it as known up to one factor fitted from the
  /// residuals; the window fits ignore it.
  Eigen::Matrix2d cov_p_WE = Eigen::Matrix2d::Zero();
  /// The body's apparent size in this frame, in any unit (a ball's fitted diameter in px, or a
  /// scale relative to a reference frame): it falls as the body moves away from the camera.
  /// NaN when not known. Used by the joint arc fit's depth correction.
  double apparent_size = core::kNaN;
  /// The frame repeats the previous image (then `valid` is false too): no sample, counted among
  /// what limited an impact.
  bool repeated = false;
  /// s.d. of the capture's time about t_s (s): 0 for a camera with a fixed period; a clip that
  /// holds its images knows a capture only to within the frame period before its first copy
  /// (tracking/frame_timing.h, FrameTiming::capture_time_sd_s).
  double t_sd_s = 0.0;
};

}  // namespace hoof::kinematics
