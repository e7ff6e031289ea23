// Finding a ball by its motion (tracking/motion_blobs.h, pipeline/moving_body.h) on drawn colour
// scenes whose truth is known in closed form: a cluttered static background, a red ball bouncing
// on parabolas with e = 0.75, its shadow sliding on the floor, a hand that holds the ball and
// leaves, and camera noise. The ball's path is the body; the others are refused with their
// reasons; its centre is measured to a fraction of a pixel; gravity's direction comes from its
// arcs; a ball that leaves the view and comes back is joined; a clip that shows captures early
// (a frame-rate conversion) is timed by their last copies; clips with nothing ballistic are
// refused naming the frames.
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "pipeline/moving_body.h"
#include "tracking/frame_source.h"
#include "tracking/motion_blobs.h"

namespace {

using hoof::pipeline::CandidateVerdict;
using hoof::pipeline::FindMovingBody;
using hoof::pipeline::MovingBody;

class ColourSource : public hoof::tracking::FrameSource {
 public:
  std::vector<cv::Mat> frames;
  int count() const override { return static_cast<int>(frames.size()); }
  cv::Mat Read(int i) override { return ReadColour(i); }
  cv::Mat ReadColour(int i) override { return frames.at(static_cast<std::size_t>(i)); }
  std::string Describe(int i) const override { return "drawn frame " + std::to_string(i); }
};

constexpr int kW = 320, kH = 240;
constexpr double kFps = 30.0, kRadius = 9.0, kE = 0.75, kFloorY = 200.0;

/// A cluttered static scene: a wall of coloured blocks (shelves, objects) and a pale floor.
cv::Mat Room(unsigned seed) {
  cv::Mat img(kH, kW, CV_32FC3, cv::Scalar(150, 160, 170));
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> x(0, kW - 40), y(0, static_cast<int>(kFloorY) - 60),
      size(8, 40), level(40, 230);
  for (int k = 0; k < 25; ++k)
    cv::rectangle(img, cv::Rect(x(rng), y(rng), size(rng), size(rng)),
                  cv::Scalar(level(rng), level(rng), level(rng)), cv::FILLED);
  img(cv::Rect(0, static_cast<int>(kFloorY), kW, kH - static_cast<int>(kFloorY)))
      .setTo(cv::Scalar(200, 205, 210));
  return img;
}

/// Area-sampled paint: `colour` over the pixels inside `inside`, 4 x 4 samples a pixel at the
/// edge, within the box [x0, x1] x [y0, y1].
template <typename Inside>
void Paint(cv::Mat& img, Inside inside, const cv::Vec3f& colour, int x0, int y0, int x1, int y1,
           bool multiply = false) {
  for (int y = std::max(0, y0); y <= std::min(img.rows - 1, y1); ++y)
    for (int x = std::max(0, x0); x <= std::min(img.cols - 1, x1); ++x) {
      int n = 0;
      for (int sy = 0; sy < 4; ++sy)
        for (int sx = 0; sx < 4; ++sx) n += inside(x - 0.375 + 0.25 * sx, y - 0.375 + 0.25 * sy);
      if (n == 0) continue;
      const float f = static_cast<float>(n) / 16.0f;
      cv::Vec3f& p = img.at<cv::Vec3f>(y, x);
      for (int c = 0; c < 3; ++c)
        p[c] = multiply ? p[c] * (1 - f + f * colour[c]) : (1 - f) * p[c] + f * colour[c];
    }
}

/// The ball's centre at time t: released at `start` with speed vx across gravity and vs0 along
/// it, gravity g along `down` (unit, image axes), bouncing with e on a floor perpendicular to it
/// at `floor` along `down` (its centre's level at contact). Also the bounce times before t.
Eigen::Vector2d BallAt(double t, const Eigen::Vector2d& start, double vx, double vs0, double g,
                       const Eigen::Vector2d& down, double floor, std::vector<double>* bounces) {
  const Eigen::Vector2d side(down.y(), -down.x());  // across gravity, toward +x of the image
  double s = start.dot(down), u = start.dot(side), vs = vs0, t0 = 0.0;
  while (true) {
    // Time to the floor from s with speed vs: floor = s + vs dt + g dt^2 / 2.
    const double dt = (-vs + std::sqrt(vs * vs + 2 * g * (floor - s))) / g;
    if (t0 + dt > t || dt < 1e-4) break;
    t0 += dt;
    if (bounces) bounces->push_back(t0);
    vs = -kE * (vs + g * dt);
    s = floor;
  }
  const double dt = t - t0;
  const double s_t = s + vs * dt + 0.5 * g * dt * dt;
  return s_t * down + (u + vx * t) * side;
}

struct Scene {
  ColourSource source;
  std::vector<Eigen::Vector2d> centre;  ///< truth per frame
  std::vector<double> bounces;          ///< bounce times
};

/// The room with the ball (and, by the flags, its shadow, a hand holding it for the first
/// frames, noise), `frames` frames at kFps, gravity `g` px/s^2 along `down`.
Scene Draw(int frames, bool ball, bool shadow, bool hand, const Eigen::Vector2d& down,
           double g = 1600.0, Eigen::Vector2d start = {110.0, 50.0}, double vx = 70.0,
           double vs0 = 0.0, unsigned seed = 3) {
  Scene sc;
  const cv::Mat room = Room(seed);
  std::mt19937 rng(seed + 100);
  std::normal_distribution<float> noise(0.0f, 2.0f);
  const double floor = kFloorY - kRadius;
  const int held = hand ? 4 : 0;  // frames the hand holds the ball still at the start
  for (int f = 0; f < frames; ++f) {
    cv::Mat img = room.clone();
    const double t = std::max(0.0, (f - held) / kFps);
    const Eigen::Vector2d c = BallAt(t, start, vx, vs0, g, down, floor, nullptr);
    sc.centre.push_back(c);
    if (shadow && ball) {
      const double sx = c.x(), sy = kFloorY + 6;
      Paint(
          img,
          [&](double x, double y) {
            return (x - sx) * (x - sx) / (14.0 * 14.0) + (y - sy) * (y - sy) / 16.0 <= 1.0;
          },
          cv::Vec3f(0.55f, 0.55f, 0.55f), static_cast<int>(sx - 16), static_cast<int>(sy - 5),
          static_cast<int>(sx + 16), static_cast<int>(sy + 5), true);
    }
    if (ball)
      Paint(
          img,
          [&](double x, double y) {
            return (x - c.x()) * (x - c.x()) + (y - c.y()) * (y - c.y()) <= kRadius * kRadius;
          },
          cv::Vec3f(50, 40, 200), static_cast<int>(c.x() - kRadius - 2),
          static_cast<int>(c.y() - kRadius - 2), static_cast<int>(c.x() + kRadius + 2),
          static_cast<int>(c.y() + kRadius + 2));
    if (hand) {
      // Skin, above the ball while it holds it, then withdrawn up and out of view.
      const double away = f < held ? 0.0 : 60.0 * (f - held + 1);
      const double hx = start.x() - 15, hy = start.y() - kRadius - 22 - away;
      Paint(
          img,
          [&](double x, double y) { return x >= hx && x <= hx + 30 && y >= hy && y <= hy + 24; },
          cv::Vec3f(120, 150, 200), static_cast<int>(hx), static_cast<int>(hy),
          static_cast<int>(hx + 31), static_cast<int>(hy + 25));
    }
    cv::Mat out(kH, kW, CV_8UC3);
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x)
        for (int ch = 0; ch < 3; ++ch)
          out.at<cv::Vec3b>(y, x)[ch] =
              cv::saturate_cast<uchar>(img.at<cv::Vec3f>(y, x)[ch] + noise(rng));
    sc.source.frames.push_back(out);
  }
  if (ball) BallAt((frames - 1 - held) / kFps, start, vx, vs0, g, down, floor, &sc.bounces);
  for (double& b : sc.bounces) b += held / kFps;
  return sc;
}

