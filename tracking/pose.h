#pragma once
/// @file
/// From marker centres to calibrated body poses: the image-to-world calibration (scale,
/// gravity direction, lens distortion) and a least-squares rigid fit of the known marker layout.

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "tracking/marker_tracker.h"

namespace hoof::tracking {

/// A 2-D rigid (or similarity) transform q = scale * rotation * p + translation.
struct RigidFit {
  Eigen::Matrix2d rotation = Eigen::Matrix2d::Identity();
  Eigen::Vector2d translation{0.0, 0.0};
  double scale = 1.0;
  double rms_residual = 0.0;  ///< rms distance between fitted and measured points
};

/// Least-squares fit mapping `model` points onto `measured` points (Kabsch/Umeyama in 2-D,
/// proper rotations only). Two or more point pairs; throws std::invalid_argument otherwise.
RigidFit FitRigid2D(const std::vector<Eigen::Vector2d>& model,
                    const std::vector<Eigen::Vector2d>& measured, bool allow_scale = false);

/// Image frame I (px, y down) to world frame W (m, y up, gravity along -y_W).
struct ImageToWorld {
  double m_per_px = 1.0;
  Eigen::Vector2d gravity_I{0.0, 1.0};  ///< unit gravity direction in the image
  /// Optional lens model (OpenCV): fx 0 cx / 0 fy cy / 0 0 1 and k1 k2 p1 p2 k3.
  std::optional<std::array<double, 9>> camera_matrix;
  std::optional<std::array<double, 5>> distortion;

  /// Removes lens distortion from an image point (px); identity without a lens model.
  Eigen::Vector2d Undistort(const Eigen::Vector2d& p_I) const;
  /// World position (m) of an image point: undistorted, scaled, and rotated so that gravity
  /// points along -y_W. The origin is the image origin.
  Eigen::Vector2d ToWorld(const Eigen::Vector2d& p_I) const;
  /// Angle (rad) to add to an image-frame direction angle (measured with y up) to get W.
  double RotationToWorld() const;
  /// Image point (px, with lens distortion when a lens model is given) of a world position:
  /// the inverse of ToWorld.
  Eigen::Vector2d ToImage(const Eigen::Vector2d& p_W) const;
};

/// The body pose in W at one frame.
struct BodyPose {
  bool valid = false;
  Eigen::Vector2d p_WE{0.0, 0.0};  ///< Centre of the round end E (m).
  double theta_W_rad = 0.0;        ///< Angle of x_B from x_W (rad), counter-clockwise.
  double rms_residual_m = 0.0;     ///< Misfit of the layout to the markers (m).
  int markers_used = 0;
  /// Distance between the first two markers as measured, projected in the image plane (m):
  /// out-of-plane rotation shrinks it.
  double marker_distance_m = 0.0;
};

/// Least-squares rigid pose of the layout from the markers found in one frame; invalid with
/// fewer than two markers.
BodyPose FitPose(const std::vector<MarkerObservation>& observations,
                 const std::vector<Eigen::Vector2d>& layout_B_m, const ImageToWorld& camera);

}  // namespace hoof::tracking
