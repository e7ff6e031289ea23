// The overlay's geometry against hand-computed pixels: a level camera at 0.2 mm/px without lens
// distortion maps W (m, y up) to the image (px, y down) as x_I = x_W / 2e-4, y_I = -y_W / 2e-4.
#include "overlay/overlay.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

namespace hoof::overlay {
namespace {

constexpr double kPi = std::numbers::pi;

tracking::ImageToWorld LevelCamera() {
  tracking::ImageToWorld cam;
  cam.m_per_px = 2e-4;
  cam.gravity_I = {0.0, 1.0};
  return cam;
}

pipeline::SpecimenSpec Bar() {
  pipeline::SpecimenSpec s;
  s.end_radius_m = 0.010;  // R = 10 mm
  s.d_EC_m = 0.020;        // C 20 mm from E along x_B
  s.length_m = 0.060;      // far end at 50 mm from E
  s.width_m = 0.012;       // half width 6 mm < R
  return s;
}

TEST(OverlayTest, BodyPointsLandWhereTheLevelCameraPutsThem) {
  const auto cam = LevelCamera();
  // C at (0.1, 0.05) m, x_B pointing straight down (theta = -90 deg): E = C + (0, 0.02) =
  // (0.1, 0.07) m, i.e. (500, -350) px.
  const Eigen::Vector2d p_WC{0.1, 0.05};
  const double theta = -kPi / 2;
  const Eigen::Vector2d E = BodyPointToImage({0, 0}, p_WC, theta, 0.02, cam);
  EXPECT_NEAR(E.x(), 500.0, 1e-9);
  EXPECT_NEAR(E.y(), -350.0, 1e-9);
  // Body point (0.05, 0.006): x_B = (0, -1) and y_B = (1, 0) in W, so W = E + (0.006, -0.05) =
  // (0.106, 0.02) m -> (530, -100) px.
  const Eigen::Vector2d q = BodyPointToImage({0.05, 0.006}, p_WC, theta, 0.02, cam);
  EXPECT_NEAR(q.x(), 530.0, 1e-9);
  EXPECT_NEAR(q.y(), -100.0, 1e-9);
}

TEST(OverlayTest, OutlineIsTheRoundEndAndTheBar) {
  const auto s = Bar();
  const auto outline = OutlineInBody(s, 1e-4);
  ASSERT_GT(outline.size(), 100u);
  // Every point lies on the boundary of (disc of radius R about E) union (bar [0, 50 mm] x
  // [-6, 6] mm): on the circle with x <= sqrt(R^2 - h^2) = 8 mm, on an edge y = +-6 mm with
  // 8 <= x <= 50 mm, or on the far end x = 50 mm.
  const double x_meet = std::sqrt(0.010 * 0.010 - 0.006 * 0.006);
  for (const auto& p : outline) {
    const bool on_arc = std::abs(p.norm() - 0.010) < 1e-12 && p.x() <= x_meet + 1e-12;
    const bool on_edge = std::abs(std::abs(p.y()) - 0.006) < 1e-12 && p.x() >= x_meet - 1e-12 &&
                         p.x() <= 0.05 + 1e-12;
    const bool on_end = std::abs(p.x() - 0.05) < 1e-12 && std::abs(p.y()) <= 0.006 + 1e-12;
    EXPECT_TRUE(on_arc || on_edge || on_end) << p.transpose();
  }
  // Extremes: the back of the round end at x = -R, the far end at 50 mm; steps <= 0.1 mm.
  double min_x = 1, max_x = -1, max_step = 0;
  for (std::size_t i = 0; i < outline.size(); ++i) {
    min_x = std::min(min_x, outline[i].x());
    max_x = std::max(max_x, outline[i].x());
    max_step = std::max(max_step, (outline[(i + 1) % outline.size()] - outline[i]).norm());
  }
  EXPECT_NEAR(min_x, -0.010, 1e-12);
  EXPECT_NEAR(max_x, 0.050, 1e-12);
  EXPECT_LE(max_step, 1e-4 + 1e-12);
}

TEST(OverlayTest, OutlineInTheImageForALevelBar) {
  // theta = 0, C at (0.02, 0): E at the W origin, image origin. The far end's corners are at
  // (0.05, +-0.006) m -> (250, -+30) px; the back of the round end at (-0.01, 0) -> (-50, 0) px.
  const auto px = OutlineToImage(Bar(), {0.02, 0.0}, 0.0, LevelCamera());
  double min_x = 1e9, max_x = -1e9, min_y = 1e9, max_y = -1e9;
  for (const auto& p : px) {
    min_x = std::min(min_x, p.x());
    max_x = std::max(max_x, p.x());
    min_y = std::min(min_y, p.y());
    max_y = std::max(max_y, p.y());
  }
  EXPECT_NEAR(min_x, -50.0, 1e-9);
  EXPECT_NEAR(max_x, 250.0, 1e-9);
  // The round end's top and bottom, R = 50 px: the arc is sampled every <= 0.2 mm (0.02 rad),
  // so the vertex nearest the top is within 0.01 rad of it: 50 (1 - cos 0.01) = 0.0025 px low.
  EXPECT_GE(min_y, -50.0 - 1e-9);
  EXPECT_LE(min_y, -50.0 + 50 * (1 - std::cos(0.01)));
  EXPECT_LE(max_y, 50.0 + 1e-9);
  EXPECT_GE(max_y, 50.0 - 50 * (1 - std::cos(0.01)));
}

TEST(OverlayTest, WithoutLengthTheOutlineIsTheRoundEnd) {
  pipeline::SpecimenSpec s = Bar();
  s.length_m = 0;
  for (const auto& p : OutlineInBody(s, 1e-3)) EXPECT_NEAR(p.norm(), 0.010, 1e-12);
}

TEST(OverlayTest, DrawingColoursTheGreyFrameAtTheMarkers) {
  const cv::Mat grey(200, 300, CV_16UC1, cv::Scalar(30000));
  FrameOverlay o;
  o.markers_sim_px = {{100.0, 80.0}};
  o.markers_meas_px = {{200.0, 120.0}, {std::nan(""), std::nan("")}};
  o.marker_radius_px = 10;
  const cv::Mat img = DrawOverlay(grey, o);
  ASSERT_EQ(img.type(), CV_8UC3);
  ASSERT_EQ(img.size(), grey.size());
  // The grey level 30000/65535 -> 117 in 8 bits, away from the drawing.
  EXPECT_EQ(img.at<cv::Vec3b>(190, 290), cv::Vec3b(117, 117, 117));
  // Red circle of radius 10 about (100, 80): its rightmost point (110, 80) is red.
  const cv::Vec3b c = img.at<cv::Vec3b>(80, 110);
  EXPECT_GT(c[2], 200);
  EXPECT_LT(c[1], 100);
  // Green cross at (200, 120).
  const cv::Vec3b g = img.at<cv::Vec3b>(120, 200);
  EXPECT_GT(g[1], 200);
  EXPECT_LT(g[2], 100);
}

TEST(OverlayTest, OptionsAreValidated) {
  OverlayOptions o;
  EXPECT_NO_THROW(o.Validate());
  o.slow = 0;
  EXPECT_THROW(o.Validate(), std::invalid_argument);
}

}  // namespace
}  // namespace hoof::overlay
