// The scale from gravity (kinematics/gravity_scale.h) on bouncing paths written here in closed
// form: free flight is p0 + v t + a t^2 / 2 with a = g / m_per_px, each bounce reverses the
// velocity along gravity (times e) between two frames. Seeded Gaussian noise on the positions.
#include "kinematics/gravity_scale.h"

#include <cmath>
#include <optional>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace hoof::kinematics {
namespace {

constexpr double kG = 9.81;

struct Path {
  std::vector<std::optional<Eigen::Vector2d>> p_px;
  int bounces = 0;
};

/// A ball dropped at `v_down_px_s` from y = 0 in an image with gravity along `g_dir` (unit),
/// bouncing with restitution `e` off a floor `floor_px` down along g_dir, at `fps` for
/// `frames` frames; sideways drift `v_side_px_s`. Exact: the flight between bounces is solved
/// in closed form, the bounce instantaneous.
Path Bouncing(double m_per_px, double fps, int frames, double floor_px, double v_down_px_s,
              double v_side_px_s, double e, const Eigen::Vector2d& g_dir, double noise_px,
              unsigned seed) {
  const double a = kG / m_per_px;
  const Eigen::Vector2d side(-g_dir.y(), g_dir.x());
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, noise_px);
  Path out;
  double s0 = 0, v0 = v_down_px_s, t0 = 0;  // along g_dir, since the last bounce
  for (int f = 0; f < frames; ++f) {
    const double t = f / fps;
    double s = s0 + v0 * (t - t0) + 0.5 * a * (t - t0) * (t - t0);
    if (s > floor_px) {  // the bounce: where the flight reaches the floor
      const double dt = (-v0 + std::sqrt(v0 * v0 + 2 * a * (floor_px - s0))) / a;
      const double v_hit = v0 + a * dt;
      t0 += dt;
      s0 = floor_px;
      v0 = -e * v_hit;
      s = s0 + v0 * (t - t0) + 0.5 * a * (t - t0) * (t - t0);
      ++out.bounces;
    }
    const Eigen::Vector2d p = s * g_dir + v_side_px_s * t * side + Eigen::Vector2d(n(rng), n(rng));
    out.p_px.emplace_back(p);
  }
  return out;
}

TEST(GravityScaleTest, ANoiseFreeBouncingPathGivesTheScaleExactly) {
  const double m_per_px = 2e-4;  // a = 49050 px/s^2
  const auto path = Bouncing(m_per_px, 1000, 200, 120, 800, 30, 0.8, Eigen::Vector2d(0, 1), 0.0, 1);
  ASSERT_EQ(path.bounces, 2);
  const GravityScale g = EstimateGravityScale(path.p_px, 1000, Eigen::Vector2d(0, 1));
  ASSERT_TRUE(g.measured) << g.message;
  EXPECT_EQ(g.arcs.size(), 3u);
  EXPECT_NEAR(g.m_per_px, m_per_px, 1e-9 * m_per_px);
  EXPECT_NEAR(g.a_px_s2.x(), 0.0, 1e-6);
  EXPECT_NEAR(g.direction_error_deg, 0.0, 1e-6);
}

// The joint flight arcs' scale: a phone's 30 fps with several short bounces, exact without
// noise; with 0.3 px of noise within three of its standard errors of the truth.
TEST(GravityScaleTest, TheJointArcsGiveTheScaleOfAPathOfShortBounces) {
  const double m_per_px = 8e-4;  // a = 12262.5 px/s^2
  const auto exact = Bouncing(m_per_px, 30, 60, 400, 0, 40, 0.75, Eigen::Vector2d(0, 1), 0.0, 1);
  ASSERT_GE(exact.bounces, 4);
  const GravityScale g = GravityScaleFromArcs(exact.p_px, 30);
  ASSERT_TRUE(g.measured) << g.message;
  EXPECT_NEAR(g.m_per_px, m_per_px, 1e-6 * m_per_px);
  const auto noisy = Bouncing(m_per_px, 30, 60, 400, 0, 40, 0.75, Eigen::Vector2d(0, 1), 0.3, 2);
  const GravityScale n = GravityScaleFromArcs(noisy.p_px, 30);
  ASSERT_TRUE(n.measured) << n.message;
  EXPECT_GT(n.m_per_px_se, 0.0);
  EXPECT_NEAR(n.m_per_px, m_per_px, 3 * n.m_per_px_se);
  EXPECT_LT(n.m_per_px_se, 0.01 * m_per_px);
}

TEST(GravityScaleTest, ARolledCameraDoesNotBiasTheScaleAndItsRollIsMeasured) {
  const double m_per_px = 1e-4, roll = 5.0 * M_PI / 180;
  const Eigen::Vector2d g_true(-std::sin(roll), std::cos(roll));
  const auto path = Bouncing(m_per_px, 2000, 200, 150, 1500, 0, 0.7, g_true, 0.0, 2);
  ASSERT_GE(path.bounces, 1);
  // The stated gravity direction is the level camera's; the fit finds the acceleration's own.
  const GravityScale g = EstimateGravityScale(path.p_px, 2000, Eigen::Vector2d(0, 1));
  ASSERT_TRUE(g.measured) << g.message;
  EXPECT_NEAR(g.m_per_px, m_per_px, 1e-9 * m_per_px);
  EXPECT_NEAR(g.direction_error_deg, 5.0, 1e-6);
}