MovingBody Find(Scene& sc, const hoof::pipeline::MovingBodyOptions& options = {}) {
  const cv::Mat background = hoof::tracking::MedianBackground(sc.source, options.motion);
  return FindMovingBody(hoof::tracking::FindMotion(sc.source, background, options.motion), kFps,
                        "drawn", options);
}

TEST(MovingBodyTest, TheBouncingBallIsTheBodyAndItsShadowAndTheHandAreNot) {
  Scene sc = Draw(45, true, true, true, {0.0, 1.0});
  const MovingBody m = Find(sc);
  ASSERT_TRUE(m.found) << m.message;
  EXPECT_TRUE(m.round);
  ASSERT_FALSE(m.candidates.empty());
  EXPECT_EQ(m.candidates.front().verdict, CandidateVerdict::kBody) << m.candidates.front().reason;
  // Its size and colour, from its own regions.
  EXPECT_NEAR(m.diameter_px, 2 * kRadius, 0.6);
  EXPECT_NEAR(m.rgb[0], 200, 25);  // red (RGB order)
  EXPECT_LT(m.rgb[2], 90);
  // No other path is taken for it, and whatever else moves is refused with a reason.
  for (std::size_t i = 1; i < m.candidates.size(); ++i) {
    EXPECT_NE(m.candidates[i].verdict, CandidateVerdict::kBody);
    EXPECT_FALSE(m.candidates[i].reason.empty());
  }
  // The centre, measured on every frame of its flights, against the drawn one; frames in
  // contact with the floor (the shadow touches the ball there) are allowed more.
  int measured = 0;
  double worst = 0;
  for (std::size_t f = 0; f < sc.centre.size(); ++f) {
    const auto& o = m.track.frames[f];
    if (!o.found) continue;
    ++measured;
    const double err = (o.p_I - sc.centre[f]).norm();
    const bool touching = sc.centre[f].y() > kFloorY - kRadius - 2;
    if (!touching) worst = std::max(worst, err);
    EXPECT_LT(err, touching ? 1.5 : 0.35) << "frame " << f;
  }
  EXPECT_GE(measured, 36);
  // The hand's frames (held) are not the body's.
  EXPECT_FALSE(m.track.frames[0].found);
  // Gravity's direction from the arcs: straight down, within half a degree.
  ASSERT_TRUE(m.down_measured);
  EXPECT_LT(std::acos(std::min(1.0, m.down_I.y())) * 180 / M_PI, 0.5);
  // The contacts: one per bounce drawn, within a frame of its time.
  ASSERT_EQ(m.arcs.contacts.size(), sc.bounces.size());
  const int first = m.path.first_frame();
  for (std::size_t k = 0; k < sc.bounces.size(); ++k) {
    const double t_after = (first + m.arcs.contacts[k].first_frame_after) / kFps;
    EXPECT_GE(t_after + 1e-9, sc.bounces[k]);
    EXPECT_LT(t_after - sc.bounces[k], 1.0 / kFps + 1e-9);
  }
}

