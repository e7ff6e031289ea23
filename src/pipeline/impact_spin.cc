#include "pipeline/impact_spin.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <set>
#include <sstream>
#include <string>

namespace hoof::pipeline {
namespace {

/// One flight's spin in the image sense, and the note that says how it was measured or why not.
struct SideSpin {
  tracking::ArcSpin spin;
  std::string note;
};

SideSpin FlightSpin(const tracking::SilhouetteTrack& track,
                    const std::vector<kinematics::PoseSample>& samples,
                    const kinematics::FlightFit& fit, const std::set<int>& left_out,
                    const tracking::BallSpinOptions& options) {
  SideSpin out;
  if (fit.first_frame < 0 || fit.last_frame < fit.first_frame) {
    out.note = "not measured: the flight holds no frames";
    return out;
  }
  std::vector<tracking::BallFace> faces;
  std::vector<double> t_s;
  int sampled = 0;
  const int last =
      std::min({fit.last_frame, track.frame_count() - 1, static_cast<int>(samples.size()) - 1});
  for (int f = fit.first_frame; f <= last; ++f) {
    const auto& o = track.frames[static_cast<std::size_t>(f)];
    const auto& s = samples[static_cast<std::size_t>(f)];
    if (!o.found || !s.valid || left_out.count(f) || !o.face) continue;
    ++sampled;
    faces.push_back(*o.face);
    t_s.push_back(s.t_s);
  }
  out.spin = tracking::FitArcSpin(faces, t_s, options);
  std::ostringstream os;
  if (out.spin.measured) {
    os << "from the ball's texture over " << out.spin.pairs << " frame pairs (frames "
       << fit.first_frame << " to " << fit.last_frame << ", mean correlation " << out.spin.mean_peak
       << ")";
  } else {
    os << "not measured: " << out.spin.why;
    if (sampled == 0) os << " (no frame of the flight has a fitted edge to sample the face about)";
  }
  out.note = os.str();
  return out;
}

}  // namespace

void MeasureImpactSpin(const tracking::SilhouetteTrack& track,
                       const std::vector<kinematics::PoseSample>& samples, double sense_W,
                       double inertia_kg_m2, const tracking::BallSpinOptions& options,
                       kinematics::ImpactKinematics& im) {
  if (!im.success) return;
  std::set<int> left_out(im.limits.outlier_frames.begin(), im.limits.outlier_frames.end());
  left_out.insert(im.limits.repeated_frames.begin(), im.limits.repeated_frames.end());
  left_out.insert(im.limits.contact_frames.begin(), im.limits.contact_frames.end());
  const auto apply = [&](const kinematics::FlightFit& fit_in, kinematics::FlightFit& fit, double& w,
                         double& w_se, double& energy, std::string& note) {
    const SideSpin side = FlightSpin(track, samples, fit_in, left_out, options);
    note = side.note;
    if (!side.spin.measured) return;
    w = sense_W * side.spin.w_I_rad_s;
    w_se = side.spin.w_se_rad_s;
    fit.w_rad_s = w;
    fit.w_se_rad_s = w_se;
    if (std::isfinite(inertia_kg_m2) && std::isfinite(energy))
      energy += 0.5 * inertia_kg_m2 * w * w;
  };
  apply(im.before, im.before, im.w_before_rad_s, im.w_before_se_rad_s, im.kinetic_energy_before_J,
        im.limits.spin_before);
  apply(im.after, im.after, im.w_after_rad_s, im.w_after_se_rad_s, im.kinetic_energy_after_J,
        im.limits.spin_after);
}

}  // namespace hoof::pipeline
