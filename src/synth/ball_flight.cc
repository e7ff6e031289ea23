#include "synth/ball_flight.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

namespace hoof::synth {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// Orientation steps while the spin turns during sliding (s): orientation is drawn, never
/// measured, and the midpoint rule's error per step is below 1e-9 rad here.
constexpr double kSlideStep_s = 5e-4;

/// The per-bounce e: a normal about e_mean, redrawn outside [0.05, 0.98].
double DrawE(const BounceOptions& b, cv::RNG& rng) {
  if (b.e_sd == 0) return b.e_mean;
  for (int i = 0; i < 1000; ++i) {
    const double e = b.e_mean + b.e_sd * rng.gaussian(1.0);
    if (e >= 0.05 && e <= 0.98) return e;
  }
  return b.e_mean;
}

/// Time from y0 (centre height) with vertical speed vy until the centre is at r (falling).
double TimeToContact(double y0, double vy, double r, double g) {
  const double h = std::max(0.0, y0 - r);
  return (vy + std::sqrt(vy * vy + 2 * g * h)) / g;
}

PathSegment Segment(double t0, double t1, BallPhase phase, const BallState& s,
                    const Eigen::Vector3d& a) {
  PathSegment seg;
  seg.t0 = t0;
  seg.t1 = t1;
  seg.phase = phase;
  seg.p0 = s.p_WC_m;
  seg.v0 = s.v_WC_m_s;
  seg.a = a;
  seg.w0 = s.w_W_rad_s;
  seg.R0 = s.R_WB;
  return seg;
}

BallState Evaluate(const PathSegment& seg, double t) {
  BallState s;
  s.phase = seg.phase;
  const double d = std::isfinite(seg.t0) ? t - seg.t0 : 0.0;
  if (!std::isfinite(seg.t0)) {  // the held (or resting) state before everything: constant
    s.p_WC_m = seg.p0;
    s.R_WB = seg.R0;
    return s;
  }
  s.p_WC_m = seg.p0 + seg.v0 * d + 0.5 * seg.a * d * d;
  s.v_WC_m_s = seg.v0 + seg.a * d;
  s.w_W_rad_s = seg.w0 + seg.alpha * d;
  if (seg.R_steps.empty()) {
    s.R_WB = Turn(seg.R0, seg.w0, d);
  } else {
    const auto last = static_cast<double>(seg.R_steps.size() - 1);
    const double i = std::clamp(std::floor(d / seg.step_s), 0.0, last);
    const double si = i * seg.step_s, rest = d - si;
    s.R_WB =
        Turn(seg.R_steps[static_cast<std::size_t>(i)], seg.w0 + seg.alpha * (si + rest / 2), rest);
  }
  return s;
}

/// The sliding segment from `s` (on the surface, v.y = 0) until the slip ends, with its
/// orientation table up to `end_s`; returns the time rolling starts (infinite without friction).
double AddSliding(BallPath& path, const BallState& s, double t, double mu, double end_s) {
  const double r = path.radius_m, k = path.inertia_factor, g = path.g_m_s2;
  const Eigen::Vector3d n = Eigen::Vector3d::UnitY();
  const Eigen::Vector3d u = s.v_WC_m_s + s.w_W_rad_s.cross(-r * n);
  if (u.norm() < 1e-12) return t;
  if (mu == 0) {
    path.segments.push_back(Segment(t, kInf, BallPhase::kSliding, s, Eigen::Vector3d::Zero()));
    return kInf;
  }
  const Eigen::Vector3d uhat = u.normalized();
  const double duration = u.norm() / (mu * g * (1 + 1 / k));
  PathSegment seg = Segment(t, t + duration, BallPhase::kSliding, s, -mu * g * uhat);
  seg.alpha = mu * g / (k * r) * n.cross(uhat);
  seg.step_s = kSlideStep_s;
  const double table_s = std::max(0.0, std::min(duration, end_s - t));
  seg.R_steps.push_back(s.R_WB);
  for (double si = 0; si < table_s; si += kSlideStep_s)
    seg.R_steps.push_back(
        Turn(seg.R_steps.back(), seg.w0 + seg.alpha * (si + kSlideStep_s / 2), kSlideStep_s));
  path.segments.push_back(std::move(seg));
  return t + duration;
}

/// The surface phase after the contact without rebound at t: sliding, then rolling.
void AddSettle(BallPath& path, BallState s, double t, double mu, double end_s) {
  path.settle_time_s = t;
  s.v_WC_m_s.y() = 0;
  path.rolling_time_s = AddSliding(path, s, t, mu, end_s);
  if (!std::isfinite(path.rolling_time_s)) {
    path.rolling_time_s = kNaN;
    return;
  }
  BallState roll = path.segments.back().t0 == t && path.segments.back().phase == BallPhase::kSliding
                       ? Evaluate(path.segments.back(), path.rolling_time_s)
                       : s;
  roll.p_WC_m.y() = path.radius_m;
  roll.v_WC_m_s.y() = 0;
  path.segments.push_back(
      Segment(path.rolling_time_s, kInf, BallPhase::kRolling, roll, Eigen::Vector3d::Zero()));
}

/// Held at rest until the carry starts, then carried at the release velocity until release.
BallState AddHeld(BallPath& path, const LaunchOptions& launch, double r) {
  const Eigen::Vector3d p_release{launch.x_m, launch.drop_height_m + r, launch.z_m};
  const bool thrown = launch.v_W_m_s.norm() > 0 && launch.throw_duration_s > 0;
  const double carry = thrown ? launch.throw_duration_s : 0.0;
  path.release_time_s = launch.release_time_s;
  path.carry_start_s = launch.release_time_s - carry;
  BallState s;
  s.p_WC_m = p_release - launch.v_W_m_s * carry;
  path.segments.push_back(Segment(-kInf, path.carry_start_s, BallPhase::kHeld, s, {0, 0, 0}));
  if (thrown) {
    s.v_WC_m_s = launch.v_W_m_s;
    s.w_W_rad_s = launch.w_W_rad_s;
    path.segments.push_back(
        Segment(path.carry_start_s, path.release_time_s, BallPhase::kHeld, s, {0, 0, 0}));
    s = Evaluate(path.segments.back(), path.release_time_s);
  }
  s.p_WC_m = p_release;
  s.v_WC_m_s = launch.v_W_m_s;
  s.w_W_rad_s = launch.w_W_rad_s;
  return s;
}

}  // namespace

