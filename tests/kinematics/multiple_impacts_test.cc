// Several impacts in one clip (MeasureImpacts) on closed-form pose sequences: a body that does
// not turn flies on exact parabolas between instantaneous impacts, each with its own e and
// mu_eff, so every impact's time and velocities are known exactly.
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/frames.h"
#include "kinematics/impact_kinematics.h"

namespace hoof::kinematics {
namespace {

constexpr double kG = core::kStandardGravity_m_s2;

/// One impact of the closed form: its touch time, and the velocity of C in S before and after.
struct TrueImpact {
  double t_s = 0;
  Eigen::Vector2d v_before_S{0, 0}, v_after_S{0, 0};
  double e = 0, mu_eff = 0;
};

struct Bounces {
  std::vector<PoseSample> poses;
  std::vector<TrueImpact> impacts;
};

/// A body (the default specimen, x_B along the surface normal, not turning) whose round end
/// touches a surface at `phi_deg` first at `t_first_s` with C's velocity `v0_S` in S, then
/// flies and bounces: at impact k the normal velocity reverses times e[k] and the tangential one
/// loses mu[k] times the change of the normal one (against its direction). Frames at `fps` from
/// t = 0 to the apex after the last impact; E's position has seeded Gaussian noise `noise_m`.
Bounces MakeBounces(double phi_deg, Eigen::Vector2d v0_S, const std::vector<double>& e,
                    const std::vector<double>& mu, double fps, double t_first_s, double noise_m,
                    unsigned seed) {
  const core::SpecimenParameters body;
  const core::SurfaceRotation S = core::SurfaceRotation::FromDegrees(phi_deg);
  const Eigen::Vector2d g_S = S.GravityInS(kG);
  // E in S at each touch: R above the surface line, moving along it.
  struct Segment {
    double t0;
    Eigen::Vector2d p0_S, v0_S;
  };
  std::vector<Segment> seg;
  Bounces b;
  Eigen::Vector2d p_S{0, body.end_radius_m}, v_S = v0_S;
  double t = t_first_s;
  seg.push_back({t, p_S, v_S});  // the approach, back in time from the first touch
  for (std::size_t k = 0; k < e.size(); ++k) {
    TrueImpact imp;
    imp.t_s = t;
    imp.v_before_S = v_S;
    const double dvy = -(1 + e[k]) * v_S.y();
    imp.v_after_S = {v_S.x() - mu[k] * dvy * (v_S.x() > 0 ? 1 : -1), -e[k] * v_S.y()};
    imp.e = e[k];
    imp.mu_eff = std::abs((imp.v_after_S.x() - v_S.x()) / dvy);
    b.impacts.push_back(imp);
    v_S = imp.v_after_S;
    seg.push_back({t, p_S, v_S});
    const double flight = -2 * v_S.y() / g_S.y();  // back to the surface
    p_S += v_S * flight + 0.5 * g_S * flight * flight;
    v_S += g_S * flight;
    t += flight;
  }
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const double theta_W = S.AngleToW(std::numbers::pi / 2);
  for (int i = 0; i / fps < t; ++i) {
    const double ti = i / fps;
    std::size_t s = 0;
    while (s + 1 < seg.size() && seg[s + 1].t0 <= ti) ++s;
    const double dt = ti - seg[s].t0;
    const Eigen::Vector2d pe_S = seg[s].p0_S + seg[s].v0_S * dt + 0.5 * g_S * dt * dt;
    PoseSample p;
    p.t_s = ti;
    p.valid = true;
    p.p_WE = S.ToW(pe_S) + noise_m * Eigen::Vector2d(gauss(rng), gauss(rng));
    p.theta_W_rad = theta_W;
    b.poses.push_back(p);
  }
  return b;
}

// Exact poses: every impact is found, at its time, with its e and, on an oblique surface, its
// mu_eff; on a level one mu_eff is NaN as for a single impact.
TEST(MultipleImpactsTest, EveryImpactOfExactArcsIsFoundAndMeasured) {
  const std::vector<double> e{0.8, 0.55, 0.7}, mu{0.15, 0.3, 0.1};
  for (double phi : {0.0, 20.0, 40.0}) {
    SCOPED_TRACE("phi " + std::to_string(phi));
    const Eigen::Vector2d v0 = phi == 0.0 ? Eigen::Vector2d(0, -3) : Eigen::Vector2d(-1.0, -3);
    const Bounces b =
        MakeBounces(phi, v0, e, phi == 0.0 ? std::vector<double>{0, 0, 0} : mu, 1000, 0.0304, 0, 1);
    const auto k = MeasureImpacts(b.poses, 1000, phi, core::SpecimenParameters{});
    ASSERT_EQ(k.size(), 3u);
    for (std::size_t i = 0; i < 3; ++i) {
      SCOPED_TRACE("impact " + std::to_string(i));
      ASSERT_TRUE(k[i].success) << k[i].message;
      EXPECT_EQ(k[i].index, static_cast<int>(i));
      const auto& truth = b.impacts[i];
      EXPECT_NEAR(k[i].impact_time_s, truth.t_s, 1e-9);
      EXPECT_EQ(k[i].impact_frame, static_cast<int>(std::floor(truth.t_s * 1000)));
      EXPECT_LE(std::abs(k[i].lowest_frame - truth.t_s * 1000), 1.0);
      EXPECT_NEAR((k[i].v_SC_before - truth.v_before_S).norm(), 0, 1e-8);
      EXPECT_NEAR((k[i].v_SC_after - truth.v_after_S).norm(), 0, 1e-8);
      EXPECT_NEAR(k[i].e, truth.e, 1e-8);
      EXPECT_NEAR(k[i].w_before_rad_s, 0, 1e-8);
      if (phi == 0.0) {
        EXPECT_TRUE(std::isnan(k[i].mu_eff));
      } else {
        EXPECT_NEAR(k[i].mu_eff, truth.mu_eff, 1e-8);
      }
      // 20 frames each side, none of them reaching into a contact.
      EXPECT_EQ(k[i].before.n, 20);
      EXPECT_EQ(k[i].after.n, 20);
      EXPECT_LT(k[i].before.last_frame / 1000.0, truth.t_s);
      EXPECT_GT(k[i].after.first_frame / 1000.0, truth.t_s);
      if (i > 0) {
        EXPECT_GT(k[i].before.first_frame / 1000.0, b.impacts[i - 1].t_s);
      }
    }
  }
}

// With the tracker's kind of noise (20 um at 1000 fps) the impacts are still found, no more and
// no fewer, and each e lies within 4 of its own standard errors of the truth.
TEST(MultipleImpactsTest, NoisyArcsGiveEachImpactWithinItsStandardError) {
  const std::vector<double> e{0.75, 0.6, 0.8, 0.7}, mu{0.2, 0.1, 0.25, 0.15};
  for (unsigned seed = 1; seed <= 5; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const Bounces b = MakeBounces(30, {0.5, -3.5}, e, mu, 1000, 0.0253, 20e-6, seed);
    const auto k = MeasureImpacts(b.poses, 1000, 30, core::SpecimenParameters{});
    ASSERT_EQ(k.size(), 4u);
    for (std::size_t i = 0; i < k.size(); ++i) {
      SCOPED_TRACE("impact " + std::to_string(i));
      ASSERT_TRUE(k[i].success) << k[i].message;
      EXPECT_GT(k[i].e_se, 0);
      EXPECT_LT(std::abs(k[i].e - e[i]), 4 * k[i].e_se) << k[i].e << " +- " << k[i].e_se;
      EXPECT_LT(std::abs(k[i].mu_eff - mu[i]), 4 * k[i].mu_eff_se);
      EXPECT_LT(k[i].e_ci_low, e[i]);
      EXPECT_GT(k[i].e_ci_high, e[i]);
      EXPECT_NEAR(k[i].impact_time_s, b.impacts[i].t_s, 0.2e-3);
    }
  }
}

// A clip with one impact: MeasureImpacts gives MeasureImpact's numbers exactly.
TEST(MultipleImpactsTest, OneImpactIsMeasureImpactBitForBit) {
  for (double phi : {0.0, 25.0}) {
    const Bounces b = MakeBounces(phi, {-0.8, -2.5}, {0.65}, {0.2}, 8000, 0.004, 4e-6, 7);
    const auto all = MeasureImpacts(b.poses, 8000, phi, core::SpecimenParameters{});
    const ImpactKinematics one = MeasureImpact(b.poses, 8000, phi, core::SpecimenParameters{});
    ASSERT_EQ(all.size(), 1u);
    ASSERT_TRUE(one.success) << one.message;
    const ImpactKinematics& k = all[0];
    ASSERT_TRUE(k.success) << k.message;
    EXPECT_EQ(k.lowest_frame, one.lowest_frame);
    EXPECT_EQ(k.impact_time_s, one.impact_time_s);
    EXPECT_EQ(k.impact_frame, one.impact_frame);
    EXPECT_EQ(k.before.first_frame, one.before.first_frame);
    EXPECT_EQ(k.after.last_frame, one.after.last_frame);
    EXPECT_EQ(k.v_SC_before, one.v_SC_before);
    EXPECT_EQ(k.v_SC_after, one.v_SC_after);
    EXPECT_EQ(k.v_SC_after_se, one.v_SC_after_se);
    EXPECT_EQ(k.w_after_rad_s, one.w_after_rad_s);
    EXPECT_EQ(k.e, one.e);
    EXPECT_EQ(k.e_se, one.e_se);
    EXPECT_EQ(k.e_ci_low, one.e_ci_low);
    if (phi != 0.0) {
      EXPECT_EQ(k.mu_eff, one.mu_eff);
      EXPECT_EQ(k.mu_eff_se, one.mu_eff_se);
    }
  }
}

// At 100 fps a weak second bounce leaves an arc of a few frames: the impacts on each side of it
// are found and reported unmeasured with the reason, not dropped; the first is still measured.
TEST(MultipleImpactsTest, AnArcTooShortToFitIsReportedNotDropped) {
  // After impact 1 (e 0.1) the body rises at 0.24 m/s: 49 ms of flight, 4 or 5 frames at
  // 100 fps (and after impact 2, 44 ms to the clip's end), fewer than min_fit_frames (6).
  const Bounces b = MakeBounces(0, {0, -3}, {0.8, 0.1, 0.9}, {0, 0, 0}, 100, 0.305, 0, 1);
  const auto k = MeasureImpacts(b.poses, 100, 0, core::SpecimenParameters{});
  ASSERT_EQ(k.size(), 3u);
  ASSERT_TRUE(k[0].success) << k[0].message;
  EXPECT_NEAR(k[0].e, 0.8, 1e-8);
  for (std::size_t i = 1; i < 3; ++i) {
    SCOPED_TRACE("impact " + std::to_string(i));
    EXPECT_FALSE(k[i].success);
    EXPECT_FALSE(k[i].no_impact);
    EXPECT_NE(k[i].message.find("too few free-flight frames"), std::string::npos) << k[i].message;
    EXPECT_NE(k[i].message.find("frame " + std::to_string(k[i].lowest_frame)), std::string::npos)
        << k[i].message;
    EXPECT_LE(std::abs(k[i].lowest_frame - b.impacts[i].t_s * 100), 1.0);
    EXPECT_EQ(k[i].impact_frame, k[i].lowest_frame);
  }
}

// A clip like the one above (e 0.12 in the middle) with min_fit_frames lowered to 3: the windows
// fit p and v with g known, so three frames determine them with a frame to spare. The impacts
// on each side of the short flight (fewer than 6 frames) are measured, and exact poses give
// their e exactly.
TEST(MultipleImpactsTest, FewerFramesPerFitAreAllowedWhenAsked) {
  const Bounces b = MakeBounces(0, {0, -3}, {0.8, 0.12, 0.9}, {0, 0, 0}, 100, 0.305, 0, 1);
  KinematicsOptions options;
  options.min_fit_frames = 3;
  const auto k = MeasureImpacts(b.poses, 100, 0, core::SpecimenParameters{}, options);
  ASSERT_EQ(k.size(), 3u);
  ASSERT_TRUE(k[0].success) << k[0].message;
  EXPECT_NEAR(k[0].e, 0.8, 1e-8);
  for (std::size_t i = 1; i < 3; ++i) {
    SCOPED_TRACE("impact " + std::to_string(i));
    ASSERT_TRUE(k[i].success) << k[i].message;
    EXPECT_NEAR(k[i].e, i == 1 ? 0.12 : 0.9, 1e-8);
  }
  // The flight between impacts 1 and 2 is the short one, too short for the default.
  EXPECT_GE(k[1].after.n, 3);
  EXPECT_LT(k[1].after.n, 6);
  EXPECT_EQ(k[2].before.n, k[1].after.n);
  const auto by_default = MeasureImpacts(b.poses, 100, 0, core::SpecimenParameters{});
  ASSERT_EQ(by_default.size(), 3u);
  EXPECT_FALSE(by_default[1].success);
  EXPECT_FALSE(by_default[2].success);
}

// A fall that never reaches the surface, and a flight with noise at its apex, hold no impact.
TEST(MultipleImpactsTest, FlightAloneHoldsNoImpact) {
  Bounces b = MakeBounces(0, {0, -3}, {0.8}, {0}, 2000, 0.05, 20e-6, 3);
  b.poses.resize(95);  // before the touch at frame 100
  EXPECT_TRUE(MeasureImpacts(b.poses, 2000, 0, core::SpecimenParameters{}).empty());
  // Only the rise after the impact, over its apex, with noise.
  Bounces up = MakeBounces(0, {0, -3}, {0.8}, {0}, 2000, 0.0, 20e-6, 4);
  up.poses.erase(up.poses.begin(), up.poses.begin() + 5);
  EXPECT_TRUE(MeasureImpacts(up.poses, 2000, 0, core::SpecimenParameters{}).empty());
}

}  // namespace
}  // namespace hoof::kinematics
