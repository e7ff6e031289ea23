#include "pipeline/trial_impacts.h"

#include <string>

#include "core/frames.h"

namespace hoof::pipeline {

void MeasureTrialImpacts(const std::vector<kinematics::PoseSample>& samples, double fps,
                         double surface_angle_deg, const core::SpecimenParameters& body,
                         const kinematics::KinematicsOptions& options, bool w_seen,
                         TrialAnalysis& out) {
  const auto hide_w = [w_seen](kinematics::ImpactKinematics& k) {
    if (!w_seen && k.success)
      k.w_before_rad_s = k.w_after_rad_s = k.w_before_se_rad_s = k.w_after_se_rad_s = core::kNaN;
  };
  out.impacts = kinematics::MeasureImpacts(samples, fps, surface_angle_deg, body, options);
  if (out.impacts.size() <= 1) {
    out.impact = kinematics::MeasureImpact(samples, fps, surface_angle_deg, body, options);
    hide_w(out.impact);
    if (out.impact.success) out.impacts = {out.impact};
    return;
  }
  for (auto& k : out.impacts) hide_w(k);
  std::size_t main = 0;
  while (main < out.impacts.size() && !out.impacts[main].success) ++main;
  if (main == out.impacts.size()) main = 0;
  for (const auto& k : out.impacts)
    if (!k.success)
      out.warnings.push_back("impact " + std::to_string(k.index) + " (near frame " +
                             std::to_string(k.lowest_frame) +
                             ") was found but not measured: " + k.message);
  if (main > 0)
    out.warnings.push_back("the trial's result is impact " + std::to_string(main) +
                           ", the first one measured");
  out.impact = out.impacts[main];
  // Its own index and frame are kept; a trial-level reader sees the same fields as for one impact.
  out.flags.push_back("several_impacts");
}

}  // namespace hoof::pipeline
