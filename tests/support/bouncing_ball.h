#pragma once
/// @file
/// A bouncing ball written out in closed form, sampled like a camera would: the truth for the
/// joint arc fit's tests (tests/kinematics/) and its scorecard (bench/arc_scorecard.cc).
///
/// The ball's centre moves in a gravity frame G (x along the floor's horizontal, y up, z away
/// from the camera; m) on exact parabolas p + v t - g y t^2 / 2 between contacts with a plane
/// through G's origin at `surface_angle_deg` (normal n = (sin phi, cos phi, 0)). At each touch
/// (n . p = radius) the normal velocity reverses times e, the tangential one loses mu (1 + e)
/// |v_n| (never reversing), and the ball rests at the touch point for `contact_s` before
/// flying on. Before `release_s` a hand carries it (p0 + v0 (t - release_s): no gravity). A
/// frame at time t shows the centre averaged over its exposure, projected through a pinhole at
/// `depth_m` (none when 0: orthographic) looking down by `tilt_deg`, rolled by `roll_deg` and
/// shifted by `origin_W` into W, plus Gaussian noise.

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "kinematics/pose_sample.h"

namespace hoof::testing {

struct BallClipOptions {
  double fps = 30.0;
  double phase_s = 0.0;  ///< time of frame 0 (the release is at release_s)
  int frames = 60;
  double g_m_s2 = 9.81;
  double radius_m = 0.033;
  double surface_angle_deg = 0.0;
  Eigen::Vector3d p0_G{0.0, 0.8, 0.0};  ///< centre at the release (m)
  Eigen::Vector3d v0_G{0.3, 0.0, 0.0};  ///< velocity at the release (m/s)
  double release_s = 0.0;
  std::vector<double> e{0.8, 0.8, 0.8, 0.8};  ///< per bounce; the clip ends at a further touch
  std::vector<double> mu{0.0, 0.0, 0.0, 0.0};
  double contact_s = 0.0;
  double exposure_s = 0.0;
  double depth_m = 0.0;               ///< camera distance to G's origin along z; 0: orthographic
  Eigen::Vector2d principal_G{0, 0};  ///< where the optical axis meets the plane z = 0 (m)
  double tilt_deg = 0.0;  ///< with depth_m: the camera looks down at principal_G by this
  double roll_deg = 0.0;  ///< "up" in W leans toward +x_W by this
  Eigen::Vector2d origin_W{0.2, -0.1};
  double m_per_px = 1.5e-3;  ///< for the noise and the apparent size
  double noise_px = 0.0;
  double size_noise_px = 0.0;
  bool give_covariance = false;  ///< set PoseSample::cov_p_WE to the noise's
  std::vector<int> missing, repeated;
  std::uint64_t seed = 1;
};

/// One bounce's truth.
struct TrueBounce {
  double t_touch = 0, t_sep = 0;
  Eigen::Vector2d v_before_S{0, 0}, v_after_S{0, 0};  ///< [along the surface, normal]
  double e = 0, mu_eff = 0;
  Eigen::Vector2d p_T_W{0, 0};  ///< the contact point in W (without perspective)
};

struct BallClip {
  std::vector<kinematics::PoseSample> poses;
  std::vector<TrueBounce> bounces;  ///< those before the clip's end
  Eigen::Vector2d up_W{0, 1};
  Eigen::Vector2d principal_W{0, 0};
  double level_m = 0;  ///< height of the contact points along up_W (level floor, no perspective)
};

namespace ball_detail {

struct Segment {
  enum Kind { kHeld, kFlight, kContact } kind;
  double t0;
  Eigen::Vector3d p, v;
};

inline Eigen::Vector3d At(const Segment& s, double t, double g) {
  const double tau = t - s.t0;
  if (s.kind == Segment::kContact) return s.p;
  if (s.kind == Segment::kHeld) return s.p + s.v * tau;
  return s.p + s.v * tau - Eigen::Vector3d(0, 0.5 * g * tau * tau, 0);
}

}  // namespace ball_detail

inline BallClip MakeBallClip(const BallClipOptions& o) {
  using ball_detail::Segment;
  const double phi = o.surface_angle_deg * M_PI / 180;
  const Eigen::Vector3d n(std::sin(phi), std::cos(phi), 0), ts(std::cos(phi), -std::sin(phi), 0);
  const Eigen::Vector3d gv(0, -o.g_m_s2, 0);
  const double t_end = o.phase_s + (o.frames - 1) / o.fps + o.exposure_s;
  const double rho = o.roll_deg * M_PI / 180;
  Eigen::Matrix2d R_WG;  // rotation by -rho: y_G goes to (sin rho, cos rho)
  R_WG << std::cos(rho), std::sin(rho), -std::sin(rho), std::cos(rho);
  BallClip clip;
  clip.up_W = R_WG * Eigen::Vector2d(0, 1);
  clip.principal_W = R_WG * o.principal_G + o.origin_W;
  clip.level_m = clip.up_W.dot(o.origin_W);
  std::vector<Segment> seg;
  seg.push_back({Segment::kHeld, o.release_s, o.p0_G, o.v0_G});  // before the release
  seg.push_back({Segment::kFlight, o.release_s, o.p0_G, o.v0_G});
  double clip_end = t_end;
  for (std::size_t k = 0;; ++k) {
    const Segment& f = seg.back();
    const double A = 0.5 * n.dot(gv), B = n.dot(f.v), C = n.dot(f.p) - o.radius_m;
    const double tau = C <= 1e-15 ? -B / A : (-B - std::sqrt(B * B - 4 * A * C)) / (2 * A);
    const double t_touch = f.t0 + tau;
    if (t_touch > t_end) break;
    if (k >= o.e.size()) {
      clip_end = t_touch;
      break;
    }
    const Eigen::Vector3d p = ball_detail::At(f, t_touch, o.g_m_s2), v = f.v + gv * tau;
    const double vn = n.dot(v);
    const Eigen::Vector3d vt = v - vn * n;
    const double dvn = -(1 + o.e[k]) * vn;
    const double dvt = std::min(vt.norm(), o.mu[k] * dvn);
    const Eigen::Vector3d t_dir =
        vt.norm() > 0 ? Eigen::Vector3d(vt / vt.norm()) : Eigen::Vector3d::Zero();
    const Eigen::Vector3d v_after = v + dvn * n - dvt * t_dir;
    TrueBounce b;
    b.t_touch = t_touch;
    b.t_sep = t_touch + o.contact_s;
    b.v_before_S = {ts.dot(v), n.dot(v)};
    b.v_after_S = {ts.dot(v_after), n.dot(v_after)};
    b.e = o.e[k];
    b.mu_eff = std::abs((b.v_after_S.x() - b.v_before_S.x()) / dvn);
    const Eigen::Vector3d pt = p - o.radius_m * n;
    b.p_T_W = R_WG * Eigen::Vector2d(pt.x(), pt.y()) + o.origin_W;
    clip.bounces.push_back(b);
    if (o.contact_s > 0) seg.push_back({Segment::kContact, t_touch, p, Eigen::Vector3d::Zero()});
    seg.push_back({Segment::kFlight, b.t_sep, p, v_after});
  }
  std::mt19937_64 rng(o.seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const auto position = [&](double t) {
    std::size_t s = 0;
    while (s + 1 < seg.size() && seg[s + 1].t0 <= t) ++s;
    return ball_detail::At(seg[s], t, o.g_m_s2);
  };
  for (int i = 0; i < o.frames; ++i) {
    const double t = o.phase_s + i / o.fps;
    if (t + 0.5 * o.exposure_s > clip_end) break;
    // The image: the centre projected, averaged over the exposure.
    Eigen::Vector2d img{0, 0};
    double z_mean = 0;
    const int sub = o.exposure_s > 0 ? 41 : 1;
    for (int j = 0; j < sub; ++j) {
      const double tj = sub == 1 ? t : t + o.exposure_s * (j / (sub - 1.0) - 0.5);
      const Eigen::Vector3d p = position(tj);
      // The camera: depth_m from principal_G (on z = 0) along its optical axis, which looks
      // down by tilt_deg; its image in G's units at that point's depth.
      const double tilt = o.tilt_deg * std::numbers::pi / 180, ct = std::cos(tilt),
                   st = std::sin(tilt);
      const Eigen::Vector3d forward(0, -st, ct), cam_up(0, ct, st);
      const Eigen::Vector3d d =
          p - Eigen::Vector3d(o.principal_G.x(), o.principal_G.y(), 0) + o.depth_m * forward;
      const double zc = o.depth_m > 0 ? d.dot(forward) : 1.0;
      const double k = o.depth_m > 0 ? o.depth_m / zc : 1.0;
      const Eigen::Vector2d offset = o.depth_m > 0 ? Eigen::Vector2d(d.x(), d.dot(cam_up))
                                                   : Eigen::Vector2d(p.x(), p.y()) - o.principal_G;
      img += (o.principal_G + offset * k) / sub;
      z_mean += zc / sub;
    }
    kinematics::PoseSample ps;
    ps.t_s = t;
    ps.valid = true;
    const double sd = o.noise_px * o.m_per_px;
    ps.p_WE = R_WG * img + o.origin_W + sd * Eigen::Vector2d(gauss(rng), gauss(rng));
    if (o.give_covariance) ps.cov_p_WE = sd * sd * Eigen::Matrix2d::Identity();
    const double size_px = 2 * o.radius_m * (o.depth_m > 0 ? o.depth_m / z_mean : 1.0) / o.m_per_px;
    ps.apparent_size = size_px + o.size_noise_px * gauss(rng);
    clip.poses.push_back(ps);
  }
  for (int f : o.missing)
    if (f >= 0 && f < static_cast<int>(clip.poses.size()))
      clip.poses[static_cast<std::size_t>(f)].valid = false;
  for (int f : o.repeated)
    if (f > 0 && f < static_cast<int>(clip.poses.size())) {
      auto& p = clip.poses[static_cast<std::size_t>(f)];
      p.p_WE = clip.poses[static_cast<std::size_t>(f) - 1].p_WE;
      p.valid = false;
      p.repeated = true;
    }
  const double t_last = clip.poses.empty() ? 0 : clip.poses.back().t_s;
  while (!clip.bounces.empty() && clip.bounces.back().t_touch > t_last) clip.bounces.pop_back();
  return clip;
}

}  // namespace hoof::testing
