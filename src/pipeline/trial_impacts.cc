#include "pipeline/trial_impacts.h"

#include <algorithm>
#include <string>

#include "core/frames.h"
#include "kinematics/arc_impacts.h"

namespace hoof::pipeline {
namespace {

void HideW(bool w_seen, kinematics::ImpactKinematics& k) {
  if (!w_seen && k.success)
    k.w_before_rad_s = k.w_after_rad_s = k.w_before_se_rad_s = k.w_after_se_rad_s = core::kNaN;
}

/// The main result among out.impacts (the first measured), with a warning for each impact not
/// measured and for a main result that is not the first.
void ChooseMain(TrialAnalysis& out) {
  std::size_t main = 0;
  while (main < out.impacts.size() && !out.impacts[main].success) ++main;
  if (main == out.impacts.size()) main = 0;
  for (const auto& k : out.impacts)
    if (!k.success)
      out.warnings.push_back("impact " + std::to_string(k.index) + " (near frame " +
                             std::to_string(k.lowest_frame) +
                             ") was found but not measured: " + k.message);
  if (main > 0 && out.impacts[main].success)
    out.warnings.push_back("the trial's result is impact " + std::to_string(main) +
                           ", the first one measured");
  out.impact = out.impacts[main];
  // Its own index and frame are kept; a trial-level reader sees the same fields as for one impact.
  if (out.impacts.size() > 1) out.flags.push_back("several_impacts");
}

/// The windows' measurement (MeasureImpact for one impact or none, MeasureImpacts for several).
void WindowImpacts(const std::vector<kinematics::PoseSample>& samples, double fps,
                   double surface_angle_deg, const core::SpecimenParameters& body,
                   const kinematics::KinematicsOptions& options, bool w_seen, TrialAnalysis& out) {
  out.impacts = kinematics::MeasureImpacts(samples, fps, surface_angle_deg, body, options);
  if (out.impacts.size() <= 1) {
    out.impact = kinematics::MeasureImpact(samples, fps, surface_angle_deg, body, options);
    HideW(w_seen, out.impact);
    if (out.impact.success) out.impacts = {out.impact};
    return;
  }
  for (auto& k : out.impacts) HideW(w_seen, k);
  ChooseMain(out);
}

/// Every impact the windows found was measured with fit_frames frames on each side.
bool WindowsFull(const TrialAnalysis& out, int fit_frames) {
  if (out.impacts.empty()) return false;
  for (const auto& k : out.impacts)
    if (!k.success || k.before.n < fit_frames || k.after.n < fit_frames) return false;
  return true;
}

}  // namespace

void MeasureTrialImpacts(const std::vector<kinematics::PoseSample>& samples, double fps,
                         double surface_angle_deg, const core::SpecimenParameters& body,
                         const kinematics::KinematicsOptions& options, bool w_seen,
                         TrialAnalysis& out) {
  using kinematics::KinematicsMethod;
  const std::size_t warnings = out.warnings.size(), flags = out.flags.size();
  bool full = false;
  if (options.method != KinematicsMethod::kArcs) {
    WindowImpacts(samples, fps, surface_angle_deg, body, options, w_seen, out);
    out.kinematics_method = KinematicsMethod::kWindows;
    if (options.method == KinematicsMethod::kWindows) return;
    full = WindowsFull(out, options.fit_frames);
  }
  kinematics::ArcImpacts arcs =
      kinematics::MeasureArcImpacts(samples, surface_angle_deg, body, options);
  // Where every window fills, the windows are kept unless the arcs see the plane of motion at
  // a slant (FlightArcs::perspective_applied): a window's parabola does not bend with the
  // perspective, and a tilted camera's windows measured e 0.006 off on clean rendered frames.
  if (full && !arcs.arcs.perspective_applied) return;
  // The arcs take gravity's direction from the data: where it does not show (arcs too short
  // in time for gravity to bend them, as at 8000 fps), the windows' known g is better.
  // Nor are they taken where they measure fewer impacts than the windows did.
  const auto measured = [](const std::vector<kinematics::ImpactKinematics>& impacts) {
    return std::count_if(impacts.begin(), impacts.end(),
                         [](const kinematics::ImpactKinematics& k) { return k.success; });
  };
  if (options.method == KinematicsMethod::kAuto &&
      (arcs.impacts.empty() || arcs.arcs.status != kinematics::ArcFitStatus::kFitted ||
       !(arcs.arcs.roll_se_deg <= options.arcs.max_roll_se_deg) ||
       measured(arcs.impacts) < measured(out.impacts)))
    return;
  out.warnings.resize(warnings);
  out.flags.resize(flags);
  out.kinematics_method = KinematicsMethod::kArcs;
  out.arcs = std::move(arcs.arcs);
  out.contact_line = arcs.contact_line;
  out.impacts = std::move(arcs.impacts);
  if (out.impacts.empty()) {
    out.impact = kinematics::ImpactKinematics{};
    out.impact.method = KinematicsMethod::kArcs;
    out.impact.no_impact = true;
    out.impact.message =
        "no impact found: the joint arc fit found no contact between flight arcs" +
        (out.arcs->message.empty() ? std::string() : " (" + out.arcs->message + ")");
    return;
  }
  for (auto& k : out.impacts) HideW(w_seen, k);
  ChooseMain(out);
}

}  // namespace hoof::pipeline