// A frame-rate conversion that leaves one capture in three out and shows the next one in its
// place and then again (captures 0, 2, 2, 3, 5, 5, ...): timed by frame index, the first copy
// would put the ball where it is a period later. Its last copy is the sample.
TEST(MovingBodyTest, AClipThatShowsCapturesEarlyIsTimedByTheirLastCopies) {
  Scene sc = Draw(60, true, false, false, {0.0, 1.0});
  Scene clip;
  for (int j = 0; j < 60; ++j) {
    const int slot = j % 3 == 1 ? j + 1 : j;  // j % 3 == 2: the same capture as frame j - 1
    clip.source.frames.push_back(sc.source.frames[static_cast<std::size_t>(slot)].clone());
  }
  const MovingBody m = Find(clip);
  ASSERT_TRUE(m.found) << m.message;
  ASSERT_EQ(m.copies.size(), 60u);
  for (std::size_t j = 1; j < 60; ++j) EXPECT_EQ(m.copies[j], j % 3 == 1) << "frame " << j;
  // Every bounce, and gravity as drawn (1600 px/s^2): timed by their first copies the samples
  // are no parabola at all, and no path is ballistic.
  EXPECT_EQ(m.arcs.contacts.size(), sc.bounces.size());
  EXPECT_NEAR(m.arcs.a_norm, 1600.0, 3 * m.arcs.a_norm_se + 2.0);
}

