#include "kinematics/capture_rate.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace hoof::kinematics {

void CaptureRateOptions::Validate() const {
  if (!(gravity_m_s2 > 0)) throw std::invalid_argument("capture rate gravity_m_s2 must be > 0");
  if (!(gravity_rel_se >= 0))
    throw std::invalid_argument("capture rate gravity_rel_se must be >= 0");
  if (!(min_significance > 0))
    throw std::invalid_argument("capture rate min_significance must be > 0");
}

CaptureRate CaptureRateFromGravity(double a_m_s2, double a_se_m_s2, double container_fps,
                                   double scale_rel_se, const CaptureRateOptions& options) {
  options.Validate();
  if (!(container_fps > 0) || !std::isfinite(container_fps))
    throw std::invalid_argument("capture rate: container_fps must be > 0");
  if (!(a_se_m_s2 >= 0) || !(scale_rel_se >= 0))
    throw std::invalid_argument("capture rate: standard errors must be >= 0");
  CaptureRate r;
  r.container_fps = container_fps;
  if (!(a_m_s2 > options.min_significance * a_se_m_s2) || !std::isfinite(a_m_s2)) {
    std::ostringstream os;
    os << "the capture rate from gravity is not measured: the fitted acceleration, " << a_m_s2
       << " m/s^2 with a standard error of " << a_se_m_s2 << ", is within "
       << options.min_significance << " standard errors of zero";
    r.message = os.str();
    return r;
  }
  // a = g (container / capture)^2, so capture / container = sqrt(g / a).
  r.ratio = std::sqrt(options.gravity_m_s2 / a_m_s2);
  const double rel = 0.5 * std::sqrt(std::pow(a_se_m_s2 / a_m_s2, 2) + scale_rel_se * scale_rel_se +
                                     options.gravity_rel_se * options.gravity_rel_se);
  r.ratio_se = r.ratio * rel;
  r.capture_fps = container_fps * r.ratio;
  r.capture_fps_se = container_fps * r.ratio_se;
  r.nearest_ratio = std::max(1, static_cast<int>(std::lround(r.ratio)));
  r.nearest_ratio_z = (r.ratio - r.nearest_ratio) / r.ratio_se;
  r.measured = true;
  return r;
}

}  // namespace hoof::kinematics
