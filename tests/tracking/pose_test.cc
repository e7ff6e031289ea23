#include "tracking/pose.h"

#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

namespace hoof::tracking {
namespace {

TEST(PoseTest, RigidFitRecoversAKnownTransform) {
  const std::vector<Eigen::Vector2d> model = {{0.006, 0}, {0.024, 0}, {0.015, 0.004}};
  const double a = 1.234;
  const Eigen::Matrix2d R{{std::cos(a), -std::sin(a)}, {std::sin(a), std::cos(a)}};
  const Eigen::Vector2d t{0.1, -0.02};
  std::vector<Eigen::Vector2d> measured;
  for (const auto& p : model) measured.push_back(R * p + t);
  const RigidFit fit = FitRigid2D(model, measured);
  EXPECT_NEAR((fit.rotation - R).norm(), 0, 1e-12);
  EXPECT_NEAR((fit.translation - t).norm(), 0, 1e-12);
  EXPECT_NEAR(fit.rms_residual, 0, 1e-12);
  // With a scale.
  for (auto& m : measured) m = 2.5 * (m - t) + t;
  const RigidFit scaled = FitRigid2D(model, measured, true);
  EXPECT_NEAR(scaled.scale, 2.5, 1e-12);
}

TEST(PoseTest, ImageToWorldTurnsGravityDown) {
  ImageToWorld cam;
  cam.m_per_px = 2e-4;
  // Level camera: image y down is world y up, scaled.
  EXPECT_NEAR((cam.ToWorld({10, 20}) - Eigen::Vector2d(2e-3, -4e-3)).norm(), 0, 1e-15);
  // A camera rolled so that gravity points along +x of the image: a step along +x_I is down.
  cam.gravity_I = {1, 0};
  const Eigen::Vector2d d = cam.ToWorld({10, 0}) - cam.ToWorld({0, 0});
  EXPECT_NEAR(d.x(), 0, 1e-15);
  EXPECT_NEAR(d.y(), -2e-3, 1e-15);
}

TEST(PoseTest, UndistortInvertsOpenCvsDistortion) {
  ImageToWorld cam;
  cam.camera_matrix = std::array<double, 9>{1500, 0, 256, 0, 1500, 192, 0, 0, 1};
  cam.distortion = std::array<double, 5>{-0.06, 0.02, 2e-4, -1e-4, 0};
  // Distort an ideal point with cv::projectPoints, then undistort it.
  const cv::Mat K(3, 3, CV_64F, cam.camera_matrix->data());
  const cv::Mat D(1, 5, CV_64F, cam.distortion->data());
  for (const Eigen::Vector2d& ideal : {Eigen::Vector2d(20, 30), Eigen::Vector2d(480, 350)}) {
    std::vector<cv::Point3d> obj{{(ideal.x() - 256) / 1500, (ideal.y() - 192) / 1500, 1.0}};
    std::vector<cv::Point2d> img;
    cv::projectPoints(obj, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, D, img);
    const Eigen::Vector2d back = cam.Undistort({img[0].x, img[0].y});
    EXPECT_NEAR((back - ideal).norm(), 0, 1e-3);
  }
}

TEST(PoseTest, ToImageInvertsToWorld) {
  ImageToWorld cam;
  cam.m_per_px = 2e-4;
  cam.gravity_I = Eigen::Vector2d(0.1, 1.0).normalized();  // a slightly rolled camera
  cam.camera_matrix = std::array<double, 9>{1500, 0, 256, 0, 1500, 192, 0, 0, 1};
  cam.distortion = std::array<double, 5>{-0.06, 0.02, 2e-4, -1e-4, 0};
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(12.5, 300.25), Eigen::Vector2d(470, 40)})
    EXPECT_NEAR((cam.ToImage(cam.ToWorld(p)) - p).norm(), 0, 1e-3);
}

TEST(PoseTest, PoseFromTwoMarkers) {
  ImageToWorld cam;
  cam.m_per_px = 2e-4;
  const std::vector<Eigen::Vector2d> layout = {{0.006, 0}, {0.024, 0}};
  // Long axis vertical (theta_W = 90 deg), E at (0.05, -0.03) in W: markers straight above E.
  std::vector<MarkerObservation> obs(2);
  for (int i = 0; i < 2; ++i) {
    const Eigen::Vector2d w{0.05, -0.03 + layout[static_cast<std::size_t>(i)].x()};
    obs[static_cast<std::size_t>(i)].found = true;
    obs[static_cast<std::size_t>(i)].p_I = {w.x() / 2e-4, -w.y() / 2e-4};
  }
  const BodyPose pose = FitPose(obs, layout, cam);
  ASSERT_TRUE(pose.valid);
  EXPECT_NEAR(pose.theta_W_rad, std::numbers::pi / 2, 1e-12);
  EXPECT_NEAR((pose.p_WE - Eigen::Vector2d(0.05, -0.03)).norm(), 0, 1e-12);
  EXPECT_NEAR(pose.marker_distance_m, 0.018, 1e-12);
  obs[1].found = false;
  EXPECT_FALSE(FitPose(obs, layout, cam).valid);  // one marker is not a pose
}

}  // namespace
}  // namespace hoof::tracking
