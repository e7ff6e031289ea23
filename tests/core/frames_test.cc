#include "core/frames.h"

#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/LU>

namespace hoof::core {
namespace {

TEST(FramesTest, SurfaceAxesPointDownTheSlopeAndOutOfTheSurface) {
  // 30 deg, descending toward +x_W: x_S points right and down, y_S up and right.
  const auto R = SurfaceRotation::FromDegrees(30.0);
  EXPECT_NEAR(R.phi_rad(), std::numbers::pi / 6, 1e-15);
  EXPECT_NEAR(R.x_S().x(), std::sqrt(3.0) / 2, 1e-15);
  EXPECT_NEAR(R.x_S().y(), -0.5, 1e-15);
  EXPECT_NEAR(R.y_S().x(), 0.5, 1e-15);
  EXPECT_NEAR(R.y_S().y(), std::sqrt(3.0) / 2, 1e-15);
  // A level surface: S is W.
  const SurfaceRotation level(0.0);
  EXPECT_EQ(level.ToS({1.5, -2.0}), Eigen::Vector2d(1.5, -2.0));
}

TEST(FramesTest, RotationIsProperAndTheConversionsInvertEachOther) {
  for (const double deg : {-40.0, 0.0, 10.0, 20.0, 30.0, 75.0}) {
    const auto R = SurfaceRotation::FromDegrees(deg);
    const Eigen::Matrix2d M = R.R_WS();
    EXPECT_NEAR((M.transpose() * M - Eigen::Matrix2d::Identity()).norm(), 0.0, 1e-15) << deg;
    EXPECT_NEAR(M.determinant(), 1.0, 1e-15) << deg;
    const Eigen::Vector2d v_S(0.7, -3.1);
    EXPECT_NEAR((R.ToW(v_S) - M * v_S).norm(), 0.0, 1e-15) << deg;
    EXPECT_NEAR((R.ToS(R.ToW(v_S)) - v_S).norm(), 0.0, 1e-15) << deg;
    EXPECT_NEAR((R.R_SW() * M - Eigen::Matrix2d::Identity()).norm(), 0.0, 1e-15) << deg;
    EXPECT_NEAR(R.AngleToW(R.AngleToS(0.3)), 0.3, 1e-15) << deg;
  }
}

TEST(FramesTest, GravityAndAVerticalDropInTheSurfaceFrame) {
  // The closed forms of docs/science.md: g_S = (g sin phi, -g cos phi); a body dropped straight
  // down at speed v has v_S = (v sin phi, -v cos phi); its long axis, upright in W, is at
  // 90 deg + phi from x_S.
  const double phi = DegToRad(20.0), g = kStandardGravity_m_s2, v = 3.0;
  const SurfaceRotation R(phi);
  EXPECT_NEAR((R.GravityInS(g) - Eigen::Vector2d(g * std::sin(phi), -g * std::cos(phi))).norm(),
              0.0, 1e-14);
  EXPECT_NEAR((R.ToS({0.0, -v}) - Eigen::Vector2d(v * std::sin(phi), -v * std::cos(phi))).norm(),
              0.0, 1e-15);
  EXPECT_NEAR(R.AngleToS(std::numbers::pi / 2), std::numbers::pi / 2 + phi, 1e-15);
  // The normal speed is the component along y_S, whatever the frame it is computed in.
  const Eigen::Vector2d v_W(0.4, -2.9);
  EXPECT_NEAR(R.ToS(v_W).y(), R.y_S().dot(v_W), 1e-15);
  EXPECT_NEAR(RadToDeg(DegToRad(33.0)), 33.0, 1e-13);
}

TEST(FramesTest, BodyAxesFollowTheBodyAngleCounterclockwise) {
  // x_B at 30 deg above x_W: y_B is x_B turned a further 90 deg.
  const BodyRotation R(std::numbers::pi / 6);
  EXPECT_NEAR(R.x_B().x(), std::sqrt(3.0) / 2, 1e-15);
  EXPECT_NEAR(R.x_B().y(), 0.5, 1e-15);
  EXPECT_NEAR(R.y_B().x(), -0.5, 1e-15);
  EXPECT_NEAR(R.y_B().y(), std::sqrt(3.0) / 2, 1e-15);
  // A marker 18 mm along x_B and 2 mm along y_B, with the body pointing straight down.
  const BodyRotation down(-std::numbers::pi / 2);
  const Eigen::Vector2d p_W = down.ToW({0.018, 0.002});
  EXPECT_NEAR(p_W.x(), 0.002, 1e-17);
  EXPECT_NEAR(p_W.y(), -0.018, 1e-17);
}

TEST(FramesTest, BodyRotationIsProperAndAgreesWithItsMatrix) {
  for (double theta : {-2.5, -0.3, 0.0, 0.7, 1.9, 3.1}) {
    const BodyRotation R(theta);
    const Eigen::Matrix2d M = R.R_WB();
    EXPECT_NEAR(M.determinant(), 1.0, 1e-15);
    EXPECT_LT((M.transpose() * M - Eigen::Matrix2d::Identity()).norm(), 1e-15);
    EXPECT_EQ(M.col(0), R.x_B());
    EXPECT_EQ(M.col(1), R.y_B());
    const Eigen::Vector2d v_B(0.013, -0.004);
    EXPECT_LT((M * v_B - R.ToW(v_B)).norm(), 1e-18);
  }
}

}  // namespace
}  // namespace hoof::core
