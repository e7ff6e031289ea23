#pragma once
/// @file
/// A calibration image for a synthetic trial (docs/synthetic-trials.md, "Calibration images"):
/// a checkerboard card or a ruler lying in the plane of motion at the trial's scale, seen
/// through the same lens, defocus, lighting and sensor noise as the trial's frames, with its
/// truth (the scale, the board's or the ruler's placement) known.

#include <cstdint>
#include <string>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "synth/options.h"

namespace hoof::synth {

/// The target's placement and geometry, drawn from the trial's seed.
struct CalibrationPlan {
  CalibrationTarget target = CalibrationTarget::kNone;
  std::string file = "calibration.png";  ///< in the trial folder
  double m_per_px = 0.0;                 ///< the scale it is drawn at (the trial's)
  Eigen::Vector2d centre_px{0, 0};       ///< the target's centre in the ideal image (px)
  double angle_deg = 0.0;                ///< its x axis from the image's x, toward the image's y
  /// Checkerboard: inner corners (columns along its x, rows) and the square's side (m).
  int cols = 9, rows = 6;
  double square_m = 0.0;
  /// Ruler: tick spacing (m), ticks from one end, and the segment across the ticks in the
  /// recorded (distorted) image that trial.json gives (px).
  double tick_m = 0.0;
  int ticks = 0;
  Eigen::Vector2d from_px{0, 0}, to_px{0, 0};
};

/// The plan of the calibration image of a trial with `options` and `seed`: the board's square
/// (three significant digits) so that the card fills about three quarters of the smaller side,
/// or the ruler's tick spacing (1, 2 or 5 x 10^k m, 4 px or more) along about 80 % of the width;
/// a seeded placement (a shift and a turn of up to 8 deg). Throws std::invalid_argument when
/// the frame is too small for the target (squares under 6 px).
CalibrationPlan PlanCalibration(const RenderOptions& options, std::uint64_t seed);

/// The recorded calibration image (CV_8U at 8 bits, else CV_16U), through options.camera's
/// lens, illumination, defocus and sensor (noise seeded from `seed`).
cv::Mat RenderCalibrationImage(const CalibrationPlan& plan, const RenderOptions& options,
                               std::uint64_t seed);

}  // namespace hoof::synth
