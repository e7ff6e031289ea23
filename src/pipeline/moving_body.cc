#include "pipeline/moving_body.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>

namespace hoof::pipeline {
namespace {

double MedianOf(std::vector<double> v) {
  if (v.empty()) return core::kNaN;
  auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

std::string Num(double x, int precision = 3) {
  std::ostringstream os;
  os.precision(precision);
  os << x;
  return os.str();
}

/// One position per frame, in image px (nullopt where none), from `first` on.
struct Positions {
  int first = 0;
  std::vector<std::optional<Eigen::Vector2d>> p;
  std::vector<Eigen::Matrix2d> cov;  ///< empty: none
  std::vector<double> size;          ///< apparent size per frame (NaN where none)
};

/// The positions of `path`'s regions (none where a region touches the frame's edge), without
/// the frames at its start and end where it holds
/// still (moving less than a tenth of its size from one region to the next): a hand holding the
/// ball before it lets go, a ball come to rest. A release from rest would otherwise look like a
/// contact to the arc fit.
Positions PositionsOf(const tracking::MotionPath& path) {
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
    out.p[static_cast<std::size_t>(k.frame - out.first)] = k.p_I;
    out.size[static_cast<std::size_t>(k.frame - out.first)] = k.diameter_px;
  }
  return out;
}

/// The joint arc fit of positions in image px: W is x right, y up (px), times frame / fps. A
/// position equal to the one before (a repeated image) is no sample.
struct ArcStats {
  kinematics::FlightArcs fit;
  bool fitted = false;
  int on_arcs = 0, in_span = 0, arcs = 0;
  int trimmed = 0;  ///< frames left out as bent by a long contact
  /// Flights fitted one by one, each with its own parabola (PiecewiseFlights), not jointly.
  bool piecewise = false;
  double arc_fraction = 0.0, a = 0.0, a_sigmas = 0.0, down_angle_deg = 180.0, rms = core::kNaN;
  int first_arc_frame = -1, last_arc_frame = -1;  ///< clip frames
};

ArcStats FitArcsOnce(const Positions& in, double fps, const std::vector<bool>& left_out);

/// FitArcsOnce, then again without the frames off the arcs by more than `trim_px` (a contact
/// that lasts several frames, on a compliant surface such as a net, bends the path between
/// arcs), while at most 40 % of the frames are left out so. The frames left out count neither
/// for nor against the path (ArcStats::trimmed).
ArcStats FitArcs(const Positions& in, double fps, double trim_px = 0.0) {
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

/// The residual a ballistic path may have: max(min_rms_px, max_rms_diameters x its size, a
/// tenth of its median motion between frames, as motion blur smears a fast ball's region).
double RmsLimit(const tracking::MotionPath& path, const MovingBodyOptions& o) {
  std::vector<double> step;
  for (std::size_t k = 1; k < path.regions.size(); ++k)
    step.push_back((path.regions[k].p_I - path.regions[k - 1].p_I).norm() /
                   std::max(1, path.regions[k].frame - path.regions[k - 1].frame));
  const double blur = step.empty() ? 0.0 : 0.1 * MedianOf(step);
  return std::max({o.min_rms_px, o.max_rms_diameters * path.MedianDiameter(), blur});
}

/// The judgement of one candidate against the rules of `o`, from its arc fit.
void Judge(MovingCandidate& c, const ArcStats& st, const MovingBodyOptions& o, double rms_limit) {
  c.arc_fraction = st.arc_fraction;
  c.a_px_s2 = st.a;
  c.a_sigmas = st.a_sigmas;
  c.down_angle_deg = st.down_angle_deg;
  c.rms_px = st.rms;
  c.arcs = st.arcs;
  if (c.regions < o.min_frames) {
    c.verdict = CandidateVerdict::kTooShort;
    c.reason = "seen in " + std::to_string(c.regions) + " frames (" + std::to_string(o.min_frames) +
               " needed to test its motion)";
  } else if (c.travel_px < o.min_travel_diameters * c.diameter_px) {
    c.verdict = CandidateVerdict::kStill;
    c.reason = "moves " + Num(c.travel_px) + " px, less than " + Num(o.min_travel_diameters) +
               " of its " + Num(c.diameter_px) + " px size";
  } else if (!st.fitted || st.on_arcs < o.min_frames) {
    c.verdict = CandidateVerdict::kNotBallistic;
    c.reason = "no flight arc of " + std::to_string(o.min_frames) + " frames fits its path" +
               (st.fitted ? std::string() : " (" + st.fit.message + ")");
  } else if (st.arc_fraction < o.min_arc_fraction || !(st.rms <= rms_limit)) {
    c.verdict = CandidateVerdict::kNotBallistic;
    c.reason = "not ballistic: " + std::to_string(st.on_arcs) + " of " +
               std::to_string(st.in_span) + " frames on arcs of one acceleration, " + Num(st.rms) +
               " px off them (a ball: " + Num(100 * o.min_arc_fraction, 2) + " % within " +
               Num(rms_limit) + " px)";
  } else if (o.rgb && (c.rgb - *o.rgb).norm() > o.max_colour_distance) {
    c.verdict = CandidateVerdict::kNotLikeBody;
    c.reason = "its colour " + ColourHex(c.rgb) + " is not the stated " + ColourHex(*o.rgb);
  } else if (o.diameter_px > 0 && (c.diameter_px > o.max_size_ratio * o.diameter_px ||
                                   c.diameter_px * o.max_size_ratio < o.diameter_px)) {
    c.verdict = CandidateVerdict::kNotLikeBody;
    c.reason =
        "its size " + Num(c.diameter_px) + " px is not the expected " + Num(o.diameter_px) + " px";
  } else if (st.a_sigmas < o.min_a_sigmas) {
    // Smooth but not seen to fall: a shadow sliding on the floor, or a flight too short in
    // time for gravity to bend it (a slow-motion clip). The body only when nothing falls.
    c.verdict = CandidateVerdict::kNoFall;
    c.score = 0.5 * st.on_arcs * std::max(1.0, c.likeness);
    c.reason = "its acceleration " + Num(st.a) + " px/s^2 is " + Num(st.a_sigmas, 2) +
               " s.e. from 0: it slides or drifts, it does not fall (a shadow on the floor?)";
  } else if (st.down_angle_deg > o.max_down_angle_deg) {
    c.verdict = CandidateVerdict::kNotDown;
    c.reason = "it accelerates " + Num(st.down_angle_deg) +
               " deg away from the image's down: it does not fall";
  } else {
    c.verdict = CandidateVerdict::kBody;
    c.score = st.on_arcs * std::max(1.0, c.likeness);
    c.reason = std::to_string(st.arcs) + " arc(s), " + std::to_string(st.on_arcs) + " of " +
               std::to_string(st.in_span) + " frames on them within " + Num(st.rms) + " px" +
               (st.trimmed > 0 ? ", " + std::to_string(st.trimmed) +
                                     " frames off them beside contacts (a long contact)"
                               : std::string());
  }
}

/// Whether the regions of `path` are discs, motion blur allowed for: in each region, the extent
/// across its motion (4 sigma of its pixels: a disc's diameter) and the extra length along it,
/// sqrt(12 (sigma_along^2 - sigma_across^2)), which a smear during the exposure explains up to the
/// distance moved between frames. An elongated outline has more, moving or not. Round when at
/// least 60 % of its regions are.
bool IsRound(const tracking::MotionPath& path) {
  const auto& r = path.regions;
  if (r.empty()) return false;
  int round = 0;
  for (std::size_t k = 0; k < r.size(); ++k) {
    const auto& a = r[k > 0 ? k - 1 : k];
    const auto& b = r[k + 1 < r.size() ? k + 1 : k];
    const Eigen::Vector2d v = (b.p_I - a.p_I) / std::max(1, b.frame - a.frame);
    const double step = v.norm();
    Eigen::Vector2d u(1, 0);
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(r[k].moments);
    // Along the motion where it moves; else along its longest axis.
    u = step > 0.5 ? Eigen::Vector2d(v / step) : Eigen::Vector2d(es.eigenvectors().col(1));
    const Eigen::Vector2d n(-u.y(), u.x());
    const double along = u.dot(r[k].moments * u), across = n.dot(r[k].moments * n);
    const double diameter = 4 * std::sqrt(std::max(0.0, across));
    const double extra = std::sqrt(std::max(0.0, 12 * (along - across)));
    if (extra <= step + 0.3 * diameter + 1.0 && along * 9 >= across) ++round;
  }
  return round >= 0.6 * static_cast<double>(r.size());
}

/// `path` without its regions outside frames [first, last].
tracking::MotionPath Trimmed(const tracking::MotionPath& path, int first, int last) {
  tracking::MotionPath out;
  for (const auto& r : path.regions)
    if (r.frame >= first && r.frame <= last) out.regions.push_back(r);
  return out;
}

/// `a` and `b` as one path, in frame order; nullopt when they share a frame.
std::optional<tracking::MotionPath> Union(const tracking::MotionPath& a,
                                          const tracking::MotionPath& b) {
  tracking::MotionPath out;
  out.regions = a.regions;
  out.regions.insert(out.regions.end(), b.regions.begin(), b.regions.end());
  std::sort(out.regions.begin(), out.regions.end(),
            [](const auto& x, const auto& y) { return x.frame < y.frame; });
  for (std::size_t i = 1; i < out.regions.size(); ++i)
    if (out.regions[i].frame == out.regions[i - 1].frame) return std::nullopt;
  return out;
}

}  // namespace

const char* CandidateVerdictName(CandidateVerdict verdict) {
  switch (verdict) {
    case CandidateVerdict::kBody:
      return "body";
    case CandidateVerdict::kJoined:
      return "joined";
    case CandidateVerdict::kTooShort:
      return "too_short";
    case CandidateVerdict::kStill:
      return "still";
    case CandidateVerdict::kNoFall:
      return "no_fall";
    case CandidateVerdict::kNotBallistic:
      return "not_ballistic";
    case CandidateVerdict::kNotDown:
      return "not_down";
    case CandidateVerdict::kNotLikeBody:
      return "not_like_body";
    case CandidateVerdict::kLessLikely:
      return "less_likely";
  }
  return "?";
}

void MovingBodyOptions::Validate() const {
  auto fail = [](const std::string& field, const std::string& rule) {
    throw std::invalid_argument("MovingBodyOptions." + field + " " + rule);
  };
  if (!(max_colour_distance > 0)) fail("max_colour_distance", "must be > 0");
  if (!(diameter_px >= 0)) fail("diameter_px", "must be >= 0");
  if (!(max_size_ratio > 1)) fail("max_size_ratio", "must be > 1");
  if (min_frames < 4) fail("min_frames", "must be >= 4");
  if (!(min_travel_diameters > 0)) fail("min_travel_diameters", "must be > 0");
  if (!(min_arc_fraction > 0 && min_arc_fraction <= 1))
    fail("min_arc_fraction", "must be in (0, 1]");
  if (!(min_rms_px > 0)) fail("min_rms_px", "must be > 0");
  if (!(max_rms_diameters > 0)) fail("max_rms_diameters", "must be > 0");
  if (!(min_a_sigmas > 0)) fail("min_a_sigmas", "must be > 0");
  if (!(max_down_angle_deg > 0 && max_down_angle_deg <= 180))
    fail("max_down_angle_deg", "must be in (0, 180]");
  if (!(depth_warning_fraction > 0)) fail("depth_warning_fraction", "must be > 0");
  motion.Validate();
  silhouette.Validate();
}

std::string ColourHex(const Eigen::Vector3d& rgb) {
  char buf[8];
  auto c = [](double v) { return static_cast<int>(std::lround(std::clamp(v, 0.0, 255.0))); };
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", c(rgb[0]), c(rgb[1]), c(rgb[2]));
  return buf;
}

Eigen::Vector3d ParseColour(const std::string& text) {
  static const std::map<std::string, Eigen::Vector3d> names = {
      {"red", {200, 30, 40}},     {"green", {40, 160, 60}},   {"blue", {40, 70, 190}},
      {"yellow", {230, 210, 40}}, {"orange", {240, 130, 30}}, {"white", {240, 240, 240}},
      {"black", {20, 20, 20}},    {"pink", {240, 120, 170}},  {"purple", {120, 50, 150}}};
  std::string t = text;
  std::transform(t.begin(), t.end(), t.begin(), [](unsigned char c) { return std::tolower(c); });
  if (const auto it = names.find(t); it != names.end()) return it->second;
  if (!t.empty() && t[0] == '#') t = t.substr(1);
  if (t.size() == 6 && t.find_first_not_of("0123456789abcdef") == std::string::npos)
    return {static_cast<double>(std::stoi(t.substr(0, 2), nullptr, 16)),
            static_cast<double>(std::stoi(t.substr(2, 2), nullptr, 16)),
            static_cast<double>(std::stoi(t.substr(4, 2), nullptr, 16))};
  throw std::invalid_argument("\"" + text +
                              "\" is not a colour: give #rrggbb or one of red, green, blue, "
                              "yellow, orange, white, black, pink, purple");
}

MovingBody FindMovingBody(tracking::MotionScene scene, double fps, const std::string& named,
                          const MovingBodyOptions& options) {
  options.Validate();
  if (!(fps > 0)) throw std::invalid_argument("FindMovingBody: fps must be > 0");
  MovingBody out;
  out.scene = std::move(scene);
  const auto& paths = out.scene.paths;
  if (paths.empty()) {
    out.message = named +
                  ": no moving body: nothing differs from the clip's background in any "
                  "frame";
    return out;
  }
  std::vector<ArcStats> stats;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    const auto& p = paths[i];
    if (static_cast<int>(p.regions.size()) < 2) continue;  // a speck: not listed
    MovingCandidate c;
    c.path = static_cast<int>(i);
    c.first_frame = p.first_frame();
    c.last_frame = p.last_frame();
    c.regions = static_cast<int>(p.regions.size());
    c.p_first_I = p.regions.front().p_I;
    c.p_last_I = p.regions.back().p_I;
    c.travel_px = p.Travel();
    c.diameter_px = p.MedianDiameter();
    c.likeness = p.MedianLikeness();
    c.rgb = p.MedianRgb();
    const double limit = RmsLimit(p, options);
    const ArcStats st = c.regions >= options.min_frames
                            ? Ballistic(PositionsOf(p), fps, limit, options.min_frames)
                            : ArcStats{};

    Judge(c, st, options, limit);
    out.candidates.push_back(c);
    stats.push_back(st);
  }
  // The body: the ballistic path with the most frames on arcs, weighted by its contrast.
  int best = -1;
  for (std::size_t i = 0; i < out.candidates.size(); ++i)
    if (out.candidates[i].verdict == CandidateVerdict::kBody &&
        (best < 0 ||
         out.candidates[i].score > out.candidates[static_cast<std::size_t>(best)].score))
      best = static_cast<int>(i);
  if (best < 0) {
    // Smooth paths not seen to fall: the body when nothing else is (a slow-motion clip).
    for (std::size_t i = 0; i < out.candidates.size(); ++i)
      if (out.candidates[i].verdict == CandidateVerdict::kNoFall &&
          IsRound(paths[static_cast<std::size_t>(out.candidates[i].path)]) &&
          (best < 0 ||
           out.candidates[i].score > out.candidates[static_cast<std::size_t>(best)].score))
        best = static_cast<int>(i);
    if (best >= 0) {
      MovingCandidate& c = out.candidates[static_cast<std::size_t>(best)];
      c.verdict = CandidateVerdict::kBody;
      out.warnings.push_back(
          "the body's path (frames " + std::to_string(c.first_frame) + "-" +
          std::to_string(c.last_frame) + ") is smooth, but gravity does not bend it measurably (" +
          c.reason +
          "): taken as the body, as nothing else moving is; a slow-motion clip's time base "
          "makes gravity look small (--fps)");
      c.reason = "smooth, no fall measured: " + c.reason;
    }
  }
  if (best < 0) {
    bool any_long = false;
    for (const auto& c : out.candidates) any_long |= c.verdict != CandidateVerdict::kTooShort;
    std::ostringstream os;
    os << named << ": "
       << (out.candidates.empty() ? "no moving body: nothing moving is seen in more than one frame"
           : !any_long            ? "no moving path with enough frames to test its motion"
                                  : "no moving path is ballistic (arcs of one acceleration)");
    int listed = 0;
    for (const auto& c : out.candidates) {
      if (listed++ == 4) break;
      os << (listed == 1 ? ": " : "; ") << "frames " << c.first_frame << "-" << c.last_frame
         << " near (" << std::lround(c.p_first_I.x()) << ", " << std::lround(c.p_first_I.y())
         << ") px " << c.reason;
    }
    out.message = os.str();
    return out;
  }
  for (auto& c : out.candidates)
    if (c.verdict == CandidateVerdict::kBody &&
        &c != &out.candidates[static_cast<std::size_t>(best)]) {
      c.verdict = CandidateVerdict::kLessLikely;
      c.reason = "ballistic too (" + c.reason + "), but the body's path explains more";
    }
  MovingCandidate& body = out.candidates[static_cast<std::size_t>(best)];
  tracking::MotionPath path = paths[static_cast<std::size_t>(body.path)];
  ArcStats body_stats = stats[static_cast<std::size_t>(best)];

