#pragma once
/// @file
/// Tracking the markers through a sequence: identity from the known layout in the first frame,
/// then a predicted search window per marker per frame. A marker that is not found, or that
/// merges with another, is recorded as such and never invented.

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "tracking/dot_detector.h"
#include "tracking/frame_source.h"

namespace hoof::tracking {

/// Settings of the tracker.
struct TrackerOptions {
  DotDetectorOptions detector;
  /// Search radius around the prediction (px); 0 = automatic: half a dot radius plus three
  /// times the last frame-to-frame displacement, at least 6 px (the velocity reverses at the
  /// impact, so a prediction can miss by two displacements there).
  double search_radius_px = 0.0;
  /// A marker missing for this many consecutive frames is lost for good; >= 1.
  int max_consecutive_misses = 4;
  /// Largest relative mismatch between the measured and the layout's marker distances in the
  /// first frame before the layout is rejected; in (0, 1).
  double layout_tolerance = 0.15;

  void Validate() const;
};

/// Per frame and marker: what was measured.
struct MarkerObservation {
  bool found = false;
  Eigen::Vector2d p_I{0.0, 0.0};  ///< Sub-pixel centre (px), when found.
  double quality = 0.0;           ///< Significance (contrast / noise); 0 when not found.
  double radius_px = 0.0;
  std::string status;  ///< "ok", "lost", "merged", "lost_for_good"
};

/// Marker tracks of one sequence.
struct MarkerTracks {
  std::vector<std::string> names;                      ///< Marker names, layout order.
  std::vector<std::vector<MarkerObservation>> frames;  ///< [frame][marker]
  std::vector<std::string> warnings;                   ///< Lost or merged markers, per frame.
  int frame_count() const { return static_cast<int>(frames.size()); }
};

/// Tracks the markers of `layout_B_m` (name, position in the body frame in metres) through
/// `source`. `m_per_px` gives the layout's size in the image. `gravity_I` (unit, image frame)
/// resolves the identity of collinear markers: the specimen is dropped with its long axis
/// vertical and the round end first, so x_B (from E toward C) points against gravity in the
/// first frame. `progress(i)` is called after each frame when given.
/// Throws std::runtime_error naming the frame source for: an unreadable frame, too few markers
/// in the first frame, or a layout that does not match what is seen.
MarkerTracks TrackMarkers(FrameSource& source,
                          const std::vector<std::pair<std::string, Eigen::Vector2d>>& layout_B_m,
                          double m_per_px, const Eigen::Vector2d& gravity_I,
                          const TrackerOptions& options = {},
                          const std::function<void(int)>& progress = {});

}  // namespace hoof::tracking
