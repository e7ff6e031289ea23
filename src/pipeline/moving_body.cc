#include "pipeline/moving_body.h"

#include "pipeline/ballistic_path.h"

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

using ballistic::ArcStats;
using ballistic::Ballistic;
using ballistic::CopiesOn;
using ballistic::FitArcs;
using ballistic::Positions;
using ballistic::PositionsOf;

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
    const ArcStats st =
        c.regions >= options.min_frames
            ? Ballistic(PositionsOf(p, CopiesOn(p, out.scene.repeat, out.scene.frame_count)), fps,
                        limit, options.min_frames)
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
    const ArcStats st =
        Ballistic(PositionsOf(*joined, CopiesOn(*joined, out.scene.repeat, out.scene.frame_count)),
                  fps, rms_limit, options.min_frames);
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
  out.copies = CopiesOn(flight, out.scene.repeat, out.scene.frame_count);
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
    if (!o.found || out.copies[static_cast<std::size_t>(f)]) continue;
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
