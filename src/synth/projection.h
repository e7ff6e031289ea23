#pragma once
/// @file
/// Where a point of the specimen lands in the ideal (undistorted) image: the planar pose from
/// the model, an optional out-of-plane rotation about C, and orthographic projection at a fixed
/// scale. The world frame W has its origin at the first-touch contact point, which appears at
/// `contact_px`; image y runs down, W's y up.

#include <cstdint>

#include <Eigen/Core>

namespace hoof::synth {

/// Pose of the specimen at one instant.
struct BodyPose {
  Eigen::Vector2d p_WE{0.0, 0.0};  ///< Centre E of the round end in W (m).
  double theta_W_rad = 0.0;        ///< Angle of x_B from x_W, counter-clockwise (rad).
  double tilt_rad = 0.0;           ///< Out-of-plane rotation about y_B (rad).
  double roll_rad = 0.0;           ///< Out-of-plane rotation about x_B (rad).
};

/// The camera's view of the plane of motion.
struct ViewGeometry {
  double m_per_px = 2e-4;                ///< Scale (m/px).
  Eigen::Vector2d contact_px{0.0, 0.0};  ///< Ideal image position of W's origin (px).
  double d_EC_m = 0.0135;                ///< |EC|: out-of-plane rotations are about C.
};

/// Affine map [x_B, y_B, 1] -> ideal image px for body points on the plane z_B = `z_B_m`
/// (z_B toward the camera): first roll about x_B, then tilt about y_B, both about C; then the
/// planar pose; then x_I = c + p_W.x / s, y_I = c - p_W.y / s.
Eigen::Matrix<double, 2, 3> BodyToImage(const BodyPose& pose, double z_B_m,
                                        const ViewGeometry& view);

/// Image of one body point (x_B, y_B, z_B).
Eigen::Vector2d ProjectBodyPoint(const BodyPose& pose, const Eigen::Vector3d& p_B_m,
                                 const ViewGeometry& view);

/// SplitMix64: a well-mixed 64-bit hash for deriving independent seeds.
std::uint64_t MixSeed(std::uint64_t a, std::uint64_t b);

}  // namespace hoof::synth