  // Pieces of the same body: alike in size and colour, sharing no frame, and the whole still
  // ballistic with more frames on its arcs.
  std::vector<std::size_t> order(out.candidates.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return out.candidates[a].regions > out.candidates[b].regions;
  });
  for (std::size_t i : order) {
    MovingCandidate& c = out.candidates[i];
    if (static_cast<int>(i) == best || c.verdict == CandidateVerdict::kStill) continue;
    const double ratio = c.diameter_px / body.diameter_px;
    if (ratio > 1.5 || ratio < 1 / 1.5 || (c.rgb - body.rgb).norm() > 60) continue;
    const auto joined = Union(path, paths[static_cast<std::size_t>(c.path)]);
    if (!joined) continue;
    const double rms_limit = RmsLimit(*joined, options);
    const ArcStats st = Ballistic(PositionsOf(*joined), fps, rms_limit, options.min_frames);
    if (!st.fitted || st.on_arcs <= body_stats.on_arcs ||
        st.arc_fraction < options.min_arc_fraction || !(st.rms <= rms_limit))
      continue;
    path = *joined;
    body_stats = st;
    c.verdict = CandidateVerdict::kJoined;
    c.reason =
        "a piece of the body's path: joined, " + std::to_string(st.on_arcs) + " frames on its arcs";
  }

