#include "tracking/marker_tracker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "tracking/pose.h"

namespace hoof::tracking {
namespace {

/// Identity of first-frame dots: the assignment of dots to layout markers whose similarity fit
/// has the smallest residual, among those whose x_B axis points against gravity.
std::vector<int> AssignIdentities(const std::vector<Dot>& dots,
                                  const std::vector<Eigen::Vector2d>& layout_px,
                                  const Eigen::Vector2d& up_I, double tolerance,
                                  const std::string& where) {
  const int n = static_cast<int>(layout_px.size());
  std::vector<int> perm(dots.size());
  std::iota(perm.begin(), perm.end(), 0);
  double best = std::numeric_limits<double>::infinity();
  std::vector<int> best_perm;
  double scale_at_best = 1.0;
  do {
    std::vector<Eigen::Vector2d> measured;
    for (int i = 0; i < n; ++i)
      measured.push_back(dots[static_cast<std::size_t>(perm[static_cast<std::size_t>(i)])].p_I);
    const RigidFit fit = FitRigid2D(layout_px, measured, /*allow_scale=*/true);
    // Image frame has y down: the body x axis in the image is the fit's rotation of (1, 0).
    const Eigen::Vector2d x_axis_I = fit.rotation.col(0);
    if (x_axis_I.dot(up_I) <= 0.0) continue;
    if (fit.rms_residual < best) {
      best = fit.rms_residual;
      best_perm.assign(perm.begin(), perm.begin() + n);
      scale_at_best = fit.scale;
    }
  } while (std::next_permutation(perm.begin(), perm.end()));
  if (best_perm.empty())
    throw std::runtime_error(where +
                             ": cannot match the markers to the layout (no assignment "
                             "puts the round end below the centre of mass)");
  // Compare distances: the scale of the best similarity fit says how well m_per_px and the
  // layout agree with what is seen.
  if (std::abs(scale_at_best - 1.0) > tolerance) {
    std::ostringstream os;
    os << where << ": the marker layout does not match the image: marker distances are "
       << scale_at_best << " times those the layout and camera.m_per_px predict";
    throw std::runtime_error(os.str());
  }
  double span = 0;
  for (const auto& p : layout_px) span = std::max(span, (p - layout_px.front()).norm());
  if (best > tolerance * span) {
    std::ostringstream os;
    os << where << ": the marker layout does not match the image (rms misfit " << best
       << " px for markers " << span << " px apart)";
    throw std::runtime_error(os.str());
  }
  return best_perm;
}

}  // namespace

void TrackerOptions::Validate() const {
  detector.Validate();
  if (search_radius_px < 0) throw std::invalid_argument("tracker search_radius_px must be >= 0");
  if (max_consecutive_misses < 1)
    throw std::invalid_argument("tracker max_consecutive_misses must be >= 1");
  if (!(layout_tolerance > 0 && layout_tolerance < 1))
    throw std::invalid_argument("tracker layout_tolerance must be in (0, 1)");
}

namespace {

/// What the tracker keeps of one marker between frames.
struct MarkerState {
  std::vector<Eigen::Vector2d> history;  ///< centres where found, in order
  int misses = 0;                        ///< consecutive frames not found
  double radius_px = 0.0;                ///< dot radius in the first frame
};

/// The first frame's dots, one per layout marker in layout order: the n most significant dots
/// given identities from the layout, else all candidates. Errors name the frame.
std::vector<Dot> IdentifyFirstFrame(FrameSource& source, const cv::Mat& first,
                                    const std::vector<Eigen::Vector2d>& layout_px,
                                    const Eigen::Vector2d& up_I, const TrackerOptions& options) {
  const int n = static_cast<int>(layout_px.size());
  const std::vector<Dot> found = FindDots(first, n + 2, options.detector);
  if (static_cast<int>(found.size()) < n) {
    std::ostringstream os;
    os << source.Describe(0) << ": found " << found.size() << " marker(s) (white dots on black "
       << "patches), the layout needs " << n;
    throw std::runtime_error(os.str());
  }
  // Try the n most significant first; if they do not fit the layout, all candidates.
  std::vector<Dot> candidates(found.begin(), found.begin() + n);
  std::vector<int> ids;
  try {
    ids =
        AssignIdentities(candidates, layout_px, up_I, options.layout_tolerance, source.Describe(0));
  } catch (const std::runtime_error&) {
    if (static_cast<int>(found.size()) == n) throw;
    candidates = found;
    ids =
        AssignIdentities(candidates, layout_px, up_I, options.layout_tolerance, source.Describe(0));
  }
  std::vector<Dot> ordered;
  for (int id : ids) ordered.push_back(candidates[static_cast<std::size_t>(id)]);
  return ordered;
}

/// Looks for one marker in `frame` near where its track predicts it (constant velocity from the
/// last two centres, over the frames since it was last found). Returns the dot, or nothing.
std::optional<Dot> FindMarker(const cv::Mat& frame, const MarkerState& m,
                              const TrackerOptions& options) {
  const auto& h = m.history;
  const std::size_t k = h.size();
  const int gap = m.misses + 1;  // frames since the last find
  Eigen::Vector2d predicted = h.back();
  Eigen::Vector2d step = Eigen::Vector2d::Zero();
  if (k >= 2) step = h[k - 1] - h[k - 2];
  predicted += gap * step;
  const double search = options.search_radius_px > 0
                            ? options.search_radius_px
                            : std::max(6.0, 0.5 * m.radius_px + 3.0 * step.norm() * gap);
  return FindDotNear(frame, predicted, search, m.radius_px, options.detector);
}

/// Two markers on one dot: records both as merged, keeps neither (and drops the centre each
/// added to its history in this frame).
void MarkMerged(std::vector<MarkerObservation>& row, std::vector<MarkerState>& markers,
                const std::string& frame, MarkerTracks& tracks) {
  const std::size_t n = row.size();
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = a + 1; b < n; ++b) {
      auto& oa = row[a];
      auto& ob = row[b];
      if (oa.found && ob.found && (oa.p_I - ob.p_I).norm() < 0.5 * (oa.radius_px + ob.radius_px)) {
        oa.found = ob.found = false;
        oa.status = ob.status = "merged";
        markers[a].history.pop_back();
        markers[b].history.pop_back();
        tracks.warnings.push_back(frame + ": markers " + tracks.names[a] + " and " +
                                  tracks.names[b] + " merged");
      }
    }
}

}  // namespace