TEST(MovingBodyTest, ARolledCameraGivesGravitysDirectionFromTheArcs) {
  const double roll = 8.0 * M_PI / 180;
  Scene sc =
      Draw(40, true, false, false, {std::sin(roll), std::cos(roll)}, 1600.0, {60.0, 40.0}, 50.0);
  const MovingBody m = Find(sc);
  ASSERT_TRUE(m.found) << m.message;
  ASSERT_TRUE(m.down_measured);
  const double found = std::atan2(m.down_I.x(), m.down_I.y()) * 180 / M_PI;
  EXPECT_NEAR(found, 8.0, 3 * m.down_se_deg + 0.2);
  EXPECT_LT(m.down_se_deg, 1.0);
}

TEST(MovingBodyTest, ABallThatLeavesTheViewAndComesBackIsJoined) {
  // Thrown up at 900 px/s from 150 px down the frame: its centre rises to 103 px above the top,
  // out of view for about 20 frames, and falls back to bounce on the floor.
  Scene sc = Draw(50, true, false, false, {0.0, 1.0}, 1600.0, {60.0, 150.0}, 40.0, -900.0);
  const MovingBody m = Find(sc);
  ASSERT_TRUE(m.found) << m.message;
  bool joined = false;
  for (const auto& c : m.candidates) joined |= c.verdict == CandidateVerdict::kJoined;
  EXPECT_TRUE(joined);
  // Measured before it leaves and after it comes back.
  int before = 0, after = 0;
  for (std::size_t f = 0; f < m.track.frames.size(); ++f) {
    if (!m.track.frames[f].found) continue;
    (f < 10 ? before : after) += 1;
    EXPECT_LT((m.track.frames[f].p_I - sc.centre[f]).norm(), 1.5) << "frame " << f;
  }
  EXPECT_GE(before, 4);
  EXPECT_GE(after, 12);
}

TEST(MovingBodyTest, AClipWhereOnlyAHandMovesIsRefusedNamingTheFrames) {
  Scene sc = Draw(30, false, false, true, {0.0, 1.0});
  const MovingBody m = Find(sc);
  EXPECT_FALSE(m.found);
  EXPECT_NE(m.message.find("drawn"), std::string::npos) << m.message;
  EXPECT_TRUE(m.message.find("frames") != std::string::npos ||
              m.message.find("no moving body") != std::string::npos)
      << m.message;
}

TEST(MovingBodyTest, AClipWhereNothingMovesHasNoMovingBody) {
  Scene sc = Draw(20, false, false, false, {0.0, 1.0});
  const MovingBody m = Find(sc);
  EXPECT_FALSE(m.found);
  EXPECT_NE(m.message.find("no moving body"), std::string::npos) << m.message;
}

TEST(MovingBodyTest, AStatedColourThatNoPathHasRefusesTheBall) {
  Scene sc = Draw(40, true, false, false, {0.0, 1.0});
  hoof::pipeline::MovingBodyOptions o;
  o.rgb = Eigen::Vector3d(40, 160, 60);  // green: the ball is red
  const MovingBody m = Find(sc, o);
  EXPECT_FALSE(m.found);
  ASSERT_FALSE(m.candidates.empty());
  EXPECT_EQ(m.candidates.front().verdict, CandidateVerdict::kNotLikeBody);
}

TEST(MotionBlobsTest, AShadowBarelyShowsInTheLikenessAndAColouredBallDoes) {
  cv::Mat bg(8, 8, CV_8UC3, cv::Scalar(180, 190, 200));
  cv::Mat shadow = bg * 0.6, ball(8, 8, CV_8UC3, cv::Scalar(50, 40, 200));
  const cv::Mat ls = hoof::tracking::Likeness(shadow, bg), lb = hoof::tracking::Likeness(ball, bg);
  EXPECT_LE(cv::norm(ls, cv::NORM_INF), 1.0);  // within rounding of the 8-bit shadow
  EXPECT_GT(cv::mean(lb)[0], 100);
}

