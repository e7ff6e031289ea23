#include "synth/pinhole_camera.h"

#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "core/frames.h"

namespace hoof::synth {

PinholeCamera::PinholeCamera(const FootageCameraOptions& o)
    : width_(o.width_px), height_(o.height_px), p_W_(o.p_W_m) {
  focal_ = o.focal_px > 0 ? o.focal_px
                          : 0.5 * o.width_px / std::tan(core::DegToRad(o.horizontal_fov_deg) / 2);
  c_ = {std::isnan(o.cx_px) ? (o.width_px - 1) / 2.0 : o.cx_px,
        std::isnan(o.cy_px) ? (o.height_px - 1) / 2.0 : o.cy_px};
  const double p = core::DegToRad(o.pan_deg), t = core::DegToRad(o.tilt_deg);
  const double rho = core::DegToRad(o.roll_deg);
  // Looking along -z_W, panned toward +x_W, tilted down: forward, and the level right axis.
  const Eigen::Vector3d forward{std::sin(p) * std::cos(t), -std::sin(t),
                                -std::cos(p) * std::cos(t)};
  const Eigen::Vector3d right0{std::cos(p), 0.0, std::sin(p)};
  const Eigen::Vector3d down0 = forward.cross(right0);
  // Rolled: the camera's axes turn counter-clockwise, so the scene turns clockwise in the image.
  R_CW_.row(0) = (std::cos(rho) * right0 - std::sin(rho) * down0).transpose();
  R_CW_.row(1) = (std::sin(rho) * right0 + std::cos(rho) * down0).transpose();
  R_CW_.row(2) = forward.transpose();
  K_inv_ << 1 / focal_, 0, -c_.x() / focal_, 0, 1 / focal_, -c_.y() / focal_, 0, 0, 1;
}

Eigen::Vector2d PinholeCamera::Project(const Eigen::Vector3d& p_W) const {
  const Eigen::Vector3d p = ToCamera(p_W);
  if (!(p.z() > 1e-9)) return Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  return {focal_ * p.x() / p.z() + c_.x(), focal_ * p.y() / p.z() + c_.y()};
}

Eigen::Vector3d PinholeCamera::RayW(double x_px, double y_px) const {
  return R_CW_.transpose() * RayC(x_px, y_px);
}

SphereImage PinholeCamera::ImageOfSphere(const Eigen::Vector3d& c_W, double r) const {
  SphereImage s;
  const Eigen::Vector3d c = ToCamera(c_W);
  s.projection_px = Project(c_W);
  if (!(c.z() > r) || c.norm() <= r) return s;
  const Eigen::Matrix3d M =
      c * c.transpose() - (c.squaredNorm() - r * r) * Eigen::Matrix3d::Identity();
  s.conic = K_inv_.transpose() * M * K_inv_;
  const Eigen::Matrix2d A = s.conic.topLeftCorner<2, 2>();
  const Eigen::Vector2d b = s.conic.block<2, 1>(0, 2);
  if (!(A.determinant() > 0) || !(A(0, 0) < 0)) return s;  // not an ellipse
  s.center_px = -A.inverse() * b;
  const double fc = b.dot(s.center_px) + s.conic(2, 2);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(A);
  // Both eigenvalues are negative; the one nearer 0 belongs to the major axis.
  const double l_major = eig.eigenvalues()(1), l_minor = eig.eigenvalues()(0);
  s.semi_major_px = std::sqrt(fc / -l_major);
  s.semi_minor_px = std::sqrt(fc / -l_minor);
  const Eigen::Vector2d axis = eig.eigenvectors().col(1);
  s.major_angle_rad = std::atan2(axis.y(), axis.x());
  if (s.major_angle_rad > std::numbers::pi / 2) s.major_angle_rad -= std::numbers::pi;
  if (s.major_angle_rad <= -std::numbers::pi / 2) s.major_angle_rad += std::numbers::pi;
  s.radius_px = std::sqrt(s.semi_major_px * s.semi_minor_px);
  s.valid = std::isfinite(s.radius_px);
  return s;
}

Eigen::Vector2d PinholeCamera::ImageVelocity(const Eigen::Vector3d& c_W, double r,
                                             const Eigen::Vector3d& v_W) const {
  const double speed = v_W.norm();
  if (speed == 0) return Eigen::Vector2d::Zero();
  const double h = 1e-6;
  const Eigen::Vector3d d = v_W / speed;
  const SphereImage a = ImageOfSphere(c_W + h * d, r), b = ImageOfSphere(c_W - h * d, r);
  if (!a.valid || !b.valid)
    return Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  return (a.center_px - b.center_px) / (2 * h) * speed;
}

Eigen::Vector2d PinholeCamera::ImageDirection(const Eigen::Vector3d& p_W,
                                              const Eigen::Vector3d& d_W) const {
  const double h = 1e-4;
  const Eigen::Vector3d d = d_W.normalized();
  return (Project(p_W + h * d) - Project(p_W - h * d)).normalized();
}

}  // namespace hoof::synth
