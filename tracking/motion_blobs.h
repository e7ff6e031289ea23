#pragma once
/// @file
/// What moves in a clip (docs/tracking.md, "Finding the body by its motion"): a background
/// model made from the clip itself (the per-pixel temporal median of frames spread over it),
/// the regions of each frame that differ from it, and those regions linked from frame to frame
/// into paths. Which path is the body is judged elsewhere, from its motion
/// (pipeline/moving_body.h); here a chosen path is then measured to sub-pixel accuracy.
///
/// A region differs from the background by its colour distortion: the distance of the pixel's
/// colour from the background's, scaled by the brightness ratio between them (clamped to
/// kShadowGain). A shadow darkens the background in proportion and keeps its hue, so it barely
/// shows; a coloured ball, a dark one or a bright one does.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "tracking/frame_source.h"
#include "tracking/frame_timing.h"
#include "tracking/silhouette_tracker.h"

namespace hoof::tracking {

/// The brightness ratios a shadow may have: within them a pixel's colour is compared with the
/// background's at the same ratio (a shadow scales the background's colour). Anything brighter
/// than the background counts in full: a white ball on a pale table, a hand on a wall.
inline constexpr double kShadowGainMin = 0.45, kShadowGainMax = 1.15;

/// Settings of the motion regions.
struct MotionOptions {
  /// The background is the median of up to this many frames spread evenly over the clip; in
  /// [3, 255].
  int background_frames = 41;
  /// Regions are found on frames scaled down to at most this width (px); >= 64.
  int work_width_px = 480;
  /// When > 0, FindMotion keeps every frame, grey and scaled to at most this many px on its
  /// longer side (ThumbnailSize), in MotionScene::thumbnails, for pictures of the clip that would
  /// otherwise read it again; only while they take at most 64 MiB in all (else none).
  int thumbnail_px = 0;
  /// The grid of the comparison of each frame with the one before (FrameDifferencer); >= 1.
  int timing_grid_pixels = FrameTimingOptions{}.max_grid_pixels;
  /// A pixel differs from the background when its likeness exceeds this many robust noise
  /// standard deviations of the frame's likeness (and `min_likeness`); > 0.
  double noise_sigmas = 6.0;
  double min_likeness = 24.0;  ///< 8-bit units of colour distance; > 0
  /// Smallest region kept, as a fraction of the working frame's area; in (0, 1).
  double min_area_fraction = 2e-5;
  /// At most this many regions per frame, the largest first; >= 1.
  int max_regions = 12;
  /// A region is linked to a path when it lies within this many of the path's sizes (its
  /// diameter) of the path's prediction, plus the distance moved since the frame before; > 0.
  double link_sizes = 2.5;
  /// ... and its size is within this factor of the path's; > 1.
  double link_size_ratio = 2.5;
  /// A path that has not been seen for more than this many frames ends; >= 0.
  int max_gap_frames = 3;

