#include "synth/projection.h"

#include <cmath>

#include <Eigen/Geometry>

#include "core/frames.h"

namespace hoof::synth {

Eigen::Matrix<double, 2, 3> BodyToImage(const BodyPose& pose, double z_B_m,
                                        const ViewGeometry& view) {
  const Eigen::Matrix3d r_oop = (Eigen::AngleAxisd(pose.tilt_rad, Eigen::Vector3d::UnitY()) *
                                 Eigen::AngleAxisd(pose.roll_rad, Eigen::Vector3d::UnitX()))
                                    .toRotationMatrix();
  const Eigen::Vector3d p_BC{view.d_EC_m, 0.0, 0.0};
  // Body point q(x, y) = R (x, y, z) - R p_BC + p_BC, keeping the in-plane components.
  Eigen::Matrix2d a_body = r_oop.topLeftCorner<2, 2>();
  const Eigen::Vector2d b_body =
      (r_oop * (Eigen::Vector3d{0.0, 0.0, z_B_m} - p_BC) + p_BC).head<2>();
  const Eigen::Matrix2d r_w = core::BodyRotation(pose.theta_W_rad).R_WB();
  const Eigen::Matrix2d to_px =
      Eigen::Vector2d{1.0 / view.m_per_px, -1.0 / view.m_per_px}.asDiagonal();
  Eigen::Matrix<double, 2, 3> m;
  m.leftCols<2>() = to_px * r_w * a_body;
  m.col(2) = view.contact_px + to_px * (pose.p_WE + r_w * b_body);
  return m;
}

Eigen::Vector2d ProjectBodyPoint(const BodyPose& pose, const Eigen::Vector3d& p_B_m,
                                 const ViewGeometry& view) {
  return BodyToImage(pose, p_B_m.z(), view) * Eigen::Vector3d{p_B_m.x(), p_B_m.y(), 1.0};
}

std::uint64_t MixSeed(std::uint64_t a, std::uint64_t b) {
  std::uint64_t z = a + 0x9E3779B97F4A7C15ull * (b + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace hoof::synth