const char* ToString(BallPhase phase) {
  switch (phase) {
    case BallPhase::kAbsent:
      return "absent";
    case BallPhase::kHeld:
      return "held";
    case BallPhase::kFlight:
      return "flight";
    case BallPhase::kSliding:
      return "sliding";
    case BallPhase::kRolling:
      return "rolling";
    case BallPhase::kRest:
      return "rest";
  }
  return "absent";
}

Eigen::Matrix3d Turn(const Eigen::Matrix3d& R, const Eigen::Vector3d& w_rad_s, double s) {
  const double angle = w_rad_s.norm() * s;
  if (angle == 0) return R;
  return Eigen::AngleAxisd(angle, w_rad_s.normalized()).toRotationMatrix() * R;
}

SphereImpact ResolveSphereImpact(const Eigen::Vector3d& v, const Eigen::Vector3d& w, double r,
                                 double k, double e, double mu, const Eigen::Vector3d& n) {
  const double vn = v.dot(n);
  const double jn = -(1 + e) * std::min(vn, 0.0);
  const Eigen::Vector3d u = (v - vn * n) + w.cross(-r * n);  // the contact point's slip
  const Eigen::Vector3d stop = -u * k / (1 + k);             // the impulse that ends the slip
  SphereImpact out;
  Eigen::Vector3d jt;
  if (stop.norm() <= mu * jn) {
    jt = stop;
    out.rolling = true;
  } else {
    jt = u.norm() > 0 ? Eigen::Vector3d(-mu * jn * u.normalized()) : Eigen::Vector3d::Zero();
  }
  out.impulse_per_kg_m_s = jn * n + jt;
  out.v_after_m_s = v + out.impulse_per_kg_m_s;
  out.w_after_rad_s = w - n.cross(jt) / (k * r);
  out.mu_eff = jn > 0 ? jt.norm() / jn : 0.0;
  return out;
}