TEST(MotionBlobsTest, TheMedianBackgroundIsTheSceneWithoutTheMovingBall) {
  Scene with = Draw(30, true, false, false, {0.0, 1.0});
  const cv::Mat background = hoof::tracking::MedianBackground(with.source);
  Scene without = Draw(30, false, false, false, {0.0, 1.0});
  // The median of noisy frames: the noise-free room within a few levels everywhere.
  cv::Mat diff;
  cv::absdiff(background, without.source.frames[0], diff);
  cv::Mat flat = diff.reshape(1);
  EXPECT_LT(cv::mean(flat)[0], 2.5);
  double worst = 0;
  cv::minMaxLoc(flat, nullptr, &worst);
  EXPECT_LT(worst, 12);
}

// The background is the median at every pixel and channel: the element at sorted index m / 2
// of the m frames it takes, checked against std::nth_element on random bytes (odd and even m,
// a width whose bytes do not fill the blocks the median works in, and values at 0 and 255).
TEST(MotionBlobsTest, TheMedianBackgroundIsTheMedianOfEveryPixel) {
  for (const int m : {41, 6, 3}) {
    ColourSource source;
    std::mt19937 rng(static_cast<unsigned>(m));
    std::uniform_int_distribution<int> level(0, 255);
    for (int f = 0; f < m; ++f) {
      cv::Mat img(7, 203, CV_8UC3);
      for (auto it = img.begin<cv::Vec3b>(); it != img.end<cv::Vec3b>(); ++it)
        for (int c = 0; c < 3; ++c) (*it)[c] = static_cast<std::uint8_t>(level(rng));
      source.frames.push_back(img);
    }
    source.frames[0].row(0).setTo(cv::Scalar(255, 255, 255));
    source.frames[1 % m].row(1).setTo(cv::Scalar(0, 0, 0));
    const cv::Mat background = hoof::tracking::MedianBackground(source);
    ASSERT_EQ(background.type(), CV_8UC3);
    int wrong = 0;
    for (int y = 0; y < 7; ++y)
      for (int x = 0; x < 3 * 203; ++x) {
        std::vector<std::uint8_t> v;
        for (const auto& f : source.frames) v.push_back(f.ptr<std::uint8_t>(y)[x]);
        std::nth_element(v.begin(), v.begin() + m / 2, v.end());
        wrong += background.ptr<std::uint8_t>(y)[x] != v[static_cast<std::size_t>(m / 2)] ? 1 : 0;
      }
    EXPECT_EQ(wrong, 0) << m << " frames";
  }
}

// The thumbnails the motion finder keeps for the contact sheet are the clip's frames, in order,
// grey and at ThumbnailSize: each within a level or two of the frame made grey and scaled
// directly, and further from every other frame (the ball moves). None without thumbnail_px.
TEST(MotionBlobsTest, TheKeptThumbnailsAreTheFramesInOrder) {
  Scene sc = Draw(12, true, true, false, {0.0, 1.0});
  const cv::Mat background = hoof::tracking::MedianBackground(sc.source);
  EXPECT_TRUE(hoof::tracking::FindMotion(sc.source, background).thumbnails.empty());
  hoof::tracking::MotionOptions options;
  options.thumbnail_px = 160;
  const auto scene = hoof::tracking::FindMotion(sc.source, background, options);
  ASSERT_EQ(scene.thumbnails.size(), sc.source.frames.size());
  const cv::Size size = hoof::tracking::ThumbnailSize({kW, kH}, 160);
  EXPECT_EQ(size, cv::Size(160, 120));
  std::vector<cv::Mat> direct;
  for (const cv::Mat& frame : sc.source.frames) {
    cv::Mat grey, small;
    cv::cvtColor(frame, grey, cv::COLOR_BGR2GRAY);
    cv::resize(grey, small, size, 0, 0, cv::INTER_AREA);
    direct.push_back(small);
  }
  for (std::size_t f = 0; f < direct.size(); ++f) {
    const cv::Mat& t = scene.thumbnails[f];
    ASSERT_EQ(t.size(), size);
    ASSERT_EQ(t.type(), CV_8UC1);
    const double own = cv::norm(t, direct[f], cv::NORM_L1) / static_cast<double>(t.total());
    EXPECT_LT(own, 2.0) << "frame " << f;
    for (std::size_t g = 0; g < direct.size(); ++g) {
      if (g == f) continue;
      EXPECT_LT(cv::norm(t, direct[f], cv::NORM_INF), cv::norm(t, direct[g], cv::NORM_INF))
          << "frame " << f << " against frame " << g;
    }
  }
}