  // The flight: from the first arc's first frame on (a hand that holds the ball before it is
  // left out; the arc fit of the measured centres below, and track's, judge the frames after).
  const tracking::MotionPath flight = Trimmed(path, body_stats.first_arc_frame, path.last_frame());
  out.path = flight;
  out.rgb = flight.MedianRgb();
  out.round = IsRound(flight);
  out.track = tracking::MeasureBallPath(flight, out.scene.frame_count, options.silhouette);
  if (body_stats.first_arc_frame > path.first_frame())
    for (int f = path.first_frame(); f < body_stats.first_arc_frame; ++f)
      out.track.frames[static_cast<std::size_t>(f)].status =
          "before the first flight arc (held, or not yet falling)";

  // The arcs of the measured centres, and "down" from them.
  Positions measured;
  measured.first = flight.first_frame();
  const int span = flight.last_frame() - flight.first_frame() + 1;
  measured.p.resize(static_cast<std::size_t>(span));
  measured.cov.assign(static_cast<std::size_t>(span), Eigen::Matrix2d::Identity());
  measured.size.assign(static_cast<std::size_t>(span), core::kNaN);
  std::vector<double> diameters;
  int found = 0;
  for (int f = flight.first_frame(); f <= flight.last_frame(); ++f) {
    const auto& o = out.track.frames[static_cast<std::size_t>(f)];
    if (!o.found) continue;
    const auto i = static_cast<std::size_t>(f - measured.first);
    measured.p[i] = o.p_I;
    measured.cov[i] = o.cov_p_I;
    measured.size[i] = o.diameter_px;
    diameters.push_back(o.diameter_px);
    ++found;
  }
  out.diameter_px = MedianOf(diameters);
  if (found < options.min_frames) {
    out.message = named + ": the body moving in frames " + std::to_string(flight.first_frame()) +
                  "-" + std::to_string(flight.last_frame()) + " was measured in only " +
                  std::to_string(found) + " of them (its edge was not fitted)";
    return out;
  }
  // Frames without a covariance (zero) would unweight the fit: fall back to equal weights.
  bool all_cov = true;
  for (std::size_t i = 0; i < measured.p.size(); ++i)
    if (measured.p[i] && !(measured.cov[i].trace() > 0)) all_cov = false;
  if (!all_cov) measured.cov.clear();
  const ArcStats fine = FitArcs(measured, fps, RmsLimit(flight, options));
  out.arcs = fine.fit;
  if (fine.fitted && fine.fit.roll_se_deg <= 1.0 && fine.fit.a_norm > 0) {
    out.down_I = Eigen::Vector2d(fine.fit.a_W.x(), -fine.fit.a_W.y()).normalized();
    out.down_measured = true;
    out.down_se_deg = fine.fit.roll_se_deg;
  }
  // Depth: the apparent size of the first and the last arc.
  if (fine.fitted) {
    std::vector<double> first_arc, last_arc;
    const kinematics::FlightArc* a0 = nullptr;
    const kinematics::FlightArc* a1 = nullptr;
    for (const auto& a : fine.fit.arcs)
      if (a.fitted) {
        if (!a0) a0 = &a;
        a1 = &a;
      }
    if (a0 && a1 && a0 != a1) {
      for (int f = a0->first_frame; f <= a0->last_frame; ++f)
        if (std::isfinite(measured.size[static_cast<std::size_t>(f)]))
          first_arc.push_back(measured.size[static_cast<std::size_t>(f)]);
      for (int f = a1->first_frame; f <= a1->last_frame; ++f)
        if (std::isfinite(measured.size[static_cast<std::size_t>(f)]))
          last_arc.push_back(measured.size[static_cast<std::size_t>(f)]);
      const double d0 = MedianOf(first_arc), d1 = MedianOf(last_arc);
      if (std::abs(d1 / d0 - 1) > options.depth_warning_fraction)
        out.warnings.push_back("the ball's apparent size changes from " + Num(d0) + " px to " +
                               Num(d1) +
                               " px between its first and its last arc: it moves in "
                               "depth, which biases e (see each impact's depth shift)");
    }
  }
  out.found = true;
  // The body first in the list.
  std::stable_sort(out.candidates.begin(), out.candidates.end(),
                   [](const MovingCandidate& a, const MovingCandidate& b) {
                     return (a.verdict == CandidateVerdict::kBody) >
                            (b.verdict == CandidateVerdict::kBody);
                   });
  return out;
}

}  // namespace hoof::pipeline
