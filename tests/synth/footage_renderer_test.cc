// Everyday footage (synth/footage_renderer.h) against ground truth measured in its own frames by
// simple independent means: the ball's colour centroid and area in lossless frames, the
// direction of its fall, the shadow's place, the hand's cover; the H.264 file read back through
// OpenCV after ffmpeg adds the rotation tag; repeats exactly where truth says; same seed, same
// bytes.
#include "synth/footage_renderer.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

namespace hoof::synth {
namespace {

namespace fs = std::filesystem;

fs::path Fresh(const std::string& name) {
  const fs::path p = fs::path(HOOF_BINARY_DIR) / "footage-test" / name;
  fs::remove_all(p);
  fs::create_directories(p.parent_path());
  return p;
}

/// A clean scene: plain wall and floor, no hand, no blur, no noise, no highlight (its white
/// would leave the colour mask), lossless frames.
FootageSpec Clean() {
  FootageSpec s;
  s.camera.width_px = 400;
  s.camera.height_px = 300;
  s.camera.p_W_m = {0.05, 0.30, 0.9};
  s.ball.radius_m = 0.03;
  s.ball.specular = 0;
  s.room.clutter = false;
  s.hand.enabled = false;
  s.sensor.motion_blur = false;
  s.sensor.noise = false;
  s.codec = FootageCodec::kPng;
  s.timing.duration_s = 1.0;
  return s;
}

/// Red pixels: red above both other channels by more than 60 levels (skin is not red).
cv::Mat RedMask(const cv::Mat& bgr) {
  cv::Mat mask(bgr.size(), CV_8U, cv::Scalar(0));
  for (int y = 0; y < bgr.rows; ++y)
    for (int x = 0; x < bgr.cols; ++x) {
      const cv::Vec3b p = bgr.at<cv::Vec3b>(y, x);
      mask.at<uchar>(y, x) = p[2] - std::max(p[0], p[1]) > 60 ? 255 : 0;
    }
  return mask;
}

/// Pixels within `reach` of `around` that differ from the empty room, weighted by how much:
/// the sum over the channels of the absolute difference, / 250, at most 1 (the ball differs from
/// this room by about 350), and 0 below 20 (noise). The ball's shading (darker below, as a real
/// ball is) changes its colour, not its contrast with the room, so this weight falls off at the
/// rim the same way at the bottom as at the top. The window keeps out the shadow on the floor.
cv::Mat ChangedMask(const cv::Mat& bgr, const cv::Mat& room, const Eigen::Vector2d& around,
                    double reach) {
  cv::Mat mask(bgr.size(), CV_32F, cv::Scalar(0));
  for (int y = 0; y < bgr.rows; ++y)
    for (int x = 0; x < bgr.cols; ++x) {
      if ((Eigen::Vector2d(x, y) - around).norm() > reach) continue;
      const cv::Vec3b a = bgr.at<cv::Vec3b>(y, x), b = room.at<cv::Vec3b>(y, x);
      const int d = std::abs(a[0] - b[0]) + std::abs(a[1] - b[1]) + std::abs(a[2] - b[2]);
      mask.at<float>(y, x) = d < 20 ? 0.0f : std::min(1.0f, static_cast<float>(d) / 250.0f);
    }
  return mask;
}

/// The room of `spec` without the ball or the hand.
cv::Mat EmptyRoom(FootageSpec spec) {
  spec.scenario = FootageScenario::kHandOnly;
  spec.hand.enabled = false;
  spec.timing.duration_s = 0.05;
  return RenderFootageFrames(PlanFootage(spec), 0, 1).front();
}

/// The weighted centroid (px, origin at the centre of the top-left pixel) and the total weight
/// of a mask (CV_8U: 255 counts 1; CV_32F: the weight).
Eigen::Vector2d Centroid(const cv::Mat& mask, double& area) {
  cv::Mat w;
  mask.convertTo(w, CV_64F, mask.type() == CV_8U ? 1.0 / 255 : 1.0);
  double n = 0, sx = 0, sy = 0;
  for (int y = 0; y < w.rows; ++y)
    for (int x = 0; x < w.cols; ++x) {
      const double v = w.at<double>(y, x);
      n += v;
      sx += v * x;
      sy += v * y;
    }
  area = n;
  return {sx / n, sy / n};
}

TEST(FootageRendererTest, TheBallsCentroidIsTheTruthsCentreToAFractionOfAPixel) {
  const FootageSpec spec = Clean();
  const FootagePlan plan = PlanFootage(spec);
  const std::vector<cv::Mat> frames = RenderFootageFrames(plan);
  const cv::Mat room = EmptyRoom(spec);
  int checked = 0;
  double worst = 0;
  for (std::size_t j = 0; j < frames.size(); ++j) {
    const FootageFrameTruth& t = plan.truth.frames[j];
    // In view, and high enough that its shadow on the floor lies apart from it.
    if (t.visibility != BallVisibility::kVisible || t.p_WC_m.y() < 4 * spec.ball.radius_m) continue;
    double area = 0;
    const Eigen::Vector2d c =
        Centroid(ChangedMask(frames[j], room, t.center_px, t.radius_px + 4), area);
    worst = std::max(worst, (c - t.center_px).norm());
    // The weight's area, as a radius, against the truth's apparent radius.
    EXPECT_NEAR(std::sqrt(area / std::acos(-1.0)), t.radius_px, 0.15) << j;
    ++checked;
  }
  EXPECT_GE(checked, 20);
  EXPECT_LT(worst, 0.08);
}

TEST(FootageRendererTest, OffTheAxisTheMeasuredCentreIsTheEllipsesNotTheProjection) {
  FootageSpec s = Clean();  // a big ball held still near the frame's corner, no hand
  s.ball.radius_m = 0.07;
  s.launch.x_m = 0.30;
  s.launch.z_m = 0.25;
  s.launch.drop_height_m = 0.15;
  s.camera.tilt_deg = 12;
  s.timing.duration_s = 0.4;  // frame 0 before the release
  const FootagePlan plan = PlanFootage(s);
  const FootageFrameTruth& t = plan.truth.frames.front();
  ASSERT_EQ(t.visibility, BallVisibility::kVisible);
  ASSERT_GT((t.center_px - t.projection_px).norm(), 1.0);  // a case where they differ
  double area = 0;
  const cv::Mat frame = RenderFootageFrames(plan, 0, 1).front();
  const Eigen::Vector2d c =
      Centroid(ChangedMask(frame, EmptyRoom(s), t.center_px, t.radius_px + 4), area);
  EXPECT_LT((c - t.center_px).norm(), 0.1);
  EXPECT_GT((c - t.projection_px).norm(), 0.9);
}

TEST(FootageRendererTest, TheBallFallsAlongTheTruthsGravityInARolledImage) {
  FootageSpec s = Clean();
  s.camera.roll_deg = 10;
  s.timing.capture_fps = 60;
  s.timing.duration_s = 0.6;
  const FootagePlan plan = PlanFootage(s);
  const std::vector<cv::Mat> frames = RenderFootageFrames(plan);
  // The first drop, from release to the first bounce, by least squares: p = a + b t + c t^2.
  cv::Mat A(0, 3, CV_64F), bx(0, 1, CV_64F), by(0, 1, CV_64F);
  for (std::size_t j = 0; j < frames.size(); ++j) {
    const FootageFrameTruth& t = plan.truth.frames[j];
    if (t.phase != BallPhase::kFlight || t.arc != 0 || t.visibility != BallVisibility::kVisible)
      continue;
    double area = 0;
    const Eigen::Vector2d c = Centroid(RedMask(frames[j]), area);
    const double ts = t.frame.t_s;
    A.push_back(cv::Mat(cv::Matx13d(1, ts, ts * ts)));
    bx.push_back(c.x());
    by.push_back(c.y());
  }
  ASSERT_GE(A.rows, 8);
  cv::Mat px, py;
  cv::solve(A, bx, px, cv::DECOMP_SVD);
  cv::solve(A, by, py, cv::DECOMP_SVD);
  const Eigen::Vector2d accel(px.at<double>(2), py.at<double>(2));
  const Eigen::Vector2d g = plan.truth.gravity_image;
  EXPECT_NEAR(std::acos(std::min(1.0, accel.normalized().dot(g))), 0.0, 0.005);  // 0.3 deg
  EXPECT_NEAR(g.x(), -std::sin(10 * std::acos(-1.0) / 180), 0.02);
}

TEST(FootageRendererTest, MotionBlurAveragesTheTrueMotionAcrossABounce) {
  FootageSpec s = Clean();
  s.sensor.motion_blur = true;
  s.room.ambient = 1;  // no direct light: no shadow under the ball at the bounce
  s.timing.exposure_s = 1.0 / 60;
  s.launch.v_W_m_s = {0.5, 0.0, 0.0};  // sideways too
  const FootagePlan plan = PlanFootage(s);
  const cv::Mat room = EmptyRoom(s);
  const double T = plan.truth.schedule.exposure_s;
  int checked = 0;
  for (const FootageBounceTruth& b : plan.truth.bounces) {
    for (const FootageFrameTruth& t : plan.truth.frames) {
      if (std::abs(t.frame.t_s - b.world.t_s) > T / 4) continue;  // the bounce inside the exposure
      // The true image centre averaged over the exposure.
      Eigen::Vector2d mean = Eigen::Vector2d::Zero();
      const int n = 2000;
      for (int i = 0; i < n; ++i) {
        const double ti = t.frame.t_s + T * ((i + 0.5) / n - 0.5);
        mean += plan.camera.ImageOfSphere(plan.path.At(ti).p_WC_m, s.ball.radius_m).center_px;
      }
      mean /= n;
      const cv::Mat frame = RenderFootageFrames(plan, t.frame.index, 1).front();
      // Weighted by the difference from the room in linear light, which is linear in the time
      // the ball covers each pixel.
      const auto linear = [](int level) {
        const double v = level / 255.0;
        return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
      };
      cv::Mat w(frame.size(), CV_32F, cv::Scalar(0));
      double lowest = -1;
      for (int y = 0; y < frame.rows; ++y)
        for (int x = 0; x < frame.cols; ++x) {
          if ((Eigen::Vector2d(x, y) - mean).norm() > 3 * t.radius_px + 4) continue;
          const cv::Vec3b a = frame.at<cv::Vec3b>(y, x), c = room.at<cv::Vec3b>(y, x);
          double d = 0;
          for (int ch = 0; ch < 3; ++ch) d += std::abs(linear(a[ch]) - linear(c[ch]));
          if (d < 0.02) continue;
          w.at<float>(y, x) = static_cast<float>(d);
          lowest = std::max(lowest, static_cast<double>(y));
        }
      // Across the streak the weight is even; along y the ball's shading (darker below, so more
      // contrast with the room) pulls it down by about half a pixel. A path that ignored the
      // bounce would run on into the floor: several pixels lower, and past the floor's line.
      double area = 0;
      const Eigen::Vector2d c = Centroid(w, area);
      EXPECT_NEAR(c.x(), mean.x(), 0.15) << t.frame.index;
      EXPECT_NEAR(c.y(), mean.y(), 0.7) << t.frame.index;
      // The streak stops at the floor: nothing below the ball's lowest point at contact.
      EXPECT_LE(lowest, b.center_px.y() + b.radius_px + 1.5) << t.frame.index;
      EXPECT_GT(t.blur_samples, 8);
      ++checked;
    }
  }
  EXPECT_GE(checked, 1);
}

TEST(FootageRendererTest, TheShadowLiesOnTheFloorAndTheHandCoversWhatTruthSays) {
  FootageSpec s = Clean();
  s.hand.enabled = true;
  s.timing.duration_s = 0.4;  // frame 0 is held (the release is at 0.3 s)
  const FootagePlan plan = PlanFootage(s);
  const cv::Mat room = EmptyRoom(s);
  const cv::Mat frame = RenderFootageFrames(plan, 0, 1).front();
  const FootageFrameTruth& t = plan.truth.frames.front();
  ASSERT_EQ(t.visibility, BallVisibility::kOccluded);
  ASSERT_GT(t.occluded_fraction, 0.05);
  // The red left uncovered, against the red of the same frame without the hand.
  FootageSpec bare = s;
  bare.hand.enabled = false;
  double area = 0, full = 0;
  Centroid(RedMask(frame), area);
  Centroid(RedMask(RenderFootageFrames(PlanFootage(bare), 0, 1).front()), full);
  EXPECT_NEAR(area / full, t.visible_fraction, 0.01);
  // Darkened pixels away from the ball and the hand: the shadow, all below the floor's edge
  // with the wall, around the point below the ball.
  const HandShape hand = plan.hand.ShapeAt(t.frame.t_s);
  const Eigen::Vector2d e0 = plan.truth.surface_edge_px[0], e1 = plan.truth.surface_edge_px[1];
  int dark = 0;
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (int y = 0; y < frame.rows; ++y)
    for (int x = 0; x < frame.cols; ++x) {
      const cv::Vec3b a = frame.at<cv::Vec3b>(y, x), b = room.at<cv::Vec3b>(y, x);
      if (b[1] - a[1] < 4 || (Eigen::Vector2d(x, y) - t.center_px).norm() < t.radius_px + 3 ||
          hand.Distance(x, y) < 3)
        continue;
      const double edge_y = e0.y() + (e1.y() - e0.y()) * (x - e0.x()) / (e1.x() - e0.x());
      EXPECT_GT(y, edge_y) << x << "," << y;
      ++dark;
      sum += Eigen::Vector2d(x, y);
    }
  ASSERT_GT(dark, 20);
  const Eigen::Vector3d L = s.room.light_p_W_m, C = t.p_WC_m;
  const Eigen::Vector2d below = plan.camera.Project(L + (C - L) * (L.y() / (L.y() - C.y())));
  EXPECT_LT((sum / dark - below).norm(), 1.5);
}

TEST(FootageRendererTest, RepeatedFramesAreTheImagesTruthSaysTheyRepeat) {
  FootageSpec s = Clean();
  s.timing = TimingOf(TimingPreset::kScreenRecording);
  s.timing.duration_s = 0.6;
  s.timing.repeat_frames = 1;
  s.sensor.noise = true;
  s.launch.release_time_s = 0.05;
  const fs::path out = Fresh("repeats");
  const FootageResult r = RenderFootage(s, out);
  int repeated = 0;
  std::string previous;
  for (const FootageFrameTruth& t : r.truth.frames) {
    char name[16];
    std::snprintf(name, sizeof name, "%06d.png", t.frame.index);
    std::ifstream in(out / "frames" / name, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_FALSE(bytes.empty()) << name;
    if (t.frame.index > 0) {
      EXPECT_EQ(bytes == previous, t.frame.repeated) << name;
    }
    repeated += t.frame.repeated ? 1 : 0;
    previous = bytes;
  }
  EXPECT_GT(repeated, 10);
  EXPECT_FALSE(fs::exists(out / "trial.json"));
}

TEST(FootageRendererTest, TheSameSeedGivesTheSameBytesAndAnotherSeedOthers) {
  FootageSpec s;  // the cluttered default with a hand, blur and noise, small and short
  s.camera.width_px = 200;
  s.camera.height_px = 120;
  s.codec = FootageCodec::kPng;
  s.timing.duration_s = 0.4;
  const auto render = [&s](const std::string& name) {
    const fs::path out = Fresh(name);
    RenderFootage(s, out, false, 2);
    std::string all;
    for (const char* f :
         {"truth.json", "frames/000000.png", "frames/000006.png", "frames/000011.png"}) {
      std::ifstream in(out / f, std::ios::binary);
      all += std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    }
    return all;
  };
  const std::string a = render("seed-a"), b = render("seed-b");
  EXPECT_GT(a.size(), 1000u);
  EXPECT_EQ(a, b);
  s.seed = 2;
  EXPECT_NE(render("seed-c"), a);
}

// The frames stored turned as a phone stores them, tagged by tools/tag-rotation, and decoded by
// a player (ffmpeg, which turns the frames by the container's display matrix): upright, as the
// lossless frames, with the ball where truth says.
TEST(FootageRendererTest, ARotationTagRoundTripsThroughAPlayer) {
  FootageSpec s = Clean();
  s.codec = FootageCodec::kH264;
  s.camera.width_px = 320;
  s.camera.height_px = 240;
  s.camera.rotation_tag_deg = 90;
  s.timing.duration_s = 0.5;
  const fs::path out = Fresh("rotated");
  const FootageResult r = RenderFootage(s, out);
  EXPECT_EQ(r.truth.stored_width_px, 240);
  EXPECT_EQ(r.truth.stored_height_px, 320);
  cv::VideoCapture raw((out / "clip.mp4").string(), cv::CAP_FFMPEG);
  ASSERT_TRUE(raw.isOpened());
  EXPECT_EQ(raw.get(cv::CAP_PROP_FRAME_WIDTH), 240);  // untagged: stored sideways
  EXPECT_NEAR(raw.get(cv::CAP_PROP_FPS), r.truth.schedule.container_fps, 1e-6);
  raw.release();
  const std::string tool = std::string(HOOF_SOURCE_DIR) + "/tools/tag-rotation";
  ASSERT_EQ(std::system((tool + " '" + out.string() + "'").c_str()), 0);
  fs::create_directories(out / "shown");
  const std::string decode = "ffmpeg -v error -y -i '" + (out / "clip.mp4").string() + "' '" +
                             (out / "shown" / "%04d.png").string() + "'";
  ASSERT_EQ(std::system(decode.c_str()), 0) << decode;
  // Each decoded frame against the lossless upright frame, and the ball where truth says.
  const FootagePlan plan = PlanFootage(s);
  const std::vector<cv::Mat> lossless = RenderFootageFrames(plan);
  const cv::Mat room = EmptyRoom(s);
  int n = 0;
  double worst = 0;
  for (;; ++n) {
    char name[16];
    std::snprintf(name, sizeof name, "%04d.png", n + 1);
    const cv::Mat frame = cv::imread((out / "shown" / name).string(), cv::IMREAD_COLOR);
    if (frame.empty()) break;
    ASSERT_EQ(frame.cols, r.truth.width_px);
    ASSERT_EQ(frame.rows, r.truth.height_px);
    const double mad = cv::norm(frame, lossless[static_cast<std::size_t>(n)], cv::NORM_L1) /
                       static_cast<double>(frame.total() * 3);
    EXPECT_LT(mad, 3.0) << n;  // mean absolute difference, levels
    const FootageFrameTruth& t = r.truth.frames[static_cast<std::size_t>(n)];
    if (t.visibility != BallVisibility::kVisible || t.p_WC_m.y() < 4 * s.ball.radius_m) continue;
    double area = 0;
    const cv::Mat mask = ChangedMask(frame, room, t.center_px, t.radius_px + 4);
    worst = std::max(worst, (Centroid(mask, area) - t.center_px).norm());
  }
  EXPECT_EQ(n, static_cast<int>(r.truth.frames.size()));
  EXPECT_LT(worst, 0.3);  // upright and where truth says, through H.264 and 4:2:0 chroma
}

}  // namespace
}  // namespace hoof::synth
