// The impact measurement on pose sequences made by the simulator (exact free flight and
// contact), with seeded noise of the size the tracker leaves.
#include "kinematics/impact_kinematics.h"

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/frames.h"
#include "dynamics/impact_simulator.h"

namespace hoof::kinematics {
namespace {

struct Sequence {
  std::vector<PoseSample> poses;
  dynamics::ImpactResult truth;
  double touch_s = 0.0;  // first touch since frame 0
};

/// 60 frames at 8000 fps around an impact of the paper's model; pose noise of s.d. `noise_m`
/// on E (x and y) and `noise_rad` on the angle, seeded.
Sequence MakeSequence(dynamics::Surface surface, double phi_deg, double speed, double mu,
                      double touch_fraction, double noise_m, double noise_rad, unsigned seed) {
  dynamics::ContactParameters contact = dynamics::PaperContact(surface);
  contact.mu = mu;
  const dynamics::ImpactSimulator sim(dynamics::SpecimenParameters{}, contact);
  const auto ic = dynamics::ImpactConditions::Paper(speed, phi_deg);
  Sequence s;
  s.touch_s = (29 + touch_fraction) / 8000.0;
  std::vector<double> t;
  for (int i = 0; i < 60; ++i) t.push_back(i / 8000.0 - s.touch_s);
  s.truth = sim.Simulate(ic, t);
  const core::SurfaceRotation S(ic.surface_angle_rad);
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (int i = 0; i < 60; ++i) {
    const auto& smp = s.truth.samples[static_cast<std::size_t>(i)];
    const Eigen::Vector2d p_WE = S.ToW(smp.p_SE);
    PoseSample p;
    p.t_s = i / 8000.0;
    p.valid = true;
    p.p_WE = p_WE + noise_m * Eigen::Vector2d(gauss(rng), gauss(rng));
    p.theta_W_rad = S.AngleToW(smp.body.theta_S_rad) + noise_rad * gauss(rng);
    s.poses.push_back(p);
  }
  return s;
}

// On a level surface nothing drives the body along it: mu_eff is not defined, and it is NaN with
// its s.e. and interval (not the ratio of the tracker's noise in v_x to dv_y), while e is
// measured as on any surface.
TEST(ImpactKinematicsTest, ANormalImpactHasNoEffectiveFriction) {
  const Sequence s = MakeSequence(dynamics::Surface::kSteel, 0, 3.0, 0.12, 0.37, 2e-6, 1e-4, 5);
  const ImpactKinematics k = MeasureImpact(s.poses, 8000, 0, core::SpecimenParameters{});
  ASSERT_TRUE(k.success) << k.message;
  EXPECT_NEAR(k.e, s.truth.e, 5e-3);
  EXPECT_TRUE(std::isnan(k.mu_eff)) << k.mu_eff;
  EXPECT_TRUE(std::isnan(k.mu_eff_se));
  EXPECT_TRUE(std::isnan(k.mu_eff_ci_low));
  EXPECT_TRUE(std::isnan(k.mu_eff_ci_high));
  // At a small angle it is measured.
  const Sequence tilted =
      MakeSequence(dynamics::Surface::kSteel, 5, 3.0, 0.12, 0.37, 2e-6, 1e-4, 5);
  const ImpactKinematics kt = MeasureImpact(tilted.poses, 8000, 5, core::SpecimenParameters{});
  ASSERT_TRUE(kt.success) << kt.message;
  EXPECT_TRUE(std::isfinite(kt.mu_eff));
}

TEST(ImpactKinematicsTest, ExactPosesGiveTheSimulatedImpact) {
  const Sequence s = MakeSequence(dynamics::Surface::kSteel, 20, 3.28, 0.12, 0.37, 0, 0, 1);
  const ImpactKinematics k = MeasureImpact(s.poses, 8000, 20, core::SpecimenParameters{});
  ASSERT_TRUE(k.success) << k.message;
  // Free flight is exactly a parabola, so the fits recover the states at touch/separation,
  // moved to the impact time by gravity alone.
  const double dt_b = k.impact_time_s - s.touch_s;
  const double dt_a = k.impact_time_s - (s.touch_s + s.truth.t_separation_s);
  const Eigen::Vector2d g_S = dynamics::GravityInSurfaceFrame(20 * std::numbers::pi / 180, 9.81);
  EXPECT_NEAR((k.v_SC_before - (s.truth.at_touch.v_SC + g_S * dt_b)).norm(), 0, 1e-9);
  EXPECT_NEAR((k.v_SC_after - (s.truth.at_separation.v_SC + g_S * dt_a)).norm(), 0, 1e-9);
  EXPECT_NEAR(k.w_after_rad_s, s.truth.at_separation.w_rad_s, 1e-7);
  EXPECT_NEAR(k.e, s.truth.e, 2e-4);  // gravity over the contact offsets the two
  EXPECT_NEAR(k.mu_eff, s.truth.mu_eff, 2e-4);
  // The fits meet inside the contact.
  EXPECT_GT(k.impact_time_s, s.touch_s);
  EXPECT_LT(k.impact_time_s, s.touch_s + s.truth.t_separation_s);
  // The paper's 20 frames each side, leaving out frames that may touch the contact.
  EXPECT_EQ(k.before.n, 20);
  EXPECT_EQ(k.after.n, 20);
  EXPECT_LT(k.before.last_frame, 29);
  EXPECT_GT(k.after.first_frame, 30);
}

TEST(ImpactKinematicsTest, StandardErrorsAreCalibrated) {
  // Noise like the tracker's (0.02 px at 0.2 mm/px = 4 um; 2e-4 rad). Over seeded replicates the
  // errors divided by their standard errors should have unit spread.
  std::vector<double> z_v, z_e, z_mu;
  for (unsigned seed = 0; seed < 200; ++seed) {
    const Sequence s =
        MakeSequence(dynamics::Surface::kConcrete, 30, 2.5, 0.3, 0.5, 4e-6, 2e-4, seed);
    const ImpactKinematics k = MeasureImpact(s.poses, 8000, 30, core::SpecimenParameters{});
    ASSERT_TRUE(k.success) << k.message;
    const ImpactKinematics exact = MeasureImpact(
        MakeSequence(dynamics::Surface::kConcrete, 30, 2.5, 0.3, 0.5, 0, 0, seed).poses, 8000, 30,
        core::SpecimenParameters{});
    z_v.push_back((k.v_SC_after.y() - exact.v_SC_after.y()) / k.v_SC_after_se.y());
    z_e.push_back((k.e - exact.e) / k.e_se);
    z_mu.push_back((k.mu_eff - exact.mu_eff) / k.mu_eff_se);
  }
  for (const auto* z : {&z_v, &z_e, &z_mu}) {
    double m = 0, v = 0;
    for (double x : *z) m += x;
    m /= static_cast<double>(z->size());
    for (double x : *z) v += (x - m) * (x - m);
    const double sd = std::sqrt(v / static_cast<double>(z->size() - 1));
    EXPECT_NEAR(m, 0.0, 0.25);
    EXPECT_GT(sd, 0.8);  // 200 draws: s.d. of the sample s.d. is about 0.05
    EXPECT_LT(sd, 1.25);
  }
}

TEST(ImpactKinematicsTest, NoImpactIsReported) {
  Sequence s = MakeSequence(dynamics::Surface::kSteel, 0, 3.0, 0.2, 0.5, 0, 0, 1);
  s.poses.resize(28);  // the sequence ends before the impact
  const ImpactKinematics k = MeasureImpact(s.poses, 8000, 0, core::SpecimenParameters{});
  EXPECT_FALSE(k.success);
  EXPECT_NE(k.message.find("no impact"), std::string::npos) << k.message;
  EXPECT_TRUE(k.no_impact);
}

TEST(ImpactKinematicsTest, TooFewFramesIsNotCalledNoImpact) {
  Sequence s = MakeSequence(dynamics::Surface::kSteel, 0, 3.0, 0.2, 0.5, 0, 0, 1);
  s.poses.resize(8);
  const ImpactKinematics k = MeasureImpact(s.poses, 8000, 0, core::SpecimenParameters{});
  EXPECT_FALSE(k.success);
  EXPECT_FALSE(k.no_impact) << k.message;
}

TEST(ImpactKinematicsTest, SecondBounceIsFlaggedAndLeftOutOfTheFit) {
  // After the rebound, frames 52-55 come down fast onto an obstacle and 56-59 bounce off it.
  Sequence b = MakeSequence(dynamics::Surface::kSteel, 0, 3.0, 0.2, 0.5, 0, 0, 1);
  const double v_up = 2.0, v_down = -2.0;
  for (int i = 52; i < 60; ++i) {
    const double t = (i - 52) / 8000.0;
    const double base = b.poses[52].p_WE.y();
    b.poses[static_cast<std::size_t>(i)].p_WE.y() =
        i < 56 ? base + v_down * t : base + v_down * 4 / 8000.0 + v_up * (t - 4 / 8000.0);
  }
  const ImpactKinematics k2 = MeasureImpact(b.poses, 8000, 0, core::SpecimenParameters{});
  ASSERT_TRUE(k2.success) << k2.message;
  ASSERT_FALSE(k2.flags.empty());
  EXPECT_EQ(k2.flags[0], "second_bounce");
  EXPECT_NE(k2.warnings[0].find("frame 5"), std::string::npos) << k2.warnings[0];
  EXPECT_LT(k2.after.last_frame, 52);
  // The first impact is still measured correctly from the frames before the second.
  EXPECT_NEAR(k2.e, b.truth.e, 5e-4);
}

// A rising flight with one sample off it (the height of frame 50 low by 400 um, so that the
// velocity into it points down and out of it jumps up by 6.4 m/s, more than 0.3 of the impact's
// jump) is a second bounce only where nothing says the positions are that noisy. With their
// stated s.d. of 150 um the jump is 2.2 s.d. of its own noise: no bounce, and the fit after the
// impact keeps its frames.
TEST(ImpactKinematicsTest, ANoisySampleOnTheRiseIsNoSecondBounce) {
  Sequence b = MakeSequence(dynamics::Surface::kSteel, 0, 3.0, 0.2, 0.5, 0, 0, 1);
  b.poses[50].p_WE.y() -= 400e-6;
  const ImpactKinematics unknown = MeasureImpact(b.poses, 8000, 0, core::SpecimenParameters{});
  ASSERT_TRUE(unknown.success) << unknown.message;
  ASSERT_FALSE(unknown.flags.empty());
  EXPECT_EQ(unknown.flags[0], "second_bounce");
  for (auto& p : b.poses) p.cov_p_WE = Eigen::Matrix2d::Identity() * 150e-6 * 150e-6;
  const ImpactKinematics k = MeasureImpact(b.poses, 8000, 0, core::SpecimenParameters{});
  ASSERT_TRUE(k.success) << k.message;
  for (const auto& f : k.flags) EXPECT_NE(f, "second_bounce");
  EXPECT_EQ(k.after.n, KinematicsOptions{}.fit_frames);
  EXPECT_GT(k.after.last_frame, unknown.after.last_frame);
}

TEST(ImpactKinematicsTest, TooFewPosesAreReported) {
  Sequence s = MakeSequence(dynamics::Surface::kSteel, 0, 3.0, 0.2, 0.5, 0, 0, 1);
  for (std::size_t i = 0; i < 60; ++i)
    if (i % 6 != 0) s.poses[i].valid = false;  // markers lost in most frames: 10 poses left
  const ImpactKinematics k = MeasureImpact(s.poses, 8000, 0, core::SpecimenParameters{});
  EXPECT_FALSE(k.success);
  EXPECT_FALSE(k.message.empty());
  EXPECT_THROW(MeasureImpact(s.poses, 0.0, 0, core::SpecimenParameters{}), std::invalid_argument);
}

}  // namespace
}  // namespace hoof::kinematics