  /// Throws std::invalid_argument naming the field.
  void Validate() const;
};

/// The likeness image of `frame` against `background` (both 8-bit, 3 channels, one size): per
/// pixel, the colour distortion |I - g B| with g the brightness ratio I.B / B.B clamped to
/// kShadowGainMin..kShadowGainMax, in 8-bit units (saturating at 255). Bright where something
/// is that the background does not show.
cv::Mat Likeness(const cv::Mat& frame, const cv::Mat& background);

/// A frame as 8-bit BGR, whatever it was read as (grey, 16-bit, float or 4 channels): 16-bit
/// and float frames are scaled by their own levels (FrameLevels). Throws std::runtime_error
/// naming `what` for an empty or unsupported image.
cv::Mat ToBgr8(const cv::Mat& image, const std::string& what);

/// The background of `source`: the per-pixel median of `options.background_frames` frames
/// spread evenly over the clip (all frames when it has fewer), 8-bit BGR, full size. A body
/// that moves shows in fewer than half of them at any pixel, so it is not in the median; one
/// that holds still for half the clip is. `progress(frames_read)` is called as frames are read.
/// Throws std::runtime_error naming the frame that cannot be read.
cv::Mat MedianBackground(FrameSource& source, const MotionOptions& options = {},
                         const std::function<void(int)>& progress = {});

/// A region of one frame that differs from the background.
struct MotionRegion {
  int frame = -1;
  Eigen::Vector2d p_I{0, 0};  ///< its centroid (full-size px)
  double area_px = 0.0;       ///< full-size px^2
  double diameter_px = 0.0;   ///< of the disc of its area
  double fill = 0.0;          ///< area over its bounding box's (a disc: pi / 4)
  double aspect = 1.0;        ///< its bounding box's longer side over its shorter
  /// The second central moments of its pixels (full-size px^2): a disc of diameter D has D^2 / 16
  /// on both axes; motion blur adds L^2 / 12 along the motion, for a smear of length L.
  Eigen::Matrix2d moments = Eigen::Matrix2d::Zero();
  double likeness = 0.0;         ///< the mean likeness over it (8-bit units)
  Eigen::Vector3d rgb{0, 0, 0};  ///< its mean colour
  bool touches_border = false;
  /// The full-size frame around it (1.2 of its diameter plus 16 px on each side of its
  /// centroid, clipped to the frame) and the background's pixels there, kept for the sub-pixel
  /// measurement; empty for a region larger than a sixteenth of the frame, and dropped from a
  /// path that ends with fewer than 4 regions.
  cv::Rect crop;
  cv::Mat crop_bgr, crop_background;
};

/// Regions linked from frame to frame: one thing moving.
struct MotionPath {
  std::vector<MotionRegion> regions;  ///< in frame order, at most one per frame
  int first_frame() const { return regions.empty() ? -1 : regions.front().frame; }
  int last_frame() const { return regions.empty() ? -1 : regions.back().frame; }
  /// The largest distance between any of its centroids and its first one (px).
  double Travel() const;
  double MedianDiameter() const;
  Eigen::Vector3d MedianRgb() const;
  double MedianLikeness() const;
};

/// Everything that moves in a clip.
struct MotionScene {
  cv::Mat background;  ///< 8-bit BGR, full size
  int frame_count = 0;
  int width = 0, height = 0;
  double noise = 0.0;             ///< the median over frames of the likeness's robust noise s.d.
  std::vector<MotionPath> paths;  ///< the longest first
  /// Per frame: its image repeats the previous frame's (tracking/frame_timing.h, FindRepeats);
  /// which copy is the sample of the motion is each path's to tell (HeldImageFromMotion).
  std::vector<bool> repeat;
  /// The comparison of each frame with the one before, made while reading (the frame timing's:
  /// tracking/frame_timing.h), on the frames at the working size, their pixels as they are.
  ImageDifferences differences;
  /// Per frame, when MotionOptions::thumbnail_px asked for them: the frame, 8-bit grey, of
  /// ThumbnailSize(its size, thumbnail_px); else empty.
  std::vector<cv::Mat> thumbnails;
};

/// The size of a thumbnail of a `full`-size frame at most `longest_px` on its longer side (the
/// frame's own size where it is smaller), each side at least 1 px.
cv::Size ThumbnailSize(const cv::Size& full, int longest_px);

/// Finds the regions of every frame of `source` that differ from `background` and links them
/// into paths (nearest to the prediction from the path's last two regions, within the size
/// and distance gates of `options`), and compares each frame's image with the one before for
/// repeats. Reads each frame once, in order, a frame ahead on a thread of its own (ReadAhead);
/// `progress(frame)` is called after each. Throws std::runtime_error naming a frame that cannot be
/// read or whose size differs from the background's.
MotionScene FindMotion(FrameSource& source, const cv::Mat& background,
                       const MotionOptions& options = {},
                       const std::function<void(int)>& progress = {});

/// Measures a ball along `path` to sub-pixel accuracy: in each region's crop, the circle fitted
/// to the edge of its likeness (MeasureSilhouetteNear, bright on dark), near the region's
/// centroid. Where that fit fails, or lies a quarter of the ball's diameter off the region's
/// centroid or a third off its size (an edge of something else: a net behind it, its stripes
/// smeared by motion blur), the region's centroid stands in, with a standard deviation of 5 %
/// of the diameter (its status says so). One observation per frame of the clip
/// (`frame_count`); frames outside the path, or cut by the frame's edge where the fit fails,
/// are not found (their status says why).
SilhouetteTrack MeasureBallPath(const MotionPath& path, int frame_count,
                                const SilhouetteOptions& options = {});

}  // namespace hoof::tracking
