#pragma once
/// @file
/// The time base from gravity (docs/tracking.md, "Joint arcs", "The time base from gravity").
/// A clip's times are frame index over the container's frame rate; when the scale is known
/// independently of gravity (a ball's known diameter, a checkerboard, a ruler), the arcs' fitted
/// acceleration |a| in m/s^2 at those times tells the rate the frames were captured at: a
/// slow-motion file that stores 240 captures a second at 30 fps plays the motion 8 times
/// slower, so |a| comes out 8^2 = 64 times too small. Capture rate = container rate x
/// sqrt(g / |a|).

#include <string>

#include "core/frames.h"

namespace hoof::kinematics {

/// Settings of the capture rate from gravity.
struct CaptureRateOptions {
  double gravity_m_s2 = core::kStandardGravity_m_s2;  ///< the local g; > 0
  /// Relative uncertainty of g where the clip was taken (standard gravity against the local
  /// value, which lies within about 0.3 % of it on the Earth's surface); >= 0.
  double gravity_rel_se = 0.0015;
  /// The rate counts as measured when |a| exceeds this many of its standard errors; > 0.
  double min_significance = 5.0;

  /// Throws std::invalid_argument naming the field.
  void Validate() const;
};

/// The capture rate gravity implies. `measured` false: `message` says why (|a| not
/// distinguishable from zero); the numbers are still filled where they could be computed.
struct CaptureRate {
  bool measured = false;
  std::string message;
  double container_fps = core::kNaN;  ///< the rate the times were computed from (1/s)
  double capture_fps = core::kNaN, capture_fps_se = core::kNaN;  ///< what gravity implies (1/s)
  /// capture / container (8 for 240 captures a second stored at 30 fps), and its s.e.
  double ratio = core::kNaN, ratio_se = core::kNaN;
  /// The whole ratio nearest `ratio` (>= 1), and how many s.e. `ratio` lies from it: a file
  /// whose ratio is 1 within a few s.e. plays in real time.
  int nearest_ratio = 0;
  double nearest_ratio_z = core::kNaN;
};

/// The capture rate from the fitted acceleration `a_m_s2` (|a| in m/s^2 with times at
/// `container_fps`, e.g. FlightArcs::a_norm times the scale in m per input unit) and its s.e.
/// `a_se_m_s2` (from the fit alone), the scale's relative s.e. `scale_rel_se` (|a| in m/s^2 is
/// proportional to it) and the uncertainty of g. The ratio's relative s.e. is half that of
/// |a| / g, all three combined. Throws std::invalid_argument for a non-positive
/// container_fps, negative standard errors or invalid options.
CaptureRate CaptureRateFromGravity(double a_m_s2, double a_se_m_s2, double container_fps,
                                   double scale_rel_se, const CaptureRateOptions& options = {});

}  // namespace hoof::kinematics
