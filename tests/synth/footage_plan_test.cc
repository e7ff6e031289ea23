// Planning everyday clips (synth/footage_plan.h): the clips without an impact (a throw that
// leaves the view, nothing moving, a hand alone), the scale and gravity's direction, the bounce
// records against the motion, and clips that cannot be drawn refused by field.
#include "synth/footage_plan.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

namespace hoof::synth {
namespace {

FootageSpec Small(FootageScenario scenario) {
  FootageSpec s = DefaultFootageSpec(scenario);
  s.camera.width_px = 320;
  s.camera.height_px = 180;
  return s;
}

TEST(FootagePlanTest, ANeverLandsClipHasNoImpactInView) {
  const FootagePlan plan = PlanFootage(Small(FootageScenario::kNeverLands));
  for (const FootageBounceTruth& b : plan.truth.bounces) EXPECT_FALSE(b.in_view);
  // Seen in flight, then gone for good.
  bool seen = false;
  for (const FootageFrameTruth& f : plan.truth.frames) seen = seen || f.in_view_fraction > 0.5;
  EXPECT_TRUE(seen);
  EXPECT_EQ(plan.truth.frames.back().visibility, BallVisibility::kOutOfView);
  // Thrown slower it lands in view: refused, naming the velocity.
  FootageSpec slow = Small(FootageScenario::kNeverLands);
  slow.launch.v_W_m_s = {0.5, 0.5, 0.0};
  try {
    PlanFootage(slow);
    ADD_FAILURE() << "a never-lands clip that lands in view was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("launch.v_W_m_s"), std::string::npos) << e.what();
  }
}

TEST(FootagePlanTest, StillAndHandOnlyClipsMoveNothingButTheHand) {
  const FootagePlan still = PlanFootage(Small(FootageScenario::kStill));
  EXPECT_TRUE(still.truth.bounces.empty());
  EXPECT_FALSE(still.hand.present());
  for (const FootageFrameTruth& f : still.truth.frames) {
    EXPECT_EQ(f.phase, BallPhase::kRest);
    EXPECT_EQ(f.p_WC_m, still.truth.frames.front().p_WC_m);
    EXPECT_EQ(f.v_WC_m_s.norm(), 0);
    EXPECT_NEAR(f.p_WC_m.y(), still.spec.ball.radius_m, 1e-15);  // on the floor
  }
  const FootagePlan hand = PlanFootage(Small(FootageScenario::kHandOnly));
  EXPECT_TRUE(hand.truth.bounces.empty());
  bool in = false;
  for (const FootageFrameTruth& f : hand.truth.frames) {
    EXPECT_EQ(f.phase, BallPhase::kAbsent);
    EXPECT_EQ(f.visibility, BallVisibility::kAbsent);
    in = in || f.hand_in_view;
  }
  EXPECT_TRUE(in);
  EXPECT_FALSE(hand.truth.frames.back().hand_in_view);  // it has left
}

TEST(FootagePlanTest, ScaleGravityAndBouncesAgreeWithTheGeometry) {
  FootageSpec s = Small(FootageScenario::kBounce);
  s.launch.v_W_m_s = {0.3, 0.0, 0.2};  // sideways and toward the camera
  const FootagePlan plan = PlanFootage(s);
  const FootageTruth& t = plan.truth;
  ASSERT_GE(t.bounces.size(), 3u);
  // The scale at the first bounce: the depth of the ball's centre along the optical axis / f.
  const Eigen::Vector3d c = t.bounces[0].world.p_WC_m;
  const Eigen::Vector3d forward = t.R_CW.row(2).transpose();
  EXPECT_NEAR(t.m_per_px, (c - s.camera.p_W_m).dot(forward) / t.focal_px, 1e-12);
  EXPECT_LT((t.reference_p_W_m - c).norm(), 1e-15);
  // Gravity's image direction: from the centre's image toward the image of a point below it.
  const Eigen::Vector2d down =
      plan.camera.Project(c - Eigen::Vector3d(0, 0.01, 0)) - plan.camera.Project(c);
  EXPECT_LT((down.normalized() - t.gravity_image).norm(), 1e-3);
  // Moving toward the camera the ball looks bigger at each bounce.
  for (std::size_t k = 1; k < t.bounces.size(); ++k)
    EXPECT_GT(t.bounces[k].radius_px, t.bounces[k - 1].radius_px);
  int framed = 0;
  for (const FootageBounceTruth& b : t.bounces) {
    EXPECT_NEAR(b.world.p_WT_m.y(), 0.0, 1e-15);
    EXPECT_NEAR(b.world.e, -b.world.v_after_m_s.y() / b.world.v_before_m_s.y(), 1e-12);
    // The frames around it: the last before shows the ball above, descending.
    if (b.first_frame_after < 0) continue;  // after the last frame
    ++framed;
    ASSERT_GT(b.first_frame_after, 0);
    const FootageFrameTruth& before = t.frames[static_cast<std::size_t>(b.first_frame_after - 1)];
    EXPECT_LT(before.frame.t_s, b.world.t_s);
    EXPECT_LT(before.v_WC_m_s.y(), 0);
    EXPECT_GT(t.frames[static_cast<std::size_t>(b.first_frame_after)].v_WC_m_s.y(),
              before.v_WC_m_s.y());
    // Image velocity: the ball moves down the image before and up after.
    EXPECT_GT(b.v_before_px_s.dot(t.gravity_image), 0);
    EXPECT_LT(b.v_after_px_s.dot(t.gravity_image), 0);
  }
  EXPECT_GE(framed, 3);
}

TEST(FootagePlanTest, ABallThrownIntoTheWallIsRefused) {
  FootageSpec s = Small(FootageScenario::kBounce);
  s.launch.v_W_m_s = {0.0, 0.0, -2.0};
  try {
    PlanFootage(s);
    ADD_FAILURE() << "a ball through the back wall was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("launch.v_W_m_s"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("back wall"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hoof::synth
