#include "tracking/marker_tracker.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "tracking/test_images.h"

namespace hoof::tracking {
namespace {

/// Frames held in memory.
class VectorSource : public FrameSource {
 public:
  std::vector<cv::Mat> frames;
  int count() const override { return static_cast<int>(frames.size()); }
  cv::Mat Read(int i) override { return frames.at(static_cast<std::size_t>(i)); }
  std::string Describe(int i) const override { return "memory frame " + std::to_string(i); }
};

const std::vector<std::pair<std::string, Eigen::Vector2d>> kLayout = {{"M1", {0.006, 0.0}},
                                                                      {"M2", {0.024, 0.0}}};

/// A vertical specimen falling 1.9 px per frame: M1 (near the round end) below M2. At 2e-4
/// m/px the markers are 90 px apart.
std::vector<Eigen::Vector2d> Positions(int i) {
  const double y1 = 200.3 + 1.9 * i, x = 160.6 + 0.05 * i;
  return {{x, y1}, {x, y1 - 90.0}};
}

VectorSource FallingSequence(int n) {
  VectorSource src;
  for (int i = 0; i < n; ++i)
    src.frames.push_back(hoof::testing::DrawDots(320, 320, Positions(i), 7.5, 15, 0.01, i + 1));
  return src;
}

TEST(MarkerTrackerTest, TracksIdentitiesThroughTheSequence) {
  VectorSource src = FallingSequence(12);
  const MarkerTracks t = TrackMarkers(src, kLayout, 2e-4, {0, 1});
  ASSERT_EQ(t.frame_count(), 12);
  EXPECT_EQ(t.names[0], "M1");
  for (int i = 0; i < 12; ++i)
    for (int m = 0; m < 2; ++m) {
      const auto& o = t.frames[static_cast<std::size_t>(i)][static_cast<std::size_t>(m)];
      ASSERT_TRUE(o.found) << i << " " << m;
      EXPECT_LT((o.p_I - Positions(i)[static_cast<std::size_t>(m)]).norm(), 0.05) << i << " " << m;
    }
}

TEST(MarkerTrackerTest, GravityDecidesWhichCollinearMarkerIsWhich) {
  VectorSource src = FallingSequence(3);
  // Gravity pointing up the image: the round end is at the top, so the identities swap.
  const MarkerTracks t = TrackMarkers(src, kLayout, 2e-4, {0, -1});
  EXPECT_LT((t.frames[0][0].p_I - Positions(0)[1]).norm(), 0.05);
}

TEST(MarkerTrackerTest, ALostMarkerIsRecordedNotInvented) {
  VectorSource src = FallingSequence(12);
  // Frame 5: M2's dot is covered (its patch painted over).
  const auto p = Positions(5)[1];
  cv::rectangle(src.frames[5],
                cv::Rect(static_cast<int>(p.x()) - 16, static_cast<int>(p.y()) - 16, 33, 33),
                cv::Scalar(115), cv::FILLED);
  const MarkerTracks t = TrackMarkers(src, kLayout, 2e-4, {0, 1});
  EXPECT_FALSE(t.frames[5][1].found);
  EXPECT_EQ(t.frames[5][1].status, "lost");
  EXPECT_TRUE(t.frames[5][0].found);
  EXPECT_TRUE(t.frames[6][1].found);  // picked up again
  EXPECT_LT((t.frames[6][1].p_I - Positions(6)[1]).norm(), 0.05);
  ASSERT_FALSE(t.warnings.empty());
  EXPECT_NE(t.warnings[0].find("memory frame 5: marker M2"), std::string::npos) << t.warnings[0];
}

TEST(MarkerTrackerTest, AMarkerLostForGoodStaysLost) {
  VectorSource src = FallingSequence(14);
  for (int i = 4; i < 14; ++i) {
    const auto p = Positions(i)[1];
    cv::rectangle(src.frames[static_cast<std::size_t>(i)],
                  cv::Rect(static_cast<int>(p.x()) - 16, static_cast<int>(p.y()) - 16, 33, 33),
                  cv::Scalar(115), cv::FILLED);
  }
  TrackerOptions o;
  o.max_consecutive_misses = 3;
  const MarkerTracks t = TrackMarkers(src, kLayout, 2e-4, {0, 1}, o);
  EXPECT_EQ(t.frames[13][1].status, "lost_for_good");
  EXPECT_FALSE(t.frames[13][1].found);
  EXPECT_TRUE(t.frames[13][0].found);
}

TEST(MarkerTrackerTest, NoMarkersOrAWrongLayoutAreErrors) {
  VectorSource blank;
  blank.frames.assign(3, cv::Mat(240, 320, CV_8U, cv::Scalar(60)));
  try {
    TrackMarkers(blank, kLayout, 2e-4, {0, 1});
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("memory frame 0: found 0 marker(s)"), std::string::npos)
        << e.what();
  }
  VectorSource src = FallingSequence(3);
  // The layout says the markers are 36 mm apart; the image shows 18 mm.
  const std::vector<std::pair<std::string, Eigen::Vector2d>> wrong = {{"M1", {0.006, 0.0}},
                                                                      {"M2", {0.042, 0.0}}};
  try {
    TrackMarkers(src, wrong, 2e-4, {0, 1});
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("layout does not match"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hoof::tracking
