#pragma once
/// @file
/// The frames every library shares, and the constants that go with them (docs/science.md,
/// "Frames and names").
///
/// W, the world (image) frame: origin at the first-touch contact point, x to the right, y up.
/// S, the surface frame: x_S down the slope, y_S the surface's outward normal. For a surface at
/// angle phi (positive when it descends toward +x_W):
///
///     x_S = ( cos phi, -sin phi)_W        y_S = ( sin phi, cos phi)_W
///
/// so R_WS, whose columns are x_S and y_S in W, is [[cos phi, sin phi], [-sin phi, cos phi]],
/// and an angle measured in S is the same angle measured in W plus phi
/// (theta_S = theta_W + phi). This is the only place that writes the rotation out: every
/// library converts between W and S through SurfaceRotation.

#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Core>

namespace hoof::core {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// Standard gravity as the project uses it (m/s^2), along -y_W.
inline constexpr double kStandardGravity_m_s2 = 9.81;
inline constexpr double kRadPerDeg = std::numbers::pi / 180.0;

constexpr double DegToRad(double deg) { return deg * kRadPerDeg; }
constexpr double RadToDeg(double rad) { return rad / kRadPerDeg; }

/// R_WS for a surface at angle phi: converts vectors and angles between W and S.
class SurfaceRotation {
 public:
  explicit SurfaceRotation(double phi_rad)
      : phi_rad_(phi_rad),
        x_S_W_(std::cos(phi_rad), -std::sin(phi_rad)),
        y_S_W_(std::sin(phi_rad), std::cos(phi_rad)) {}
  static SurfaceRotation FromDegrees(double phi_deg) { return SurfaceRotation(DegToRad(phi_deg)); }

  double phi_rad() const { return phi_rad_; }
  /// The unit vectors of S, expressed in W.
  const Eigen::Vector2d& x_S() const { return x_S_W_; }
  const Eigen::Vector2d& y_S() const { return y_S_W_; }

  /// v_W = R_WS v_S.
  Eigen::Vector2d ToW(const Eigen::Vector2d& v_S) const {
    return x_S_W_ * v_S.x() + y_S_W_ * v_S.y();
  }
  /// v_S = R_SW v_W (R_SW is the transpose of R_WS).
  Eigen::Vector2d ToS(const Eigen::Vector2d& v_W) const {
    return {x_S_W_.dot(v_W), y_S_W_.dot(v_W)};
  }
  /// An angle of a body measured from x_W, measured from x_S instead, and back.
  double AngleToS(double theta_W_rad) const { return theta_W_rad + phi_rad_; }
  double AngleToW(double theta_S_rad) const { return theta_S_rad - phi_rad_; }

  /// The matrices, for covariances (C_S = R_SW C_W R_WS).
  Eigen::Matrix2d R_WS() const {
    Eigen::Matrix2d R;
    R.col(0) = x_S_W_;
    R.col(1) = y_S_W_;
    return R;
  }
  Eigen::Matrix2d R_SW() const { return R_WS().transpose(); }

  /// Gravity g along -y_W, expressed in S: (g sin phi, -g cos phi).
  Eigen::Vector2d GravityInS(double g_m_s2) const { return ToS(Eigen::Vector2d(0.0, -g_m_s2)); }

 private:
  double phi_rad_;
  Eigen::Vector2d x_S_W_, y_S_W_;
};

/// R_WB for the specimen's body frame B (origin E, the centre of the round end; x_B toward the
/// centre of mass C) when x_B makes the angle theta with x_W. The only place that writes this
/// rotation out: every library turns body vectors into W through BodyRotation.
class BodyRotation {
 public:
  explicit BodyRotation(double theta_W_rad)
      : c_(std::cos(theta_W_rad)), s_(std::sin(theta_W_rad)) {}

  /// The unit vectors of B, expressed in W.
  Eigen::Vector2d x_B() const { return {c_, s_}; }
  Eigen::Vector2d y_B() const { return {-s_, c_}; }

  /// v_W = R_WB v_B.
  Eigen::Vector2d ToW(const Eigen::Vector2d& v_B) const {
    return {c_ * v_B.x() - s_ * v_B.y(), s_ * v_B.x() + c_ * v_B.y()};
  }
  /// The matrix, whose columns are x_B and y_B in W.
  Eigen::Matrix2d R_WB() const {
    Eigen::Matrix2d R;
    R << c_, -s_, s_, c_;
    return R;
  }

 private:
  double c_, s_;
};

}  // namespace hoof::core
