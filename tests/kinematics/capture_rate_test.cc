// The capture rate from gravity (kinematics/capture_rate.h): the closed form (a slow-motion file
// of 240 captures a second stored at 30 fps falls 64 times too slowly), the standard error's
// propagation, and a bouncing ball (tests/support/bouncing_ball.h) captured at 240 fps with its
// times at 30 fps, through the joint arc fit.
#include "kinematics/capture_rate.h"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "kinematics/flight_arcs.h"
#include "support/bouncing_ball.h"

namespace hoof::kinematics {
namespace {

TEST(CaptureRateTest, GravitySixtyFourTimesTooSmallMeansEightTimesTheRate) {
  const CaptureRate r = CaptureRateFromGravity(9.81 / 64, 0.0, 30, 0.0, {.gravity_rel_se = 0});
  ASSERT_TRUE(r.measured) << r.message;
  EXPECT_NEAR(r.ratio, 8.0, 1e-12);
  EXPECT_NEAR(r.capture_fps, 240.0, 1e-9);
  EXPECT_EQ(r.nearest_ratio, 8);
  // The ratio goes as |a|^(-1/2): half the relative s.e. of |a|, the scale's and g's.
  const CaptureRate s = CaptureRateFromGravity(9.81, 0.0981, 25, 0.02, {.gravity_rel_se = 0.01});
  EXPECT_NEAR(s.ratio, 1.0, 1e-12);
  EXPECT_NEAR(s.ratio_se, 0.5 * std::sqrt(0.01 * 0.01 + 0.02 * 0.02 + 0.01 * 0.01), 1e-12);
  EXPECT_NEAR(s.capture_fps_se, 25 * s.ratio_se, 1e-12);
  EXPECT_NEAR(s.nearest_ratio_z, 0.0, 1e-9);
}

TEST(CaptureRateTest, AnAccelerationWithinItsErrorOfZeroIsNotMeasured) {
  const CaptureRate r = CaptureRateFromGravity(0.3, 0.1, 30, 0.0);
  EXPECT_FALSE(r.measured);
  EXPECT_NE(r.message.find("not measured"), std::string::npos) << r.message;
  EXPECT_THROW(CaptureRateFromGravity(9.81, 0.1, 0, 0.0), std::invalid_argument);
  EXPECT_THROW(CaptureRateFromGravity(9.81, -0.1, 30, 0.0), std::invalid_argument);
  EXPECT_THROW(CaptureRateFromGravity(9.81, 0.1, 30, 0.0, {.gravity_m_s2 = 0}),
               std::invalid_argument);
}

// Four bounces captured at 240 fps (1 px noise at 1.5 mm/px), the times those of a 30 fps file:
// the arcs' |a| is g / 64 and the rate 240 within 3 s.e., the whole ratio 8.
TEST(CaptureRateTest, ASlowMotionFileGivesItsCaptureRate) {
  testing::BallClipOptions o;
  o.fps = 240;
  o.frames = 400;
  o.phase_s = 0.0017;
  o.noise_px = 1.0;
  o.e = {0.8, 0.7, 0.75, 0.6};
  testing::BallClip clip = testing::MakeBallClip(o);
  for (std::size_t i = 0; i < clip.poses.size(); ++i)
    clip.poses[i].t_s = static_cast<double>(i) / 30;
  const FlightArcs A = FitFlightArcs(clip.poses, 0.0, 0.0);
  ASSERT_EQ(A.status, ArcFitStatus::kFitted) << A.message;
  EXPECT_GE(A.contacts.size(), 3u);
  const CaptureRate r = CaptureRateFromGravity(A.a_norm, A.a_norm_se, 30, 0.0);
  ASSERT_TRUE(r.measured) << r.message;
  EXPECT_LT(std::abs(r.capture_fps - 240), 3 * r.capture_fps_se);
  EXPECT_LT(r.capture_fps_se, 2.0);
  EXPECT_EQ(r.nearest_ratio, 8);
}

}  // namespace
}  // namespace hoof::kinematics
