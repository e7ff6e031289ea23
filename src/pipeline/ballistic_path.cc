#include "pipeline/ballistic_path.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/QR>

#include "tracking/frame_timing.h"

namespace hoof::pipeline::ballistic {

std::vector<bool> CopiesOn(const tracking::MotionPath& path, const std::vector<bool>& repeat,
                           int frame_count) {
  std::vector<bool> rep = repeat;
  rep.resize(static_cast<std::size_t>(std::max(0, frame_count)), false);
  std::vector<std::optional<Eigen::Vector2d>> p(rep.size());
  for (const auto& r : path.regions)
    if (r.frame >= 0 && r.frame < frame_count && !r.touches_border)
      p[static_cast<std::size_t>(r.frame)] = r.p_I;
  // Copies coded again that the images could not tell from new captures: the path stands still
  // for a frame while it moves.
  tracking::AddRepeatsFromMotion(p, tracking::FrameTimingOptions{}, rep);
  if (tracking::HeldImageFromMotion(p, rep).held == tracking::HeldImage::kLast)
    return tracking::SampleAtLastCopy(rep);
  return rep;
}

Positions PositionsOf(const tracking::MotionPath& path, const std::vector<bool>& copy) {
  const auto& r = path.regions;
  std::size_t lo = 0, hi = r.empty() ? 0 : r.size() - 1;
  const double still = 0.1 * path.MedianDiameter();
  while (lo + 1 < r.size() && (r[lo + 1].p_I - r[lo].p_I).norm() < still) ++lo;
  while (hi > lo + 1 && (r[hi].p_I - r[hi - 1].p_I).norm() < still) --hi;
  if (hi < lo + 3) {  // hardly anything else: keep the path whole (it is still)
    lo = 0;
    hi = r.empty() ? 0 : r.size() - 1;
  }
  tracking::MotionPath kept;
  kept.regions.assign(r.begin() + static_cast<std::ptrdiff_t>(lo),
                      r.begin() + static_cast<std::ptrdiff_t>(hi + 1));
  Positions out;
  out.first = kept.first_frame();
  out.p.resize(static_cast<std::size_t>(kept.last_frame() - out.first + 1));
  out.size.assign(out.p.size(), core::kNaN);
  for (const auto& k : kept.regions) {
    if (k.touches_border) continue;  // cut by the frame's edge: its centroid is not the ball's
    if (k.frame >= 0 && static_cast<std::size_t>(k.frame) < copy.size() &&
        copy[static_cast<std::size_t>(k.frame)])
      continue;
    out.p[static_cast<std::size_t>(k.frame - out.first)] = k.p_I;
    out.size[static_cast<std::size_t>(k.frame - out.first)] = k.diameter_px;
  }
  return out;
}

ArcStats FitArcsOnce(const Positions& in, double fps, const std::vector<bool>& left_out);

/// FitArcsOnce, then again without the frames off the arcs by more than `trim_px` (a contact
/// that lasts several frames, on a compliant surface such as a net, bends the path between
/// arcs), while at most 40 % of the frames are left out so. The frames left out count neither
/// for nor against the path (ArcStats::trimmed).
ArcStats FitArcs(const Positions& in, double fps, double trim_px) {
  std::vector<bool> left_out(in.p.size(), false);
  ArcStats st = FitArcsOnce(in, fps, left_out);
  if (!(trim_px > 0)) return st;
  int valid = 0;
  for (const auto& p : in.p) valid += p ? 1 : 0;
  for (int round = 0; round < 4 && st.fitted && !st.fit.contacts.empty() && !(st.rms <= trim_px);
       ++round) {
    int removed = 0, already = 0;
    for (bool b : left_out) already += b ? 1 : 0;
    std::vector<bool> next = left_out;
    for (std::size_t i = 0; i < in.p.size(); ++i) {
      if (!in.p[i] || left_out[i]) continue;
      const auto& fr = st.fit.frames[i];
      if (fr.arc < 0 || !st.fit.arcs[static_cast<std::size_t>(fr.arc)].fitted) continue;
      const Eigen::Vector2d model = kinematics::ArcPosition(
          st.fit, st.fit.x, fr.arc, (in.first + static_cast<double>(i)) / fps);
      const Eigen::Vector2d seen(in.p[i]->x(), -in.p[i]->y());
      if ((model - seen).norm() > 2 * trim_px) {
        next[i] = true;
        ++removed;
      }
    }
    if (removed == 0 || already + removed > 0.4 * valid) break;
    const ArcStats again = FitArcsOnce(in, fps, next);
    if (!again.fitted) break;
    left_out = next;
    st = again;
    st.trimmed = already + removed;
  }
  return st;
}

ArcStats FitArcsOnce(const Positions& in, double fps, const std::vector<bool>& left_out) {
  std::vector<kinematics::PoseSample> poses(in.p.size());
  bool has_previous = false;
  Eigen::Vector2d previous{0, 0};
  for (std::size_t i = 0; i < in.p.size(); ++i) {
    auto& s = poses[i];
    s.t_s = (in.first + static_cast<double>(i)) / fps;
    if (!in.p[i] || left_out[i]) {
      has_previous = false;
      continue;
    }
    if (has_previous && (*in.p[i] - previous).norm() < 1e-3) {
      s.repeated = true;
      continue;
    }
    has_previous = true;
    previous = *in.p[i];
    s.valid = true;
    s.p_WE = {in.p[i]->x(), -in.p[i]->y()};
    if (!in.cov.empty()) {
      s.cov_p_WE = in.cov[i];
      s.cov_p_WE(0, 1) = s.cov_p_WE(1, 0) = -in.cov[i](0, 1);
    }
    s.apparent_size = in.size.empty() ? core::kNaN : in.size[i];
  }
  ArcStats st;
  try {
    st.fit = kinematics::FitFlightArcs(poses, 0.0, 0.0);
  } catch (const std::exception&) {
    return st;
  }
  if (st.fit.status != kinematics::ArcFitStatus::kFitted) return st;
  st.fitted = true;
  for (const auto& a : st.fit.arcs)
    if (a.fitted) {
      ++st.arcs;
      if (st.first_arc_frame < 0) st.first_arc_frame = in.first + a.first_frame;
      st.last_arc_frame = in.first + a.last_frame;
    }
  if (st.arcs == 0) return st;
  for (int f = st.first_arc_frame; f <= st.last_arc_frame; ++f) {
    const auto i = static_cast<std::size_t>(f - in.first);
    if (!poses[i].valid) continue;
    ++st.in_span;
    if (st.fit.frames[i].role == kinematics::ArcFrameRole::kArc) ++st.on_arcs;
  }
  st.arc_fraction = st.in_span > 0 ? static_cast<double>(st.on_arcs) / st.in_span : 0.0;
  st.a = st.fit.a_norm;
  st.a_sigmas = st.fit.a_norm_se > 0 ? st.fit.a_norm / st.fit.a_norm_se : 0.0;
  if (st.fit.a_norm > 0) {
    const Eigen::Vector2d down_I(st.fit.a_W.x(), -st.fit.a_W.y());
    st.down_angle_deg = std::acos(std::clamp(down_I.normalized().y(), -1.0, 1.0)) * 180 / M_PI;
  }
  st.rms = st.fit.sigma;
  return st;
}

/// A parabola in time fitted to each coordinate of positions (t, p): its rms residual (px, per
/// coordinate) and its acceleration (px/s^2, image axes); false with fewer than 4 samples.
bool FitParabola(const std::vector<double>& t, const std::vector<Eigen::Vector2d>& p, double& rms,
                 Eigen::Vector2d& a) {
  const std::size_t n = t.size();
  if (n < 4) return false;
  Eigen::MatrixXd A(static_cast<Eigen::Index>(n), 3);
  Eigen::MatrixXd b(static_cast<Eigen::Index>(n), 2);
  const double t0 = t[n / 2];
  for (std::size_t i = 0; i < n; ++i) {
    const double dt = t[i] - t0;
    A.row(static_cast<Eigen::Index>(i)) << 1.0, dt, 0.5 * dt * dt;
    b.row(static_cast<Eigen::Index>(i)) = p[i].transpose();
  }
  const Eigen::MatrixXd x = A.colPivHouseholderQr().solve(b);
  const Eigen::MatrixXd r = A * x - b;
  rms = std::sqrt(r.squaredNorm() / std::max<double>(1.0, 2.0 * static_cast<double>(n) - 6.0));
  a = x.row(2).transpose();
  return true;
}

/// The path as flights between bounces, each fitted with its own parabola: split at each
/// bounce (a lowest point along the image's down within two samples either side), the frames
/// nearest each bounce left out, as few as let the flight fit within `limit_px` (a contact
/// that lasts several frames, on a net or a soft floor, bends the path between flights). A
/// flight that cannot be fitted before the first that can (a hand, a ball cut by the frame's
/// edge) is passed over, and one after the last ends the path (short bounces, rolling). Fills
/// `st` (the acceleration the mean of the flights', its standard error their spread) and
/// returns true when the flights hold at least `min_frames` samples.
bool PiecewiseFlights(const Positions& in, double fps, double limit_px, int min_frames,
                      ArcStats& st) {
  std::vector<double> t;
  std::vector<Eigen::Vector2d> p;
  std::vector<int> frame;
  for (std::size_t i = 0; i < in.p.size(); ++i)
    if (in.p[i]) {
      t.push_back((in.first + static_cast<double>(i)) / fps);
      p.push_back(*in.p[i]);
      frame.push_back(in.first + static_cast<int>(i));
    }
  const int n = static_cast<int>(p.size());
  if (n < min_frames) return false;
  std::vector<int> bounces;
  for (int i = 1; i + 1 < n; ++i) {
    bool lowest = true;
    for (int k = std::max(0, i - 2); k <= std::min(n - 1, i + 2); ++k)
      if (k != i && p[static_cast<std::size_t>(k)].y() >= p[static_cast<std::size_t>(i)].y())
        lowest = false;
    if (lowest) bounces.push_back(i);
  }
  std::vector<std::pair<int, int>> pieces;  // [lo, hi] sample indices
  std::vector<Eigen::Vector2d> accelerations;
  std::vector<int> sizes;
  double worst = 0;
  for (std::size_t k = 0; k <= bounces.size(); ++k) {
    const int from = k == 0 ? 0 : bounces[k - 1] + 1;
    const int to = k < bounces.size() ? bounces[k] - 1 : n - 1;
    double rms = 0;
    Eigen::Vector2d a;
    auto fits = [&](int lo, int hi) {
      if (hi - lo + 1 < 4) return false;
      std::vector<double> tt(t.begin() + lo, t.begin() + hi + 1);
      std::vector<Eigen::Vector2d> pp(p.begin() + lo, p.begin() + hi + 1);
      return FitParabola(tt, pp, rms, a) && rms <= limit_px;
    };
    bool found = false;
    for (int drop = 0; !found && to - from + 1 - drop >= 4; ++drop)
      for (int ds = drop; ds >= 0 && !found; --ds)
        if (fits(from + ds, to - (drop - ds))) {
          pieces.push_back({from + ds, to - (drop - ds)});
          found = true;
        }
    if (!found) {
      if (pieces.empty()) continue;  // before the first flight that fits
      break;                         // the path's end
    }
    fits(pieces.back().first, pieces.back().second);  // its rms and acceleration
    accelerations.push_back(a);
    sizes.push_back(pieces.back().second - pieces.back().first + 1);
    worst = std::max(worst, rms);
  }
  if (pieces.empty()) return false;
  int on = 0;
  for (const auto& [lo, hi] : pieces) on += hi - lo + 1;
  const int span = pieces.back().second - pieces.front().first + 1;
  if (on < min_frames) return false;
  // The frames between flights are the contacts': they count neither for nor against the path,
  // up to half of its span.
  int between = 0;
  for (std::size_t k = 1; k < pieces.size(); ++k)
    between += pieces[k].first - pieces[k - 1].second - 1;
  between = std::min(between, span / 2);
  // The shared acceleration: the flights' weighted by their samples.
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  double w = 0;
  for (std::size_t k = 0; k < accelerations.size(); ++k) {
    mean += sizes[k] * accelerations[k];
    w += sizes[k];
  }
  mean /= w;
  double spread = 0;
  for (std::size_t k = 0; k < accelerations.size(); ++k)
    spread += sizes[k] * (accelerations[k] - mean).squaredNorm();
  spread = std::sqrt(spread / w);
  st = ArcStats{};
  st.fitted = true;
  st.arcs = static_cast<int>(pieces.size());
  st.on_arcs = on;
  st.in_span = span - between;
  st.trimmed = between;
  st.arc_fraction = static_cast<double>(on) / st.in_span;
  st.a = mean.norm();
  // The mean's standard error from the flights' spread; one flight alone has none, and its
  // acceleration counts as measured where it exceeds a tenth of a pixel per frame squared.
  st.a_sigmas =
      accelerations.size() > 1
          ? st.a / std::max(1e-9, spread / std::sqrt(static_cast<double>(accelerations.size())))
          : st.a / std::max(1e-9, 0.02 * fps * fps);
  st.down_angle_deg =
      st.a > 0 ? std::acos(std::clamp(mean.normalized().y(), -1.0, 1.0)) * 180 / M_PI : 180.0;
  st.rms = worst;
  st.first_arc_frame = frame[static_cast<std::size_t>(pieces.front().first)];
  st.last_arc_frame = frame[static_cast<std::size_t>(pieces.back().second)];
  st.piecewise = true;
  return true;
}

/// The joint arc fit (FitArcs), or the flights one by one (PiecewiseFlights) where they explain
/// more frames within `limit_px`: the joint fit walks from contact to contact, and stops where
/// the noise of region centroids hides one.
ArcStats Ballistic(const Positions& in, double fps, double limit_px, int min_frames) {
  ArcStats st = FitArcs(in, fps, limit_px);
  ArcStats pieces;
  if (PiecewiseFlights(in, fps, limit_px, min_frames, pieces) &&
      (!(st.fitted && st.rms <= limit_px) || pieces.on_arcs > st.on_arcs))
    st = pieces;
  return st;
}

}  // namespace hoof::pipeline::ballistic