// A ball smeared by motion blur to four times its length, with stripes across it, before a
// plain wall: where the edge fit has no circle to take, the region's centroid, the centre at
// mid-exposure, stands in.
TEST(MotionBlobsTest, ABallSmearedByMotionBlurIsMeasuredAtItsMidExposureCentre) {
  ColourSource source;
  const cv::Mat room(kH, kW, CV_32FC3, cv::Scalar(150, 160, 170));  // a plain wall
  std::vector<Eigen::Vector2d> centre;
  const double step = 36.0, radius = 9.0;  // px per frame, all of it exposed
  for (int f = 0; f < 8; ++f) {
    cv::Mat img = room.clone();
    const Eigen::Vector2d c(20 + step * f, 100 + 6 * f);
    centre.push_back(c);
    cv::Mat smear(img.size(), CV_32FC3, cv::Scalar(0, 0, 0));
    cv::Mat weight(img.size(), CV_32F, cv::Scalar(0));
    constexpr int kSubsteps = 24;
    for (int k = 0; k < kSubsteps; ++k) {
      const double u = (k + 0.5) / kSubsteps - 0.5;
      const Eigen::Vector2d q = c + u * Eigen::Vector2d(step, 6);
      cv::Mat disc(img.size(), CV_32F, cv::Scalar(0));
      cv::circle(disc, cv::Point2d(q.x(), q.y()) * 16, static_cast<int>(radius * 16),
                 cv::Scalar(1.0 / kSubsteps), cv::FILLED, cv::LINE_AA, 4);
      // Dark stripes across the ball, turning with it.
      for (int stripe = -1; stripe <= 1; ++stripe)
        cv::line(disc, cv::Point2d(q.x() + 3 * stripe + 3 * u, q.y() - radius) * 16,
                 cv::Point2d(q.x() + 3 * stripe - 3 * u, q.y() + radius) * 16, cv::Scalar(0), 4,
                 cv::LINE_AA, 4);
      weight += disc;
    }
    for (int y = 0; y < img.rows; ++y)
      for (int x = 0; x < img.cols; ++x) {
        const float w = std::min(1.0f, weight.at<float>(y, x));
        cv::Vec3f& p = img.at<cv::Vec3f>(y, x);
        for (int ch = 0; ch < 3; ++ch) p[ch] = (1 - w) * p[ch] + w * (ch == 1 ? 220.0f : 40.0f);
      }
    cv::Mat out;
    img.convertTo(out, CV_8UC3);
    source.frames.push_back(out);
  }
  const cv::Mat background = hoof::tracking::MedianBackground(source);
  const auto scene = hoof::tracking::FindMotion(source, background);
  ASSERT_FALSE(scene.paths.empty());
  const auto track = hoof::tracking::MeasureBallPath(scene.paths.front(), 8);
  int found = 0, by_centroid = 0;
  for (int f = 1; f < 7; ++f) {  // the first and last frames: half the ball is in the background
    const auto& o = track.frames[static_cast<std::size_t>(f)];
    ASSERT_TRUE(o.found) << "frame " << f << ": " << o.status;
    ++found;
    by_centroid += o.status.find("centroid") != std::string::npos ? 1 : 0;
    EXPECT_LT((o.p_I - centre[static_cast<std::size_t>(f)]).norm(), 2.0)
        << "frame " << f << ": " << o.status;
  }
  EXPECT_EQ(found, 6);
  EXPECT_GE(by_centroid, 1);
}

}  // namespace
