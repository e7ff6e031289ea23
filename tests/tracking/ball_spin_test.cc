#include "tracking/ball_spin.h"

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace hoof::tracking {
namespace {

constexpr double kPi = std::numbers::pi;

/// How the test ball's face is painted.
enum class Pattern { kPlain, kCross, kStripes };

/// A ball of radius `r` px at `c` on a grey background, its face turned by `turn_I` (image
/// sense): a base level with a shading gradient from the upper left and a specular highlight
/// (neither turns with the ball), and the pattern (which does). Each pixel is the mean of 4 x 4
/// sub-samples; Gaussian noise of s.d. `noise` (unit levels) is added. 8-bit.
/// `fixed` adds shading that stays put in the image and that a ring's first harmonic does not
/// hold: a second harmonic around the centre (as a light's terminator or a camera's gamma).
cv::Mat DrawBall(int w, int h, Eigen::Vector2d c, double r, double turn_I, Pattern pattern,
                 double noise, std::mt19937_64& rng, double fixed = 0.0) {
  std::normal_distribution<double> n01(0.0, 1.0);
  cv::Mat img(h, w, CV_8U);
  const double cs = std::cos(turn_I), sn = std::sin(turn_I);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double sum = 0;
      for (int sy = 0; sy < 4; ++sy)
        for (int sx = 0; sx < 4; ++sx) {
          const double px = x - 0.375 + 0.25 * sx - c.x(), py = y - 0.375 + 0.25 * sy - c.y();
          if (px * px + py * py > r * r) {
            sum += 0.3;
            continue;
          }
          // The pattern in the ball's own frame: the point turned back by the ball's turn.
          const double u = cs * px + sn * py, v = -sn * px + cs * py;
          double level = 0.55 - 0.15 * (px + py) / r;  // lit from the upper left
          level += fixed * (px * px - py * py) / (r * r);
          if (pattern == Pattern::kCross && (std::abs(u) < 0.12 * r || std::abs(v) < 0.12 * r))
            level -= 0.3;
          if (pattern == Pattern::kStripes && std::cos(3 * kPi * u / r) > 0.3) level -= 0.3;
          const double hx = px + 0.4 * r, hy = py + 0.4 * r;  // the highlight
          level += 0.35 * std::exp(-(hx * hx + hy * hy) / (0.02 * r * r));
          sum += level;
        }
      const double v = sum / 16 + noise * n01(rng);
      img.at<unsigned char>(y, x) = cv::saturate_cast<unsigned char>(255 * v);
    }
  return img;
}

// One pair: the turn of a drawn cross between two frames, with the ball moved between them. A
// cross looks alike after a quarter turn, so one pair gives the turn up to quarter turns.
TEST(BallSpinTest, TheTurnBetweenTwoFramesIsTheTurnDrawn) {
  std::mt19937_64 rng(3);
  for (double turn_deg : {-40.0, -7.5, 0.0, 3.0, 25.0}) {
    const Eigen::Vector2d a(60.3, 58.8), b(71.9, 61.2);
    const cv::Mat fa = DrawBall(130, 120, a, 24, 0.2, Pattern::kCross, 0.01, rng);
    const cv::Mat fb =
        DrawBall(130, 120, b, 24, 0.2 + turn_deg * kPi / 180, Pattern::kCross, 0.01, rng);
    const BallFace face_a = SampleBallFace(fa, a, 24, 0.0), face_b = SampleBallFace(fb, b, 24, 0.0);
    ASSERT_TRUE(face_a.textured) << face_a.why;
    ASSERT_TRUE(face_b.textured) << face_b.why;
    const FaceTurn t = BestTurn(FaceCorrelation(face_a, face_b));
    EXPECT_NEAR(std::remainder(t.turn_I_rad * 180 / kPi - turn_deg, 90.0), 0.0, 0.5)
        << "drawn " << turn_deg << " deg, measured " << t.turn_I_rad * 180 / kPi;
    EXPECT_GT(t.peak, 0.8);
  }
}

// An arc: a constant spin, frames at 30 fps, the pattern's symmetry (a cross repeats every
// quarter turn, stripes every half turn) settled by the fit over all pairs.
TEST(BallSpinTest, AnArcsSpinIsTheSpinDrawn) {
  std::mt19937_64 rng(7);
  const double fps = 30;
  for (const auto& [pattern, w_I] :
       std::vector<std::pair<Pattern, double>>{{Pattern::kCross, 9.0},
                                               {Pattern::kCross, -14.0},
                                               {Pattern::kStripes, 21.0},
                                               {Pattern::kStripes, -4.0}}) {
    std::vector<BallFace> faces;
    std::vector<double> t;
    for (int i = 0; i < 9; ++i) {
      const double ti = i / fps;
      const Eigen::Vector2d c(50 + 4.1 * i, 55 + 1.7 * i);
      const double r = 22 - 0.1 * i;  // a little farther each frame
      faces.push_back(SampleBallFace(
          DrawBall(110, 90 + 20, c, r, 0.4 + w_I * ti, pattern, 0.01, rng), c, r, 0.0));
      t.push_back(ti);
    }
    const ArcSpin s = FitArcSpin(faces, t);
    ASSERT_TRUE(s.measured) << s.why;
    EXPECT_EQ(s.pairs, 8);
    EXPECT_NEAR(s.w_I_rad_s, w_I, 0.05 * std::abs(w_I) + 0.3) << "drawn " << w_I << " rad/s";
    EXPECT_LT(std::abs(s.w_I_rad_s - w_I), 4 * s.w_se_rad_s + 0.05)
        << "error " << s.w_I_rad_s - w_I << " for s.e. " << s.w_se_rad_s;
  }
}

// Shading that stays where it is in the image, beyond what a ring's first harmonic holds, would
// pull every pair's turn toward none; it is the arc's mean face, and is taken out.
TEST(BallSpinTest, ShadingThatStaysPutDoesNotSlowTheSpin) {
  std::mt19937_64 rng(5);
  const double fps = 60, w_I = 12.0;
  std::vector<BallFace> faces;
  std::vector<double> t;
  for (int i = 0; i < 12; ++i) {
    const Eigen::Vector2d c(45 + 2.5 * i, 50 + 0.8 * i);
    faces.push_back(SampleBallFace(
        DrawBall(110, 100, c, 18, 0.1 + w_I * i / fps, Pattern::kStripes, 0.01, rng, 0.3), c, 18,
        0.0));
    t.push_back(i / fps);
  }
  const ArcSpin s = FitArcSpin(faces, t);
  ASSERT_TRUE(s.measured) << s.why;
  EXPECT_NEAR(s.w_I_rad_s, w_I, 0.05 * w_I) << "drawn " << w_I << " rad/s";
}

// Faces that hold only noise, let through as textured by a low threshold: the turns that best
// correlate them correlate poorly, and no spin is reported.
TEST(BallSpinTest, NoiseIsNotTakenForATurningTexture) {
  std::mt19937_64 rng(13);
  BallSpinOptions o;
  o.min_texture_to_noise = 0.01;
  std::vector<BallFace> faces;
  std::vector<double> t;
  for (int i = 0; i < 10; ++i) {
    const Eigen::Vector2d c(50 + 2.0 * i, 50);
    faces.push_back(
        SampleBallFace(DrawBall(110, 100, c, 20, 0.0, Pattern::kPlain, 0.03, rng), c, 20, 0.0, o));
    ASSERT_TRUE(faces.back().textured);
    t.push_back(i / 30.0);
  }
  const ArcSpin s = FitArcSpin(faces, t, o);
  EXPECT_FALSE(s.measured) << s.w_I_rad_s << " rad/s, mean correlation " << s.mean_peak;
  EXPECT_NE(s.why.find("not a texture turning"), std::string::npos) << s.why;
}

// A ball under 24 px across is not sampled, however clear its pattern: its rings would lie
// less than a pixel apart.
TEST(BallSpinTest, ABallTooSmallIsNotSampled) {
  std::mt19937_64 rng(17);
  const Eigen::Vector2d c(40, 40);
  const BallFace face =
      SampleBallFace(DrawBall(80, 80, c, 10, 0.3, Pattern::kCross, 0.01, rng), c, 10, 0.0);
  EXPECT_FALSE(face.textured);
  EXPECT_NE(face.why.find("too small"), std::string::npos) << face.why;
  BallSpinOptions o;
  o.min_radius_px = 8;
  EXPECT_TRUE(
      SampleBallFace(DrawBall(80, 80, c, 10, 0.3, Pattern::kCross, 0.01, rng), c, 10, 0.0, o)
          .textured);
}

TEST(BallSpinTest, APlainBallShowsNoSpin) {
  std::mt19937_64 rng(11);
  std::vector<BallFace> faces;
  std::vector<double> t;
  for (int i = 0; i < 5; ++i) {
    const Eigen::Vector2d c(50 + 3.0 * i, 50);
    faces.push_back(
        SampleBallFace(DrawBall(110, 100, c, 20, 0.3 * i, Pattern::kPlain, 0.01, rng), c, 20, 0.0));
    EXPECT_FALSE(faces.back().textured) << "texture s.d. " << faces.back().texture_sd;
    t.push_back(i / 30.0);
  }
  const ArcSpin s = FitArcSpin(faces, t);
  EXPECT_FALSE(s.measured);
  EXPECT_NE(s.why.find("no texture"), std::string::npos) << s.why;
}

TEST(BallSpinTest, BadOptionsNameTheField) {
  BallSpinOptions o;
  o.angles = 100;
  EXPECT_THROW(o.Validate(), std::invalid_argument);
  o = {};
  o.inner_fraction = 0.9;
  EXPECT_THROW(o.Validate(), std::invalid_argument);
  o = {};
  o.min_static_faces = 1;
  EXPECT_THROW(o.Validate(), std::invalid_argument);
  o = {};
  o.alias_margin = 1.0;
  EXPECT_THROW(o.Validate(), std::invalid_argument);
  o = {};
  o.min_mean_peak = -0.1;
  EXPECT_THROW(o.Validate(), std::invalid_argument);
}

}  // namespace
}  // namespace hoof::tracking