BallState BallPath::At(double t_s) const {
  if (!present || segments.empty()) return {};
  auto it = std::upper_bound(segments.begin(), segments.end(), t_s,
                             [](double t, const PathSegment& s) { return t < s.t0; });
  if (it != segments.begin()) --it;
  return Evaluate(*it, t_s);
}

BallPath PlanBallPath(FootageScenario scenario, const BallOptions& ball,
                      const LaunchOptions& launch, const BounceOptions& bounce, double end_s,
                      std::uint64_t seed) {
  BallPath path;
  path.radius_m = ball.radius_m;
  path.inertia_factor = InertiaFactor(ball.inertia);
  path.g_m_s2 = bounce.g_m_s2;
  path.end_s = end_s;
  path.settle_time_s = path.rolling_time_s = path.release_time_s = path.carry_start_s = kNaN;
  const double r = path.radius_m, g = path.g_m_s2;
  if (scenario == FootageScenario::kHandOnly) {
    path.present = false;
    return path;
  }
  if (scenario == FootageScenario::kStill) {
    BallState s;
    s.phase = BallPhase::kRest;
    s.p_WC_m = {launch.x_m, r, launch.z_m};
    path.segments.push_back(Segment(-kInf, kInf, BallPhase::kRest, s, {0, 0, 0}));
    return path;
  }
  BallState s = AddHeld(path, launch, r);
  cv::RNG rng(seed * 0x9E3779B97F4A7C15ull + 0xB0B);
  const Eigen::Vector3d gravity{0, -g, 0};
  double t = path.release_time_s;
  for (int guard = 0; guard < 100000; ++guard) {
    const double tc = t + TimeToContact(s.p_WC_m.y(), s.v_WC_m_s.y(), r, g);
    if (!(tc < end_s)) {
      path.segments.push_back(Segment(t, kInf, BallPhase::kFlight, s, gravity));
      return path;
    }
    path.segments.push_back(Segment(t, tc, BallPhase::kFlight, s, gravity));
    BallState c = Evaluate(path.segments.back(), tc);
    c.p_WC_m.y() = r;  // exactly on the surface (the root's rounding aside)
    const double e = DrawE(bounce, rng);
    const double vn = c.v_WC_m_s.y();
    if (e * e * vn * vn / (2 * g) < bounce.min_rebound_height_m) {
      const SphereImpact imp =
          ResolveSphereImpact(c.v_WC_m_s, c.w_W_rad_s, r, path.inertia_factor, 0.0, bounce.mu);
      c.v_WC_m_s = imp.v_after_m_s;
      c.w_W_rad_s = imp.w_after_rad_s;
      AddSettle(path, c, tc, bounce.mu, end_s);
      return path;
    }
    const SphereImpact imp =
        ResolveSphereImpact(c.v_WC_m_s, c.w_W_rad_s, r, path.inertia_factor, e, bounce.mu);
    BallBounce b;
    b.t_s = tc;
    b.p_WC_m = c.p_WC_m;
    b.p_WT_m = c.p_WC_m - Eigen::Vector3d(0, r, 0);
    b.v_before_m_s = c.v_WC_m_s;
    b.w_before_rad_s = c.w_W_rad_s;
    b.v_after_m_s = imp.v_after_m_s;
    b.v_after_m_s.y() = -e * vn;
    b.w_after_rad_s = imp.w_after_rad_s;
    b.e = e;
    b.mu_eff = imp.mu_eff;
    b.rolling = imp.rolling;
    path.bounces.push_back(b);
    c.v_WC_m_s = b.v_after_m_s;
    c.w_W_rad_s = b.w_after_rad_s;
    s = c;
    t = tc;
  }
  path.segments.push_back(Segment(t, kInf, BallPhase::kFlight, s, gravity));
  return path;
}

}  // namespace hoof::synth
