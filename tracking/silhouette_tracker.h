#pragma once
/// @file
/// Tracking a body without markers by its silhouette (docs/tracking.md, "Bodies without
/// markers"): a ball (a disc in the image) or an unmarked specimen's outline (elongated), bright
/// on dark or dark on bright, back-lit included. Per frame: a sub-pixel centre, an orientation
/// where the outline has one, and an uncertainty from the fit's own residuals.
///
/// Nothing is normalised to an assumed full scale: the levels come from the data (percentiles
/// of the frame for finding the body; for the sub-pixel work, a ball's levels along each ray
/// just inside and just outside its edge, an outline's medians just inside and just outside),
/// so 8-bit frames and 16-bit frames holding 12-bit values are measured alike.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "tracking/ball_spin.h"
#include "tracking/frame_source.h"

namespace hoof::tracking {

/// What the silhouette is.
enum class SilhouetteShape {
  kBall,     ///< a disc: centre and diameter; no orientation (a ball's rotation is not seen)
  kOutline,  ///< an elongated body: centroid and principal axis
};

/// Which side of the edge is the body.
enum class Polarity {
  kAuto,          ///< found in the first frame where a body is found
  kDarkOnBright,  ///< e.g. back-lit
  kBrightOnDark,
};

/// "dark_on_bright", "bright_on_dark" or "auto".
std::string PolarityName(Polarity polarity);

/// Settings of the silhouette tracker.
struct SilhouetteOptions {
  SilhouetteShape shape = SilhouetteShape::kBall;
  Polarity polarity = Polarity::kAuto;
  /// Smallest body area to consider when finding it (px^2); > 0.
  double min_area_px = 50.0;
  /// A body counts only when its contrast with its surround exceeds this many noise standard
  /// deviations (the statistical rule of the dot detector); > 0.
  double min_significance = 8.0;
  /// Ball: an edge point whose distance from the fitted circle exceeds this many robust
  /// standard deviations of all the points (and at least `min_outlier_px`) is rejected; > 0.
  double outlier_sigmas = 3.5;
  double min_outlier_px = 0.05;
  /// Unit gravity direction in the image; orients an outline's axis: the specimen is dropped
  /// round end first, so its x_B (from the round end toward the centre of mass) points against
  /// gravity in the first frame, and turns continuously after it.
  Eigen::Vector2d gravity_I{0.0, 1.0};
  /// TrackSilhouette: frames read ahead of the tracker on a thread of its own, so reading the
  /// next frames overlaps measuring this one (docs/performance.md, "Silhouette tracking"); 0
  /// reads on the calling thread. The track is the same whatever the value: the frames are
  /// measured one after the other, in order, on the calling thread. >= 0.
  int read_ahead_frames = 2;
  /// Ball: sample its face in every frame where its edge is fitted (SilhouetteObservation::face),
  /// from which its spin is measured (tracking/ball_spin.h).
  bool sample_faces = false;
  BallSpinOptions spin;  ///< how the faces are sampled

  /// Throws std::invalid_argument naming the field.
  void Validate() const;
};

/// One frame's measurement.
struct SilhouetteObservation {
  bool found = false;
  std::string status;             ///< "ok", "lost" (not found) or the reason
  Eigen::Vector2d p_I{0.0, 0.0};  ///< centre (ball) or centroid (outline), px
  /// Covariance of p_I (px^2), from the fit's residuals (ball) or the noise on the edge
  /// (outline).
  Eigen::Matrix2d cov_p_I = Eigen::Matrix2d::Zero();
  bool has_orientation = false;  ///< outline only
  double angle_I_rad = 0.0;      ///< direction of x_B in the image, atan2(y, x) with y down
  double angle_se_rad = 0.0;
  double diameter_px = 0.0;  ///< ball: fitted diameter; outline: 0
  double diameter_se_px = 0.0;
  double length_px = 0.0, width_px = 0.0;  ///< outline: extent along and across the axis
  int edge_points = 0;                     ///< ball: edge points used in the fit
  int edge_points_rejected = 0;            ///< ball: rejected as outliers (shadow, glare, surface)
  double rms_residual_px = 0.0;            ///< ball: of the inliers about the circle
  double contrast = 0.0;                   ///< body minus surround level (frame units, signed)
  double noise = 0.0;                      ///< noise s.d. near the edge (frame units)
  /// Ball, with SilhouetteOptions::sample_faces: its face about the fitted centre, in frame
  /// coordinates; not sampled where the centre stands in for a failed edge fit.
  std::optional<BallFace> face;
};

/// A sequence's silhouette track.
struct SilhouetteTrack {
  Polarity polarity = Polarity::kAuto;  ///< the polarity used (found or given)
  std::vector<SilhouetteObservation> frames;
  std::vector<std::string> warnings;
  int frame_count() const { return static_cast<int>(frames.size()); }
};

/// Finds the body in a whole frame (single channel, any depth): the largest region of one
/// polarity, holes filled, not touching the frame's border, of at least `min_area_px` and
/// significantly different from its surround; for a ball the roundest such region. Then
/// measures it to sub-pixel accuracy. `found` is false when there is no such region.
SilhouetteObservation FindSilhouette(const cv::Mat& grey, const SilhouetteOptions& options,
                                     Polarity* polarity_found = nullptr);

/// Measures the body near a predicted position (`predicted_I`, with the previous frame's size:
/// `previous`) with the polarity known. `search_px` bounds how far the edge may lie from the
/// prediction. Looks only at a window around it.
SilhouetteObservation MeasureSilhouetteNear(const cv::Mat& grey, const SilhouetteOptions& options,
                                            Polarity polarity, const Eigen::Vector2d& predicted_I,
                                            const SilhouetteObservation& previous,
                                            double search_px);

/// Tracks the body through `source`: found in the first frame that shows it, then measured
/// near its prediction from the last two frames (found afresh when that fails). Throws
/// std::runtime_error naming the source when no frame shows a body. With
/// `options.read_ahead_frames` > 0, `source.Read` is called from a second thread (one call at a
/// time, in frame order) while `source.Describe` and `progress` are called from this one; an
/// error reading a frame is rethrown here when the tracker reaches that frame.
SilhouetteTrack TrackSilhouette(FrameSource& source, const SilhouetteOptions& options = {},
                                const std::function<void(int)>& progress = {});

/// Low and high levels of a frame from its own values (the 0.5th and 99.5th percentiles), in
/// the frame's units: a 16-bit frame holding 12-bit values gives levels within 0..4095.
std::pair<double, double> FrameLevels(const cv::Mat& grey);

}  // namespace hoof::tracking