// The stated standard error is the error's spread: over 400 seeds, the mean of the squared
// standardized errors is 1 within its sampling error (s.d. sqrt(2 / 400) = 0.07), and the
// scale is within 1 % of the truth at 1000 fps with tracker-size noise (0.03 px).
TEST(GravityScaleTest, ItsStandardErrorMatchesItsScatterOverSeeds) {
  const double m_per_px = 2e-4;
  double sum_z2 = 0, worst = 0;
  const int seeds = 400;
  for (int seed = 0; seed < seeds; ++seed) {
    const auto path =
        Bouncing(m_per_px, 1000, 70, 100, 900, 10, 0.8, Eigen::Vector2d(0, 1), 0.03, seed + 10u);
    const GravityScale g = EstimateGravityScale(path.p_px, 1000, Eigen::Vector2d(0, 1));
    ASSERT_TRUE(g.measured) << g.message;
    ASSERT_EQ(g.arcs.size(), static_cast<std::size_t>(path.bounces) + 1) << "seed " << seed;
    const double z = (g.m_per_px - m_per_px) / g.m_per_px_se;
    sum_z2 += z * z;
    worst = std::max(worst, std::abs(g.m_per_px / m_per_px - 1));
  }
  EXPECT_NEAR(sum_z2 / seeds, 1.0, 0.21);
  EXPECT_LT(worst, 0.01);
}

TEST(GravityScaleTest, AFlightTooShortToCurveIsNotMeasuredAndSaysWhy) {
  // 15 frames at 30,000 fps, 19.7 um/px (the real ball clip's): gravity bends the path by
  // 0.013 px, below noise of 0.03 px.
  const auto path =
      Bouncing(19.7e-6, 30000, 15, 1e9, 2.64 * 30000, 0, 0.8, Eigen::Vector2d(0, 1), 0.03, 3);
  const GravityScale g = EstimateGravityScale(path.p_px, 30000, Eigen::Vector2d(0, 1));
  EXPECT_FALSE(g.measured);
  EXPECT_NE(g.message.find("not measured"), std::string::npos) << g.message;
  const GravityScale none = EstimateGravityScale({}, 1000, Eigen::Vector2d(0, 1));
  EXPECT_FALSE(none.measured);
  EXPECT_NE(none.message.find("free-flight arc"), std::string::npos) << none.message;
  EXPECT_THROW(EstimateGravityScale(path.p_px, 0, Eigen::Vector2d(0, 1)), std::invalid_argument);
}

TEST(GravityScaleTest, MissingFramesAreSkipped) {
  const double m_per_px = 2e-4;
  auto path = Bouncing(m_per_px, 1000, 100, 100, 900, 0, 0.8, Eigen::Vector2d(0, 1), 0.0, 4);
  for (int f : {3, 17, 40, 41, 77}) path.p_px[static_cast<std::size_t>(f)].reset();
  const GravityScale g = EstimateGravityScale(path.p_px, 1000, Eigen::Vector2d(0, 1));
  ASSERT_TRUE(g.measured) << g.message;
  EXPECT_NEAR(g.m_per_px, m_per_px, 1e-9 * m_per_px);
}

// The scale's relative s.e. r enters each velocity component as the fully correlated r v:
// se^2 = se_fit^2 + (r v)^2 on a level surface (S = W); e and mu_eff are left alone, and the
// kinetic energy's s.e. is m |v| times the velocity's along v (no spin here).
TEST(GravityScaleTest, TheScalesErrorEntersTheVelocitiesAndEnergiesNotE) {
  ImpactKinematics k;
  k.before.v_WC = {0.3, -2.0};
  k.after.v_WC = {0.2, 1.6};
  k.before.cov_v_WC = Eigen::Vector2d(1e-4, 4e-4).asDiagonal();
  k.after.cov_v_WC = Eigen::Vector2d(1e-4, 9e-4).asDiagonal();
  k.e = 0.8;
  k.e_se = 0.01;
  core::SpecimenParameters body;
  body.mass_kg = 0.008;
  body.inertia_kg_m2 = 1e-6;
  AddScaleUncertainty(0.02, 0.0, body, k);
  EXPECT_NEAR(k.v_SC_before_se.x(), std::hypot(0.01, 0.02 * 0.3), 1e-12);
  EXPECT_NEAR(k.v_SC_before_se.y(), std::hypot(0.02, 0.02 * 2.0), 1e-12);
  EXPECT_NEAR(k.v_SC_after_se.y(), std::hypot(0.03, 0.02 * 1.6), 1e-12);
  EXPECT_EQ(k.e, 0.8);
  EXPECT_EQ(k.e_se, 0.01);
  // Var(KE) = m^2 v^T C v with C = C_fit + r^2 v v^T.
  const Eigen::Vector2d v = k.after.v_WC;
  const double var =
      0.008 * 0.008 * (1e-4 * 0.04 + 9e-4 * 2.56 + 0.0004 * std::pow(v.squaredNorm(), 2));
  EXPECT_NEAR(k.kinetic_energy_after_se_J, std::sqrt(var), 1e-12);
}

}  // namespace
}  // namespace hoof::kinematics
