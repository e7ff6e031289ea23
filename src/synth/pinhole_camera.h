#pragma once
/// @file
/// The everyday-footage camera: an ideal pinhole in the image as delivered (I: x right, y down,
/// px, origin at the centre of the top-left pixel), and the exact image of a sphere through it.
///
/// The image of a sphere is the conic where the cone of rays tangent to it meets the image
/// plane: with the sphere's centre c and radius r in camera coordinates and K the camera matrix,
/// the pixels u = (x, y, 1) inside satisfy u^T Q u >= 0, Q = K^-T (c c^T - (c.c - r^2) I) K^-1.
/// Off the optical axis it is an ellipse whose centre is NOT the projection of c: the ellipse's
/// centre (which is also the centroid of the sphere's image) is what the truth calls the ball's
/// image centre.

#include <Eigen/Core>

#include "synth/footage_options.h"

namespace hoof::synth {

/// The image of a sphere.
struct SphereImage {
  bool valid = false;  ///< In front of the camera, the camera outside it, and an ellipse.
  Eigen::Vector2d center_px{0.0, 0.0};      ///< Centre of the ellipse (= centroid of the image).
  Eigen::Vector2d projection_px{0.0, 0.0};  ///< Projection of the sphere's centre.
  double semi_major_px = 0.0, semi_minor_px = 0.0;
  double major_angle_rad = 0.0;  ///< Of the major axis from x_I toward y_I.
  double radius_px = 0.0;        ///< sqrt(semi_major * semi_minor): the area's radius.
  Eigen::Matrix3d conic = Eigen::Matrix3d::Zero();  ///< Q: u^T Q u >= 0 inside.
};

/// A pinhole camera placed in W.
class PinholeCamera {
 public:
  /// From the options (validated by the caller).
  explicit PinholeCamera(const FootageCameraOptions& options);

  int width_px() const { return width_; }
  int height_px() const { return height_; }
  double focal_px() const { return focal_; }
  Eigen::Vector2d principal_point_px() const { return c_; }
  const Eigen::Vector3d& p_W_m() const { return p_W_; }
  /// Rotation from W to camera coordinates (x right, y down, z forward).
  const Eigen::Matrix3d& R_CW() const { return R_CW_; }

  /// p_W in camera coordinates (m).
  Eigen::Vector3d ToCamera(const Eigen::Vector3d& p_W) const { return R_CW_ * (p_W - p_W_); }
  /// The image of a point (px); NaN when it is not in front of the camera.
  Eigen::Vector2d Project(const Eigen::Vector3d& p_W) const;
  /// The direction in W of the ray through pixel (x, y) (not normalised; camera z = 1).
  Eigen::Vector3d RayW(double x_px, double y_px) const;
  /// The ray's direction in camera coordinates (camera z = 1).
  Eigen::Vector3d RayC(double x_px, double y_px) const {
    return {(x_px - c_.x()) / focal_, (y_px - c_.y()) / focal_, 1.0};
  }
  /// The sphere's image (see the file comment).
  SphereImage ImageOfSphere(const Eigen::Vector3d& c_W, double radius_m) const;
  /// d(center_px)/dt of the sphere's image when its centre moves at v_W (px/s), by central
  /// differences of ImageOfSphere along v_W (step 1 um).
  Eigen::Vector2d ImageVelocity(const Eigen::Vector3d& c_W, double radius_m,
                                const Eigen::Vector3d& v_W) const;
  /// The unit image direction in which a point at p_W moves when it moves along d_W.
  Eigen::Vector2d ImageDirection(const Eigen::Vector3d& p_W, const Eigen::Vector3d& d_W) const;
  /// Metres per pixel in the plane parallel to the image plane through p_W: its depth / f.
  double MetresPerPixel(const Eigen::Vector3d& p_W) const { return ToCamera(p_W).z() / focal_; }

 private:
  int width_ = 0, height_ = 0;
  double focal_ = 0.0;
  Eigen::Vector2d c_{0.0, 0.0};
  Eigen::Vector3d p_W_{0.0, 0.0, 0.0};
  Eigen::Matrix3d R_CW_ = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d K_inv_ = Eigen::Matrix3d::Identity();
};

}  // namespace hoof::synth
