// The overlay's geometry against hand-computed pixels: a level camera at 0.2 mm/px without lens
// distortion maps W (m, y up) to the image (px, y down) as x_I = x_W / 2e-4, y_I = -y_W / 2e-4.
#include "overlay/overlay.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <utility>

#include <gtest/gtest.h>
#include <unistd.h>
#include <opencv2/core.hpp>

#include "compare/replay_convention.h"

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

/// Whether `p` (BGR) is the colour of `g`, within `tol` per channel.
bool IsColour(const cv::Vec3b& p, const compare::replay::Glyph& g, int tol) {
  return std::abs(p[0] - g.b) <= tol && std::abs(p[1] - g.g) <= tol && std::abs(p[2] - g.r) <= tol;
}

TEST(OverlayTest, DrawingUsesTheReplayGlyphs) {
  using namespace compare::replay;
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
  // The simulated marker is a plus (magenta) of half arm 1.4 x 10 px about (100, 80): its
  // centre and the point 12 px right of it are drawn; the point 10 px right and 10 px down
  // (off the arms) is not.
  EXPECT_TRUE(IsColour(img.at<cv::Vec3b>(80, 100), kSimulated, 40)) << img.at<cv::Vec3b>(80, 100);
  EXPECT_TRUE(IsColour(img.at<cv::Vec3b>(80, 112), kSimulated, 40));
  EXPECT_EQ(img.at<cv::Vec3b>(90, 110), cv::Vec3b(117, 117, 117));
  // The measured marker is a ring (green) of radius 10 about (200, 120): its rightmost point is
  // drawn, its centre is not.
  EXPECT_TRUE(IsColour(img.at<cv::Vec3b>(120, 210), kMeasured, 40)) << img.at<cv::Vec3b>(120, 210);
  EXPECT_EQ(img.at<cv::Vec3b>(120, 200), cv::Vec3b(117, 117, 117));
}

TEST(OverlayTest, TheResidualArrowEndsWhereTheFormulaPutsIt) {
  using namespace compare::replay;
  // Measured (300, 300), simulated (300.4, 299.7): the residual (0.4, -0.3) px is sub-pixel; at
  // F = 20 the arrow runs from (300, 300) to (300 + 20 * 0.4, 300 - 20 * 0.3) = (308, 294), 10
  // px long. At F = 50 it ends at (320, 285). (The marker is clear of the legend at the top
  // left, whose residual line is written in the arrow's colour.)
  for (const auto& [scale, end] :
       {std::pair{20, cv::Point2d(308, 294)}, std::pair{50, cv::Point2d(320, 285)}}) {
    const cv::Mat grey(400, 600, CV_8UC1, cv::Scalar(100));
    FrameOverlay o;
    o.markers_meas_px = {{300.0, 300.0}};
    o.markers_sim_px = {{300.4, 299.7}};
    o.marker_radius_px = 4;
    o.residual_scale = scale;
    const cv::Mat img = DrawOverlay(grey, o);
    // The arrow's pixels (its colour, strongly) in the window about the marker; the farthest
    // from the measured centre is the arrow's end.
    auto arrow_pixels = [](const cv::Mat& image, cv::Point2d& tip) {
      double farthest = 0;
      int n = 0;
      for (int y = 240; y < 360; ++y)
        for (int x = 240; x < 360; ++x)
          if (IsColour(image.at<cv::Vec3b>(y, x), kResidual, 60)) {
            ++n;
            const double d = std::hypot(x - 300.0, y - 300.0);
            if (d > farthest) farthest = d, tip = cv::Point2d(x, y);
          }
      return n;
    };
    cv::Point2d tip;
    ASSERT_GT(arrow_pixels(img, tip), 5) << "F = " << scale;
    EXPECT_LE(std::hypot(tip.x - end.x, tip.y - end.y), 1.5)
        << "F = " << scale << ": tip at " << tip << ", expected " << end;
    // Without the magnification (0) no arrow is drawn.
    o.residual_scale = 0;
    EXPECT_EQ(arrow_pixels(DrawOverlay(grey, o), tip), 0);
  }
}

TEST(OverlayTest, TheLegendStatesTheGlyphsTheMagnificationAndThePace) {
  FrameOverlay o;
  o.residual_scale = 20;
  o.pace = PlanVideo(8000, 1000).Legend();
  std::string all;
  for (const auto& [line, colour] : OverlayLegend(o)) all += line + "\n";
  EXPECT_NE(all.find("o  measured marker\n"), std::string::npos) << all;
  EXPECT_NE(all.find("+  simulated marker, outline\n"), std::string::npos) << all;
  EXPECT_NE(all.find("-> residual x 20 (sim. - meas.)\n"), std::string::npos) << all;
  EXPECT_NE(all.find("video 1/1000 of real time, 8 frames/s\n"), std::string::npos) << all;
}

TEST(OverlayTest, TheLegendGoesToTheCornerThatHidesTheFewestMarks) {
  const cv::Size size(600, 400);
  FrameOverlay o;
  o.residual_scale = 20;
  o.marker_radius_px = 4;
  const cv::Rect box = LegendRect(size, o);  // top left
  EXPECT_EQ(box.x, 0);
  EXPECT_EQ(box.y, 0);
  ASSERT_GT(box.width, 100);
  ASSERT_GT(box.height, 50);
  o.legend_corner = 3;  // bottom right
  const cv::Rect br = LegendRect(size, o);
  EXPECT_EQ(br.x + br.width, 600);
  EXPECT_EQ(br.y + br.height, 400);
  EXPECT_EQ(br.size(), box.size());
  // Nothing drawn: the top left. A marker there: the top right. Markers in both top corners:
  // the bottom left.
  o.legend_corner = 0;
  EXPECT_EQ(LegendCorner(size, {o}), 0);
  o.markers_meas_px = {{30.0, 30.0}};
  o.markers_sim_px = {{30.0, 30.0}};
  EXPECT_EQ(LegendCorner(size, {o}), 1);
  FrameOverlay later = o;
  later.markers_meas_px = {{570.0, 30.0}};
  later.markers_sim_px = {{570.0, 30.0}};
  EXPECT_EQ(LegendCorner(size, {o, later}), 2);
  // A residual arrow that reaches into the bottom left from outside it counts too.
  FrameOverlay arrow = o;
  arrow.markers_meas_px = {{300.0, 200.0}};
  arrow.markers_sim_px = {{300.0 - 250.0 / 20, 200.0 + 180.0 / 20}};  // ends at (50, 380)
  EXPECT_EQ(LegendCorner(size, {o, later, arrow}), 3);
}

