#pragma once
/// @file
/// Finding the impact surface's edge in a frame, to check the trial's stated surface angle.

#include <optional>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace hoof::tracking {

/// A straight line in the image frame I.
struct ImageLine {
  Eigen::Vector2d point_I{0, 0};      ///< a point on the line (px)
  Eigen::Vector2d direction_I{1, 0};  ///< unit direction, pointing toward +x
  double length_px = 0.0;             ///< extent of the edge found along it
  double rms_residual_px = 0.0;       ///< scatter of the edge points about the line
};

/// The longest straight edge within 60 deg of the image horizontal that spans at least a third
/// of the image width: the surface. Edges come from Canny with thresholds set from the image's
/// own gradient distribution; the line is refined by a robust (Huber) fit of nearby edge
/// points. When there is no such edge, the surface is taken as a region: the top edge of the
/// region, unlike the background above it, that fills the bottom of the image (Otsu's split of
/// the smoothed image; a line fitted to each column's topmost pixel of that region, points off
/// it by more than three robust deviations dropped), as for a textured strip whose texture
/// hides its edge from Canny. nullopt when there is neither.
std::optional<ImageLine> FindSurfaceLine(const cv::Mat& grey);

}  // namespace hoof::tracking