MarkerTracks TrackMarkers(FrameSource& source,
                          const std::vector<std::pair<std::string, Eigen::Vector2d>>& layout_B_m,
                          double m_per_px, const Eigen::Vector2d& gravity_I,
                          const TrackerOptions& options, const std::function<void(int)>& progress) {
  options.Validate();
  const std::size_t n = layout_B_m.size();
  if (n < 2) throw std::invalid_argument("the marker layout needs two or more markers");
  MarkerTracks tracks;
  std::vector<Eigen::Vector2d> layout_px;
  for (const auto& [name, p] : layout_B_m) {
    tracks.names.push_back(name);
    // Body frame (y up, like W) to image scale with y down.
    layout_px.emplace_back(p.x() / m_per_px, -p.y() / m_per_px);
  }

  // First frame: the n most significant dots, then identities from the layout.
  const std::vector<Dot> first =
      IdentifyFirstFrame(source, source.Read(0), layout_px, -gravity_I.normalized(), options);
  std::vector<MarkerState> markers(n);
  // One row per frame as it is read (not `count` rows up front: a count of 2e9 would be
  // allocated before its first missing frame is found).
  tracks.frames.emplace_back();
  for (std::size_t m = 0; m < n; ++m) {
    const Dot& d = first[m];
    tracks.frames[0].push_back({true, d.p_I, d.significance, d.radius_px, "ok"});
    markers[m].history.push_back(d.p_I);
    markers[m].radius_px = d.radius_px;
  }
  if (progress) progress(0);

  for (int f = 1; f < source.count(); ++f) {
    const cv::Mat frame = source.Read(f);
    auto& row = tracks.frames.emplace_back();
    row.resize(n);
    for (std::size_t m = 0; m < n; ++m) {
      MarkerState& state = markers[m];
      auto& obs = row[m];
      if (state.misses >= options.max_consecutive_misses) {
        obs.status = "lost_for_good";
        continue;
      }
      const auto dot = FindMarker(frame, state, options);
      if (!dot) {
        obs.status = "lost";
        ++state.misses;
        tracks.warnings.push_back(source.Describe(f) + ": marker " + tracks.names[m] +
                                  " not found near its predicted position");
        continue;
      }
      obs = {true, dot->p_I, dot->significance, dot->radius_px, "ok"};
      state.misses = 0;
      state.history.push_back(dot->p_I);
    }
    MarkMerged(row, markers, source.Describe(f), tracks);
    if (progress) progress(f);
  }
  return tracks;
}

}  // namespace hoof::tracking