TEST(OverlayTest, TheVideoPaceFollowsTheSlowdown) {
  // 8000 fps at 1/1000: 8 captured frames per video second; each written ceil(20 / 8) = 3
  // times, the video at 24 fps.
  VideoPace p = PlanVideo(8000, 1000);
  EXPECT_EQ(p.repeats, 3);
  EXPECT_DOUBLE_EQ(p.video_fps, 24.0);
  EXPECT_DOUBLE_EQ(p.slowdown, 1000.0);
  EXPECT_FALSE(p.limited);
  // 8000 fps at 1/200: 40 frames per second, each once.
  p = PlanVideo(8000, 200);
  EXPECT_EQ(p.repeats, 1);
  EXPECT_DOUBLE_EQ(p.video_fps, 40.0);
  EXPECT_DOUBLE_EQ(p.slowdown, 200.0);
  // 8000 fps at 1/20 would need 400 fps: the video runs at 60 fps, 1/133.3 of real time.
  p = PlanVideo(8000, 20);
  EXPECT_TRUE(p.limited);
  EXPECT_EQ(p.repeats, 1);
  EXPECT_DOUBLE_EQ(p.video_fps, 60.0);
  EXPECT_NEAR(p.slowdown, 8000.0 / 60.0, 1e-9);
  EXPECT_EQ(p.Legend(), "1/133 of real time, 60 frames/s");
  // 1000 fps at 1/3000: 1/3 frame per second, each written 60 times at 20 fps.
  p = PlanVideo(1000, 3000);
  EXPECT_EQ(p.repeats, 60);
  EXPECT_NEAR(p.video_fps, 20.0, 1e-9);
  EXPECT_NEAR(p.slowdown, 3000.0, 1e-9);
  EXPECT_THROW(PlanVideo(0, 10), std::invalid_argument);
  EXPECT_THROW(PlanVideo(8000, 0), std::invalid_argument);
}

TEST(OverlayTest, OptionsAreValidated) {
  OverlayOptions o;
  EXPECT_NO_THROW(o.Validate());
  EXPECT_EQ(o.slowdown, 1000);
  EXPECT_EQ(o.residual_scale, compare::replay::kDefaultResidualScale);
  o.slowdown = 0;
  EXPECT_THROW(o.Validate(), std::invalid_argument);
  o = {};
  for (const int bad : {0, -3, 1001}) {
    o.residual_scale = bad;
    try {
      o.Validate();
      ADD_FAILURE() << bad << ": no exception";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("residual_scale"), std::string::npos) << e.what();
    }
  }
}

/// A folder with a trial.json.
void MakeTrial(const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "trial.json") << "{}";
}

TEST(ReplayConventionTest, ATrialFolderIsFoundUnderTheMovedStudyFolder) {
  namespace fs = std::filesystem;
  using compare::replay::LocateTrialFolder;
  const fs::path root =
      fs::temp_directory_path() / ("replay_convention_" + std::to_string(::getpid()));
  fs::remove_all(root);
  // Recorded: /old/study/trials/t1 in /old/study; moved to root/new/study.
  const fs::path old_study = root / "old" / "study", new_study = root / "new" / "study";
  MakeTrial(new_study / "trials" / "t1");
  auto s = LocateTrialFolder(old_study / "trials" / "t1", old_study, new_study);
  ASSERT_TRUE(s.found);
  EXPECT_EQ(*s.found, new_study / "trials" / "t1");
  EXPECT_EQ(s.tried.size(), 2u);
  // A trailing separator on the recorded folder changes nothing.
  s = LocateTrialFolder((old_study / "trials" / "t1").string() + "/", old_study.string() + "/",
                        new_study);
  ASSERT_TRUE(s.found);
  EXPECT_EQ(*s.found, new_study / "trials" / "t1");
  // Without the new place it is not found; the message names the recorded folder and the
  // option.
  s = LocateTrialFolder(old_study / "trials" / "t1", old_study);
  EXPECT_FALSE(s.found);
  const std::string m = compare::replay::NotFoundMessage(s, false);
  EXPECT_NE(m.find((old_study / "trials" / "t1").string()), std::string::npos) << m;
  EXPECT_NE(m.find("--study-dir"), std::string::npos) << m;
  // Where it is still recorded, the recorded folder wins.
  MakeTrial(old_study / "trials" / "t1");
  s = LocateTrialFolder(old_study / "trials" / "t1", old_study, new_study);
  ASSERT_TRUE(s.found);
  EXPECT_EQ(*s.found, old_study / "trials" / "t1");
  // A trial folder outside the study folder is looked for by its name in the new place.
  MakeTrial(new_study / "t2");
  s = LocateTrialFolder(root / "elsewhere" / "t2", old_study, new_study);
  ASSERT_TRUE(s.found);
  EXPECT_EQ(*s.found, new_study / "t2");
  fs::remove_all(root);
}

}  // namespace
}  // namespace hoof::overlay
