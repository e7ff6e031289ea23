#pragma once
/// @file
/// The scale from a calibration image (docs/tracking.md, "4b. The scale"): a checkerboard or a
/// ruler lying in the plane of motion. A checkerboard's inner corners are found with OpenCV
/// (cv::findChessboardCornersSB, again on the image flattened by the board's own white and black
/// levels), undistorted with the trial's lens model, and fitted with a similarity (scale,
/// rotation, shift; a mirror image allowed) to the board's grid; a ruler's ticks are found by
/// the phase of the profile along a segment the user gives (straightened by the lens model), and
/// their positions fitted with a straight line of tick index. Either fit's residuals give the
/// standard error of the scale; the ruler's is too small (docs/tracking.md, "4b. The scale").

#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "tracking/pose.h"

namespace hoof::tracking {

/// A scale measured from a calibration image.
struct CalibrationScale {
  double m_per_px = 0.0, m_per_px_se = 0.0;  ///< m per undistorted pixel, and its s.e.
  double rms_residual_px = 0.0;              ///< of the points about the fitted grid or line (px)
  int points = 0;                            ///< corners or ticks used
  double angle_deg = 0.0;  ///< the board's x axis or the ruler from the image's x (toward y)
  /// Checkerboard: the corners found (recorded image px, OpenCV's order). Ruler: the ticks'
  /// positions (recorded image px, on the segment).
  std::vector<Eigen::Vector2d> points_px;
};

/// Converts a grey or colour, 8- or 16-bit image to 8-bit grey, stretched so that its 0.1 and
/// 99.9 percentiles span 0..255 (a 12-bit frame in a 16-bit container becomes visible).
cv::Mat ToGrey8(const cv::Mat& image);

/// The scale from a checkerboard with `cols` x `rows` inner corners of `square_m` squares in
/// `image`, its points undistorted by `lens` (its m_per_px is not used). `name` names the image
/// in errors. Throws std::runtime_error naming it when no board is found, or a board with
/// another corner count is (the message gives the count found).
CalibrationScale MeasureCheckerboard(const cv::Mat& image, int cols, int rows, double square_m,
                                     const ImageToWorld& lens, const std::string& name);

/// The scale from a ruler whose ticks, `tick_m` apart, cross the segment `from_px` -> `to_px`
/// (recorded image px) in `image`; tick positions undistorted by `lens`. The ticks may be dark
/// on a light ruler or light on a dark one. Throws std::runtime_error naming `name` when the
/// segment leaves the image, is shorter than 4 ticks, or no regular ticks are found along it.
CalibrationScale MeasureRuler(const cv::Mat& image, const Eigen::Vector2d& from_px,
                              const Eigen::Vector2d& to_px, double tick_m, const ImageToWorld& lens,
                              const std::string& name);

}  // namespace hoof::tracking
