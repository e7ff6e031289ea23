// The everyday ball's motion (synth/ball_flight.h) against closed forms and conservation laws:
// apex heights fall by e^2 per bounce, contact times follow the flight-time recursion, the
// tangential impulse obeys Coulomb's bound and ends in rolling when it says so, angular momentum
// about the contact point is conserved through each impact, and energy never rises.
#include "synth/ball_flight.h"

#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

namespace hoof::synth {
namespace {

/// A ball dropped from rest (no hand carry) with the given restitution spread.
BallPath Drop(double e_mean, double e_sd, double h0, double end_s, std::uint64_t seed = 3) {
  BallOptions ball;
  LaunchOptions launch;
  launch.drop_height_m = h0;
  launch.release_time_s = 0.2;
  BounceOptions bounce;
  bounce.e_mean = e_mean;
  bounce.e_sd = e_sd;
  bounce.min_rebound_height_m = 1e-5;
  return PlanBallPath(FootageScenario::kBounce, ball, launch, bounce, end_s, seed);
}

/// Height of the ball's lowest point at the apex of the flight after bounce k.
double ApexAfter(const BallPath& p, std::size_t k) {
  const BallBounce& b = p.bounces[k];
  const double t_apex = b.t_s + b.v_after_m_s.y() / p.g_m_s2;
  return p.At(t_apex).p_WC_m.y() - p.radius_m;
}

TEST(BallFlightTest, ApexHeightsFallByESquaredPerBounce) {
  const double h0 = 0.45, e = 0.8;
  const BallPath p = Drop(e, 0.0, h0, 3.0);
  ASSERT_GE(p.bounces.size(), 6u);
  for (std::size_t k = 0; k < 6; ++k)
    EXPECT_NEAR(ApexAfter(p, k), h0 * std::pow(e, 2.0 * static_cast<double>(k + 1)), 1e-12) << k;
  // With e drawn per bounce, each apex is the one before times that bounce's e^2.
  const BallPath q = Drop(0.75, 0.05, h0, 3.0);
  double h = h0;
  for (std::size_t k = 0; k < 5; ++k) {
    h *= q.bounces[k].e * q.bounces[k].e;
    EXPECT_NEAR(ApexAfter(q, k), h, 1e-12) << k;
  }
}

TEST(BallFlightTest, BounceTimesFollowTheFlightTimeRecursion) {
  const double h0 = 0.6, g = 9.81;
  const BallPath p = Drop(0.75, 0.03, h0, 3.0, 11);
  ASSERT_GE(p.bounces.size(), 5u);
  double t = 0.2 + std::sqrt(2 * h0 / g);  // the drop
  double v = std::sqrt(2 * g * h0);        // speed at the first touch
  for (std::size_t k = 0; k < 5; ++k) {
    EXPECT_NEAR(p.bounces[k].t_s, t, 1e-12) << k;
    EXPECT_NEAR(-p.bounces[k].v_before_m_s.y(), v, 1e-9) << k;
    v *= p.bounces[k].e;
    t += 2 * v / g;  // up and down again at the rebound speed
  }
  // The e drawn differ and stay near their mean.
  EXPECT_NE(p.bounces[0].e, p.bounces[1].e);
  for (const BallBounce& b : p.bounces) EXPECT_NEAR(b.e, 0.75, 0.15);
}

TEST(BallFlightTest, SphereImpactOfTheTextbook) {
  // A sphere without spin striking with tangential speed u: if friction suffices it leaves
  // rolling with v_t = u / (1 + k) (5/7 u solid, 3/5 u hollow), w = v_t / r.
  for (const BallInertia kind : {BallInertia::kSolid, BallInertia::kHollow}) {
    const double k = InertiaFactor(kind), r = 0.03;
    const SphereImpact s = ResolveSphereImpact({1.0, -2.0, 0.0}, {0, 0, 0}, r, k, 0.7, 1.0);
    EXPECT_TRUE(s.rolling);
    EXPECT_NEAR(s.v_after_m_s.x(), 1.0 / (1 + k), 1e-14);
    EXPECT_NEAR(s.v_after_m_s.y(), 1.4, 1e-14);
    EXPECT_NEAR(s.w_after_rad_s.z(), -s.v_after_m_s.x() / r, 1e-12);  // rolls toward +x
    EXPECT_NEAR(s.mu_eff, (1 - 1 / (1 + k)) / 3.4, 1e-14);
  }
  // Too little friction: it slides throughout, |dv_t| = mu |dv_n| exactly.
  const SphereImpact s = ResolveSphereImpact({1.0, -2.0, 0.0}, {0, 0, 0}, 0.03, 0.4, 0.7, 0.05);
  EXPECT_FALSE(s.rolling);
  EXPECT_NEAR(1.0 - s.v_after_m_s.x(), 0.05 * 3.4, 1e-14);
  EXPECT_NEAR(s.mu_eff, 0.05, 1e-14);
}

TEST(BallFlightTest, ImpactsObeyCoulombAndConserveAngularMomentumAboutTheContact) {
  cv::RNG rng(20240601);
  int rolled = 0, slid = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const double r = rng.uniform(0.01, 0.1), k = rng.uniform(0, 2) ? 0.4 : 2.0 / 3.0;
    const double e = rng.uniform(0.1, 0.95), mu = rng.uniform(0.0, 1.2);
    const Eigen::Vector3d v{rng.uniform(-3.0, 3.0), -rng.uniform(0.2, 5.0), rng.uniform(-3.0, 3.0)};
    const Eigen::Vector3d w{rng.uniform(-80.0, 80.0), rng.uniform(-80.0, 80.0),
                            rng.uniform(-80.0, 80.0)};
    const SphereImpact s = ResolveSphereImpact(v, w, r, k, e, mu);
    const Eigen::Vector3d n = Eigen::Vector3d::UnitY(), arm = r * n;  // contact -> centre
    const Eigen::Vector3d dv = s.v_after_m_s - v;
    const double dvn = dv.dot(n);
    const Eigen::Vector3d dvt = dv - dvn * n;
    EXPECT_NEAR(s.v_after_m_s.y(), -e * v.y(), 1e-12);
    EXPECT_LE(dvt.norm(), mu * std::abs(dvn) + 1e-12);
    EXPECT_NEAR(s.mu_eff, dvt.norm() / std::abs(dvn), 1e-12);
    // Per unit mass: L_T = arm x v + k r^2 w, unchanged (the impulse acts at T).
    const Eigen::Vector3d before = arm.cross(v) + k * r * r * w;
    const Eigen::Vector3d after = arm.cross(s.v_after_m_s) + k * r * r * s.w_after_rad_s;
    EXPECT_LT((after - before).norm(), 1e-12 * (1 + before.norm()));
    // Energy never rises.
    const double E0 = v.squaredNorm() + k * r * r * w.squaredNorm();
    const double E1 = s.v_after_m_s.squaredNorm() + k * r * r * s.w_after_rad_s.squaredNorm();
    EXPECT_LE(E1, E0 + 1e-12);
    const Eigen::Vector3d slip_before = v - v.dot(n) * n + w.cross(-arm);
    const Eigen::Vector3d slip_after =
        s.v_after_m_s - s.v_after_m_s.dot(n) * n + s.w_after_rad_s.cross(-arm);
    if (s.rolling) {
      ++rolled;
      EXPECT_LT(slip_after.norm(), 1e-12 * (1 + slip_before.norm()));
    } else {
      ++slid;
      EXPECT_NEAR(dvt.norm(), mu * std::abs(dvn), 1e-12);
      EXPECT_GT(slip_after.dot(slip_before), 0);  // slowed, never reversed
    }
  }
  EXPECT_GT(rolled, 20);
  EXPECT_GT(slid, 20);
}

TEST(BallFlightTest, AThrownSpinningBallSlidesThenRollsOnceTheBouncingEnds) {
  BallOptions ball;
  LaunchOptions launch;
  launch.drop_height_m = 0.3;
  launch.v_W_m_s = {0.8, 0.0, -0.2};
  launch.w_W_rad_s = {0.0, 5.0, 60.0};
  BounceOptions bounce;
  bounce.e_mean = 0.6;
  bounce.e_sd = 0;
  bounce.mu = 0.05;
  bounce.min_rebound_height_m = 0.05;  // one bounce (0.11 m high), then the next one ends it
  const BallPath p = PlanBallPath(FootageScenario::kBounce, ball, launch, bounce, 5.0, 1);
  ASSERT_EQ(p.bounces.size(), 1u);
  ASSERT_TRUE(std::isfinite(p.settle_time_s));
  ASSERT_GT(p.rolling_time_s, p.settle_time_s);
  const double r = p.radius_m, k = p.inertia_factor;
  // Sliding: the slip falls at mu g (1 + 1/k) and ends exactly at rolling_time_s.
  const auto slip = [&](double t) {
    const BallState s = p.At(t);
    return Eigen::Vector3d(s.v_WC_m_s + s.w_W_rad_s.cross(Eigen::Vector3d(0, -r, 0)));
  };
  const double t0 = p.settle_time_s + 1e-9;
  const double expected = slip(t0).norm() / (bounce.mu * bounce.g_m_s2 * (1 + 1 / k));
  EXPECT_NEAR(p.rolling_time_s - p.settle_time_s, expected, 1e-8);
  EXPECT_LT(slip(p.rolling_time_s + 0.1).norm(), 1e-9);
  EXPECT_EQ(p.At(p.rolling_time_s + 0.1).phase, BallPhase::kRolling);
  EXPECT_NEAR(p.At(p.rolling_time_s + 0.1).p_WC_m.y(), r, 1e-12);
  // Spin about the vertical has no torque at a point contact: it survives the sliding.
  EXPECT_NEAR(p.At(p.rolling_time_s + 0.1).w_W_rad_s.y(), p.At(t0).w_W_rad_s.y(), 1e-9);
  // Each bounce of the clip obeys the bound on the impulse ratio.
  for (const BallBounce& b : p.bounces) EXPECT_LE(b.mu_eff, bounce.mu + 1e-12);
}

TEST(BallFlightTest, HeldStillThenCarriedThenReleased) {
  BallOptions ball;
  LaunchOptions launch;
  launch.v_W_m_s = {1.0, 2.0, 0.0};
  launch.throw_duration_s = 0.1;
  launch.release_time_s = 0.5;
  const BallPath p = PlanBallPath(FootageScenario::kBounce, ball, launch, BounceOptions{}, 3, 1);
  const Eigen::Vector3d release{0, launch.drop_height_m + ball.radius_m, 0};
  EXPECT_EQ(p.At(0.1).phase, BallPhase::kHeld);
  EXPECT_LT((p.At(0.1).p_WC_m - p.At(0.39).p_WC_m).norm(), 1e-15);  // still in the hand
  EXPECT_LT((p.At(0.45).p_WC_m - (release - 0.05 * launch.v_W_m_s)).norm(), 1e-12);  // carried
  EXPECT_LT((p.At(0.5).p_WC_m - release).norm(), 1e-12);
  EXPECT_EQ(p.At(0.5).phase, BallPhase::kFlight);
  const double s = 0.1;
  const Eigen::Vector3d ballistic =
      release + launch.v_W_m_s * s + Eigen::Vector3d(0, -0.5 * 9.81 * s * s, 0);
  EXPECT_LT((p.At(0.5 + s).p_WC_m - ballistic).norm(), 1e-12);
}

}  // namespace
}  // namespace hoof::synth
