// Which method measures a clip's impacts (pipeline/trial_impacts.h), on closed-form bouncing
// balls (tests/support/bouncing_ball.h): the windows where every window fills (their numbers
// exactly as MeasureImpact gives them), the joint arcs where not, or the method asked for.
#include "pipeline/trial_impacts.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "support/bouncing_ball.h"

namespace hoof::pipeline {
namespace {

using kinematics::KinematicsMethod;

core::SpecimenParameters Ball(double radius_m) {
  core::SpecimenParameters b;
  b.d_EC_m = 0;
  b.end_radius_m = radius_m;
  return b;
}

// One bounce at 2000 fps, 150 frames on each side, noise of rendered high-speed frames: every
// window holds its 20 frames, and the result is MeasureImpact's, bit for bit.
TEST(TrialImpactsTest, WindowsWhereEveryWindowFills) {
  testing::BallClipOptions o;
  o.fps = 2000;
  o.frames = 300;
  o.p0_G = {0, 0.033 + 0.5 * 9.81 * 0.075 * 0.075, 0};  // touches 75 ms after the release
  o.release_s = 0.0;                                    // released at frame 0
  o.e = {0.8};
  o.mu = {0};
  o.m_per_px = 2e-4;
  o.noise_px = 0.02;  // a rendered clip's (the windows' second-bounce test needs it small)
  const testing::BallClip clip = testing::MakeBallClip(o);
  ASSERT_EQ(clip.bounces.size(), 1u);
  TrialAnalysis out;
  MeasureTrialImpacts(clip.poses, o.fps, 0.0, Ball(o.radius_m), {}, false, out);
  EXPECT_EQ(out.kinematics_method, KinematicsMethod::kWindows);
  EXPECT_FALSE(out.arcs.has_value());
  ASSERT_TRUE(out.impact.success) << out.impact.message;
  const auto k = kinematics::MeasureImpact(clip.poses, o.fps, 0.0, Ball(o.radius_m));
  EXPECT_EQ(out.impact.e, k.e);
  EXPECT_EQ(out.impact.e_se, k.e_se);
  EXPECT_EQ(out.impact.impact_time_s, k.impact_time_s);
  EXPECT_EQ(out.impact.before.n, 20);
  EXPECT_TRUE(std::isnan(out.impact.w_before_rad_s));  // a ball: w not seen
  // Asked for, the joint arcs measure the same clip, to well within its s.e.
  kinematics::KinematicsOptions arcs;
  arcs.method = KinematicsMethod::kArcs;
  TrialAnalysis a;
  MeasureTrialImpacts(clip.poses, o.fps, 0.0, Ball(o.radius_m), arcs, false, a);
  EXPECT_EQ(a.kinematics_method, KinematicsMethod::kArcs);
  ASSERT_TRUE(a.impact.success) << a.impact.message;
  EXPECT_LT(std::abs(a.impact.e - 0.8), 4 * a.impact.e_se);
  EXPECT_EQ(a.impact.method, KinematicsMethod::kArcs);
}

// Four bounces at 30 fps: the windows cannot fill, the joint arcs measure every bounce; asked
// for, the windows run instead.
TEST(TrialImpactsTest, JointArcsWhereTheWindowsCannotFill) {
  testing::BallClipOptions o;
  o.fps = 30;
  o.frames = 60;
  o.phase_s = 0.013;
  o.noise_px = 0.5;
  o.roll_deg = 6;
  o.e = {0.8, 0.7, 0.75, 0.6};
  const testing::BallClip clip = testing::MakeBallClip(o);
  TrialAnalysis out;
  MeasureTrialImpacts(clip.poses, o.fps, 0.0, Ball(o.radius_m), {}, false, out);
  EXPECT_EQ(out.kinematics_method, KinematicsMethod::kArcs);
  ASSERT_TRUE(out.arcs.has_value());
  ASSERT_TRUE(out.contact_line.has_value());
  EXPECT_TRUE(out.contact_line->measured);
  ASSERT_EQ(out.impacts.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    ASSERT_TRUE(out.impacts[i].success) << out.impacts[i].message;
    EXPECT_LT(std::abs(out.impacts[i].e - o.e[i]), 4 * out.impacts[i].e_se);
  }
  EXPECT_EQ(out.impact.index, 0);
  EXPECT_NE(std::find(out.flags.begin(), out.flags.end(), "several_impacts"), out.flags.end());
  kinematics::KinematicsOptions windows;
  windows.method = KinematicsMethod::kWindows;
  TrialAnalysis w;
  MeasureTrialImpacts(clip.poses, o.fps, 0.0, Ball(o.radius_m), windows, false, w);
  EXPECT_EQ(w.kinematics_method, KinematicsMethod::kWindows);
  EXPECT_FALSE(w.arcs.has_value());
}

// A clip with no bounce (the ball falls out of the frame): neither method finds an impact, and
// the windows' no-impact report is the result.
TEST(TrialImpactsTest, NoImpactKeepsTheWindowsReport) {
  testing::BallClipOptions o;
  o.fps = 30;
  o.frames = 20;
  o.p0_G = {0, 3.0, 0};
  o.noise_px = 0.5;
  const testing::BallClip clip = testing::MakeBallClip(o);
  ASSERT_TRUE(clip.bounces.empty());
  TrialAnalysis out;
  MeasureTrialImpacts(clip.poses, o.fps, 0.0, Ball(o.radius_m), {}, false, out);
  EXPECT_FALSE(out.impact.success);
  EXPECT_TRUE(out.impact.no_impact);
  EXPECT_TRUE(out.impacts.empty());
  EXPECT_EQ(out.kinematics_method, KinematicsMethod::kWindows);
}

}  // namespace
}  // namespace hoof::pipeline
