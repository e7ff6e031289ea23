#include "tracking/silhouette_tracker.h"

#include <cmath>
#include <iostream>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tracking/silhouette_test_images.h"

namespace hoof::tracking {
namespace {

using hoof::testing::PaintDisc;
using hoof::testing::Quantize;

class VectorSource : public FrameSource {
 public:
  std::vector<cv::Mat> frames;
  int count() const override { return static_cast<int>(frames.size()); }
  cv::Mat Read(int i) override { return frames.at(static_cast<std::size_t>(i)); }
  std::string Describe(int i) const override { return "memory frame " + std::to_string(i); }
};

cv::Mat Background(int w, int h, double level) { return cv::Mat(h, w, CV_64F, cv::Scalar(level)); }

/// A disc of radius r at c: level `body` on `bg`, as 8-bit or 12-bit-in-16-bit.
cv::Mat DiscFrame(const Eigen::Vector2d& c, double r, double body, double bg, int depth,
                  double noise = 0, unsigned seed = 1, int size = 160) {
  cv::Mat img = Background(size, size, bg);
  PaintDisc(img, c, r, body, bg);
  return Quantize(img, depth, noise, seed);
}

SilhouetteOptions Ball() { return SilhouetteOptions{}; }

TEST(SilhouetteTrackerTest, BrightDiscOnDarkIsCentredToAFewHundredthsOfAPixel) {
  for (const Eigen::Vector2d& c :
       {Eigen::Vector2d(80.0, 80.0), Eigen::Vector2d(71.37, 90.81), Eigen::Vector2d(85.5, 66.25)}) {
    Polarity p = Polarity::kAuto;
    const auto obs = FindSilhouette(DiscFrame(c, 23.4, 220, 20, CV_8U), Ball(), &p);
    ASSERT_TRUE(obs.found) << obs.status;
    EXPECT_EQ(p, Polarity::kBrightOnDark);
    EXPECT_LT((obs.p_I - c).norm(), 0.02) << c.transpose() << " -> " << obs.p_I.transpose();
    EXPECT_NEAR(obs.diameter_px, 2 * 23.4, 0.1);
    EXPECT_FALSE(obs.has_orientation);
  }
}

TEST(SilhouetteTrackerTest, DarkDiscOnBrightIn12BitValuesFindsItsPolarity) {
  const Eigen::Vector2d c{77.31, 81.62};
  const cv::Mat frame = DiscFrame(c, 30.2, 300, 3900, CV_16U, 20.0, 3);
  const auto [lo, hi] = FrameLevels(frame);
  EXPECT_LE(hi, 4095.0);  // normalised from the data, not from 65535
  EXPECT_GT(lo, 200.0);
  Polarity p = Polarity::kAuto;
  const auto obs = FindSilhouette(frame, Ball(), &p);
  ASSERT_TRUE(obs.found) << obs.status;
  EXPECT_EQ(p, Polarity::kDarkOnBright);
  EXPECT_LT((obs.p_I - c).norm(), 0.05);
  EXPECT_NEAR(obs.diameter_px, 60.4, 0.15);
}

TEST(SilhouetteTrackerTest, BackLitSphereWithABrightCentreSpotIsOneDisc) {
  // A back-lit sphere: a dark disc with a bright spot at its centre (the light through it).
  const Eigen::Vector2d c{79.43, 82.18};
  cv::Mat img = Background(170, 170, 4000);
  PaintDisc(img, c, 40.3, 250, 4000);
  PaintDisc(img, c + Eigen::Vector2d(0.7, -0.4), 15.0, 3600, 250);
  Polarity p = Polarity::kAuto;
  const auto obs = FindSilhouette(Quantize(img, CV_16U, 15.0, 5), Ball(), &p);
  ASSERT_TRUE(obs.found) << obs.status;
  EXPECT_EQ(p, Polarity::kDarkOnBright);
  EXPECT_LT((obs.p_I - c).norm(), 0.05);
  EXPECT_NEAR(obs.diameter_px, 80.6, 0.15);
  EXPECT_EQ(obs.edge_points_rejected, 0);
}

TEST(SilhouetteTrackerTest, MotionBlurredDiscIsCentredOnItsMidExposurePosition) {
  // The exposure integrates 32 positions along 4 px of motion; the truth is the middle.
  const Eigen::Vector2d c{80.27, 78.64}, v{1.2, 3.8};
  cv::Mat img = Background(160, 160, 0);
  for (int k = 0; k < 32; ++k) {
    const Eigen::Vector2d ck = c + v * ((k + 0.5) / 32 - 0.5);
    cv::Mat one = Background(160, 160, 30);
    PaintDisc(one, ck, 25.0, 230, 30);
    img += one / 32;
  }
  const auto obs = FindSilhouette(Quantize(img, CV_8U, 1.5, 7), Ball());
  ASSERT_TRUE(obs.found) << obs.status;
  EXPECT_LT((obs.p_I - c).norm(), 0.05) << obs.p_I.transpose();
}

TEST(SilhouetteTrackerTest, AShadowJoiningTheDiscsLowerEdgeIsRejected) {
  // A dark disc (25) on a bright back-light (230), and a dark shadow blob touching its lower
  // edge. A shadow as dark as the disc hides that part of its edge: the edge points there lie
  // on the shadow's outline, off the circle, and are dropped. A shadow a little lighter (40)
  // leaves a step of 15 between disc and shadow, which is the disc's own edge: those points
  // are used, weighted by their smaller step.
  const Eigen::Vector2d c{80.41, 70.77};
  const double r = 28.0;
  const auto clean = FindSilhouette(DiscFrame(c, r, 25, 230, CV_8U, 1.5, 9), Ball());
  ASSERT_TRUE(clean.found);
  for (const double shadow_level : {25.0, 40.0}) {
    cv::Mat img = Background(160, 160, 230);
    PaintDisc(img, c, r, 25, 230);
    const auto shadow = [&](double x, double y) {
      const double dx = (x - c.x()) / 22.0, dy = (y - (c.y() + r + 5.0)) / 7.0;
      return dx * dx + dy * dy <= 1 &&
             (x - c.x()) * (x - c.x()) + (y - c.y()) * (y - c.y()) > r * r;
    };
    hoof::testing::Paint(img, shadow, shadow_level - 230, 50, 90, 110, 115);
    const auto obs = FindSilhouette(Quantize(img, CV_8U, 1.5, 9), Ball());
    ASSERT_TRUE(obs.found) << obs.status;
    std::cout << "shadow " << shadow_level << ": error " << (obs.p_I - c).norm() << " px, "
              << obs.edge_points << " edge points (" << obs.edge_points_rejected
              << " rejected), rms " << obs.rms_residual_px << " px; without it "
              << clean.edge_points << " points, rms " << clean.rms_residual_px << " px\n";
    if (shadow_level == 25.0) {
      EXPECT_LT(obs.edge_points, clean.edge_points - 5);
    }
    EXPECT_LT((obs.p_I - c).norm(), 0.05) << obs.p_I.transpose();
    EXPECT_NEAR(obs.diameter_px, 2 * r, 0.2);
  }
}

TEST(SilhouetteTrackerTest, AGlarePatchOnTheBodyIsRejected) {
  // A dark body with a bright glare patch reaching its rim on the upper left.
  const Eigen::Vector2d c{78.8, 81.3};
  const double r = 30.0;
  cv::Mat img = Background(160, 160, 210);
  PaintDisc(img, c, r, 20, 210);
  const Eigen::Vector2d g = c + Eigen::Vector2d(-19, -19);
  const auto glare = [&](double x, double y) {
    return (x - g.x()) * (x - g.x()) + (y - g.y()) * (y - g.y()) <= 64 &&
           (x - c.x()) * (x - c.x()) + (y - c.y()) * (y - c.y()) <= r * r;
  };
  hoof::testing::Paint(img, glare, 250 - 20, 40, 40, 80, 80);
  const auto obs = FindSilhouette(Quantize(img, CV_8U, 1.5, 11), Ball());
  ASSERT_TRUE(obs.found) << obs.status;
  const auto clean = FindSilhouette(DiscFrame(c, r, 20, 210, CV_8U, 1.5, 11), Ball());
  ASSERT_TRUE(clean.found);
  std::cout << "glare: error " << (obs.p_I - c).norm() << " px, " << obs.edge_points
            << " edge points (" << obs.edge_points_rejected << " rejected), without it "
            << clean.edge_points << "\n";
  EXPECT_LT(obs.edge_points, clean.edge_points - 2);
  EXPECT_LT((obs.p_I - c).norm(), 0.05) << obs.p_I.transpose();
}

TEST(SilhouetteTrackerTest, TheReportedUncertaintyMatchesTheScatterOverSeeds) {
  // 200 noisy frames of one disc: the centre's error over its reported s.d., per coordinate,
  // should scatter like a standard normal (mean of squares near 1).
  const Eigen::Vector2d c{80.3, 79.6};
  double sum_z2 = 0, sum_err2 = 0, sum_var = 0;
  const int n = 200;
  for (int s = 0; s < n; ++s) {
    const auto obs = FindSilhouette(DiscFrame(c, 20.0, 180, 60, CV_8U, 12.0, 100 + s), Ball());
    ASSERT_TRUE(obs.found) << s;
    const Eigen::Vector2d e = obs.p_I - c;
    sum_z2 += e.x() * e.x() / obs.cov_p_I(0, 0) + e.y() * e.y() / obs.cov_p_I(1, 1);
    sum_err2 += e.squaredNorm();
    sum_var += obs.cov_p_I.trace();
  }
  const double mean_z2 = sum_z2 / (2 * n);
  std::cout << "rms error " << std::sqrt(sum_err2 / n) << " px, rms reported s.d. "
            << std::sqrt(sum_var / n) << " px, mean z^2 " << mean_z2 << "\n";
  // For 400 standard normal deviates the mean of squares has s.d. 0.07.
  EXPECT_GT(mean_z2, 0.7);
  EXPECT_LT(mean_z2, 1.4);
}

TEST(SilhouetteTrackerTest, AnUnmarkedSpecimensOutlineGivesItsCentroidAndAxis) {
  // A bar with one rounded end (the project's specimen, 16 px wide here), round end down.
  const double w = 16, rect = 40, angle = -std::numbers::pi / 2 + 0.35;  // x_B up and right
  const Eigen::Vector2d E{78.37, 101.82};
  cv::Mat img = Background(160, 160, 25);
  hoof::testing::Paint(img, hoof::testing::RoundedBar(E, angle, w, rect), 200, 0, 0, 159, 159);
  SilhouetteOptions options;
  options.shape = SilhouetteShape::kOutline;
  const auto obs = FindSilhouette(Quantize(img, CV_8U), options);
  ASSERT_TRUE(obs.found) << obs.status;
  ASSERT_TRUE(obs.has_orientation);
  const Eigen::Vector2d x_B{std::cos(angle), std::sin(angle)};
  const Eigen::Vector2d truth = E + hoof::testing::RoundedBarCentroid(w, rect) * x_B;
  EXPECT_LT((obs.p_I - truth).norm(), 0.02) << obs.p_I.transpose() << " vs " << truth.transpose();
  EXPECT_NEAR(obs.angle_I_rad, angle, 1e-3);
}

TEST(SilhouetteTrackerTest, TracksAFallingBallThroughASequence) {
  VectorSource src;
  const auto centre = [](int i) { return Eigen::Vector2d(70.2 + 0.3 * i, 50.4 + 2.64 * i); };
  for (int i = 0; i < 15; ++i)
    src.frames.push_back(DiscFrame(centre(i), 25.0, 300, 3800, CV_16U, 10.0, 20 + i));
  const SilhouetteTrack t = TrackSilhouette(src, Ball());
  ASSERT_EQ(t.frame_count(), 15);
  EXPECT_EQ(t.polarity, Polarity::kDarkOnBright);
  for (int i = 0; i < 15; ++i) {
    ASSERT_TRUE(t.frames[static_cast<std::size_t>(i)].found) << i;
    EXPECT_LT((t.frames[static_cast<std::size_t>(i)].p_I - centre(i)).norm(), 0.05) << i;
  }
}

// Reading ahead on a second thread changes nothing in the track: every field of every frame is
// the same, bit for bit, as when the frames are read on the calling thread, for a ball with a
// bounce (the prediction misses, the window widens) and for frames whose body is lost.
TEST(SilhouetteTrackerTest, ReadingAheadOnASecondThreadGivesTheSameTrack) {
  VectorSource src;
  for (int i = 0; i < 24; ++i) {
    const double y = i < 12 ? 40.0 + 4.0 * i : 84.0 - 3.2 * (i - 11);
    if (i == 17)
      src.frames.push_back(Quantize(Background(160, 160, 3800), CV_16U, 10.0, 60 + i));
    else
      src.frames.push_back(
          DiscFrame(Eigen::Vector2d(60.3 + 1.1 * i, y), 22.0, 300, 3800, CV_16U, 10.0, 60 + i));
  }
  SilhouetteOptions serial = Ball(), ahead = Ball();
  serial.read_ahead_frames = 0;
  ahead.read_ahead_frames = 3;
  const SilhouetteTrack a = TrackSilhouette(src, serial), b = TrackSilhouette(src, ahead);
  ASSERT_EQ(a.frame_count(), 24);
  ASSERT_EQ(b.frame_count(), 24);
  EXPECT_FALSE(a.frames[17].found);
  EXPECT_EQ(a.warnings, b.warnings);
  for (std::size_t i = 0; i < 24; ++i) {
    const auto &x = a.frames[i], &y = b.frames[i];
    EXPECT_EQ(x.found, y.found) << i;
    EXPECT_EQ(x.status, y.status) << i;
    EXPECT_EQ(x.p_I, y.p_I) << i;
    EXPECT_EQ(x.cov_p_I, y.cov_p_I) << i;
    EXPECT_EQ(x.diameter_px, y.diameter_px) << i;
    EXPECT_EQ(x.edge_points, y.edge_points) << i;
    EXPECT_EQ(x.rms_residual_px, y.rms_residual_px) << i;
  }
}

// A ball that leaves the view for 300 frames and one lone frame where it is lost give two
// warnings, each naming its frames, not 301 lines; frames before the ball first appears are
// not warned of.
TEST(SilhouetteTrackerTest, ARunOfFramesWithoutTheBodyIsOneWarning) {
  VectorSource src;
  const auto empty = [](unsigned seed) {
    return Quantize(Background(160, 160, 3800), CV_16U, 10.0, seed);
  };
  const auto ball = [](int i) {
    return DiscFrame(Eigen::Vector2d(60.0 + 0.5 * i, 50.0 + 0.4 * i), 20.0, 300, 3800, CV_16U, 10.0,
                     500u + static_cast<unsigned>(i));
  };
  for (int i = 0; i < 3; ++i) src.frames.push_back(empty(100u + static_cast<unsigned>(i)));
  for (int i = 3; i < 10; ++i) src.frames.push_back(ball(i));
  src.frames.push_back(empty(200));  // frame 10
  for (int i = 11; i < 16; ++i) src.frames.push_back(ball(i));
  for (int i = 16; i < 316; ++i) src.frames.push_back(empty(static_cast<unsigned>(1000 + i)));
  const SilhouetteTrack t = TrackSilhouette(src, Ball());
  ASSERT_EQ(t.frame_count(), 316);
  int found = 0;
  for (const auto& o : t.frames) found += o.found;
  EXPECT_EQ(found, 12);
  ASSERT_EQ(t.warnings.size(), 2u);
  const std::string why = ": the body was not found (" + t.frames[10].status + ")";
  EXPECT_EQ(t.warnings[0], "memory frame 10" + why);
  EXPECT_EQ(t.warnings[1], "memory frame 16 to memory frame 315 (300 frames)" + why);
  for (int i = 16; i < 316; ++i)
    EXPECT_EQ(t.frames[static_cast<std::size_t>(i)].status, t.frames[10].status) << i;
}

// An error reading a frame on the read-ahead thread reaches the caller, with its message.
TEST(SilhouetteTrackerTest, AnErrorReadingAheadIsRethrownToTheCaller) {
  class FailingSource : public VectorSource {
   public:
    cv::Mat Read(int i) override {
      if (i == 5) throw std::runtime_error("memory frame 5 is cut short");
      return VectorSource::Read(i);
    }
  } src;
  for (int i = 0; i < 8; ++i)
    src.frames.push_back(
        DiscFrame(Eigen::Vector2d(70.0, 40.0 + 3.0 * i), 20.0, 300, 3800, CV_16U, 10.0, 80 + i));
  try {
    TrackSilhouette(src, Ball());
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "memory frame 5 is cut short");
  }
}

TEST(SilhouetteTrackerTest, FramesWithoutABodyAreAnErrorNamingTheSource) {
  VectorSource src;
  for (int i = 0; i < 3; ++i) {
    cv::Mat img = Background(120, 120, 100);
    src.frames.push_back(Quantize(img, CV_8U, 2.0, 40 + i));
  }
  try {
    TrackSilhouette(src, Ball());
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("memory frame 0"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no body found"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hoof::tracking
