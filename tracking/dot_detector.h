#pragma once
/// @file
/// Finding the markers: white dots on black patches, located to a fraction of a pixel.
///
/// No intensity threshold is set by hand. A dot is a bright disk on a dark surround; the
/// detector scores "mean inside minus mean of the surrounding ring" at a few scales, and a dot
/// counts only when its contrast is many times the image noise (a statistical rule). Its levels
/// (dot and patch) are measured around each dot, and the centre comes from one of two
/// sub-pixel methods, compared on synthetic trials in docs/tracking.md:
/// - an intensity-weighted centroid with weights (I - dark) / (bright - dark) clipped to [0, 1]
///   in a disk re-centred a few times: for an anti-aliased disk the weight is its coverage, so
///   the centroid is the disk's centre; symmetric blur (defocus, constant-velocity motion) and
///   noise leave it unbiased;
/// - an ellipse fitted to sub-pixel crossings of the mid level along 64 rays.

#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace hoof::tracking {

/// How a dot's sub-pixel centre is computed.
enum class CentreMethod { kWeightedCentroid, kEllipseFit };

/// Settings of the dot detector.
struct DotDetectorOptions {
  CentreMethod method = CentreMethod::kWeightedCentroid;
  /// A dot counts only when (bright - dark) exceeds this many noise standard deviations; > 0.
  double min_significance = 8.0;
  /// Re-centring passes of the weighted centroid; >= 1.
  int centroid_iterations = 3;
  /// Smallest and largest dot radius the full-frame search considers (px); 1 < min < max.
  double min_radius_px = 2.5;
  double max_radius_px = 40.0;

  /// Throws std::invalid_argument naming the field.
  void Validate() const;
};

/// One dot found in an image.
struct Dot {
  Eigen::Vector2d p_I{0.0, 0.0};  ///< Centre in the image frame I (px; x right, y down).
  double radius_px = 0.0;         ///< Radius of a disk of the dot's weighted area (px).
  double bright = 0.0;            ///< Level of the dot (0..1 of full scale).
  double dark = 0.0;              ///< Level of the patch around it.
  double noise = 0.0;             ///< Noise standard deviation on the patch.
  double significance = 0.0;      ///< (bright - dark) / noise.
  double fit_residual_px = 0.0;   ///< Ellipse method: rms distance of edge points; else 0.
};

/// The `count` most significant dots in the whole image (most significant first), at least
/// 2.5 radii apart. Fewer are returned when fewer pass the significance rule.
std::vector<Dot> FindDots(const cv::Mat& grey, int count, const DotDetectorOptions& options = {});

/// The dot nearest `predicted_I` whose centre lies within `search_radius_px`, expected to have
/// about `expected_radius_px`. Looks only at a window around the prediction. nullopt when no
/// dot there passes the significance rule.
std::optional<Dot> FindDotNear(const cv::Mat& grey, const Eigen::Vector2d& predicted_I,
                               double search_radius_px, double expected_radius_px,
                               const DotDetectorOptions& options = {});

/// Robust noise standard deviation of an image region (median absolute difference of
/// horizontal neighbours, scaled for a Gaussian).
double EstimateNoise(const cv::Mat& unit_float);

}  // namespace hoof::tracking
