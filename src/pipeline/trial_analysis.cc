#include "pipeline/trial_analysis.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <sstream>

#include "core/frames.h"
#include "tracking/frame_source.h"
#include "tracking/surface_line.h"

namespace hoof::pipeline {
namespace {

double Median(std::vector<double> v) {
  if (v.empty()) return core::kNaN;
  auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

/// Surface angle from the first frame, in the trial's convention (descending toward +x).
void CheckSurface(const TrialSpec& spec, const cv::Mat& first, const tracking::ImageToWorld& cam,
                  const TrialAnalysisOptions& options, TrialAnalysis& out) {
  const auto line = tracking::FindSurfaceLine(first);
  if (!line) {
    out.warnings.push_back(
        "no surface line found in the first frame; the surface angle is "
        "not checked");
    return;
  }
  const Eigen::Vector2d d_W =
      cam.ToWorld(line->point_I + 50 * line->direction_I) - cam.ToWorld(line->point_I);
  double phi = -std::atan2(d_W.y(), d_W.x()) * 180 / M_PI;
  if (phi > 90) phi -= 180;
  if (phi < -90) phi += 180;
  out.surface_angle_measured_deg = phi;
  if (std::abs(phi - spec.surface_angle_deg) > options.surface_angle_tolerance_deg) {
    std::ostringstream os;
    os << "the surface in the image is at " << phi << " deg, trial.json says "
       << spec.surface_angle_deg << " deg";
    out.warnings.push_back(os.str());
    out.flags.push_back("surface_angle");
  }
}

/// Projected marker distance over the layout distance, and whether it changes beyond noise.
void CheckOutOfPlane(const TrialSpec& spec, const TrialAnalysisOptions& options,
                     TrialAnalysis& out) {
  const double layout =
      (spec.specimen.markers_B_m[0].second - spec.specimen.markers_B_m[1].second).norm();
  out.marker_distance_ratio.assign(out.poses.size(), core::kNaN);
  for (std::size_t f = 0; f < out.poses.size(); ++f)
    if (out.poses[f].valid && out.poses[f].marker_distance_m > 0)
      out.marker_distance_ratio[f] = out.poses[f].marker_distance_m / layout;
  // Over the frames the fits use (or all, if the impact was not measured).
  std::vector<double> r, diffs;
  for (std::size_t f = 0; f < out.marker_distance_ratio.size(); ++f) {
    const bool in_fit = !out.impact.success ||
                        (static_cast<int>(f) >= out.impact.before.first_frame &&
                         static_cast<int>(f) <= out.impact.before.last_frame) ||
                        (static_cast<int>(f) >= out.impact.after.first_frame &&
                         static_cast<int>(f) <= out.impact.after.last_frame);
    if (!in_fit || std::isnan(out.marker_distance_ratio[f])) continue;
    if (!r.empty() && f > 1 && !std::isnan(out.marker_distance_ratio[f - 1]) &&
        !std::isnan(out.marker_distance_ratio[f - 2]))
      diffs.push_back(std::abs(out.marker_distance_ratio[f] - 2 * out.marker_distance_ratio[f - 1] +
                               out.marker_distance_ratio[f - 2]));
    r.push_back(out.marker_distance_ratio[f]);
  }
  if (r.size() < 4) return;
  // Noise from second differences, which a smooth trend (a steady rotation) hardly enters:
  // for white noise of s.d. sigma they have s.d. sqrt(6) sigma. Range from 3-frame medians.
  out.out_of_plane_noise = 1.4826 * Median(diffs) / std::sqrt(6.0);
  std::vector<double> smooth;
  for (std::size_t i = 1; i + 1 < r.size(); ++i)
    smooth.push_back(Median({r[i - 1], r[i], r[i + 1]}));
  const auto [lo, hi] = std::minmax_element(smooth.begin(), smooth.end());
  out.out_of_plane_change = *hi - *lo;
  const double threshold = std::max(options.out_of_plane_threshold, 8.0 * out.out_of_plane_noise);
  if (out.out_of_plane_change > threshold) {
    std::ostringstream os;
    os << "out-of-plane rotation: the projected distance between "
       << spec.specimen.markers_B_m[0].first << " and " << spec.specimen.markers_B_m[1].first
       << " changes by " << 100 * out.out_of_plane_change << " % (noise "
       << 100 * out.out_of_plane_noise << " %)";
    out.warnings.push_back(os.str());
    out.flags.push_back("out_of_plane");
  }
}

}  // namespace

tracking::ImageToWorld TrialCamera(const TrialSpec& spec, double m_per_px) {
  tracking::ImageToWorld cam;
  cam.m_per_px = m_per_px;
  cam.gravity_I = spec.camera.gravity_image;
  cam.camera_matrix = spec.camera.camera_matrix;
  cam.distortion = spec.camera.distortion;
  return cam;
}

TrialAnalysis AnalyzeTrial(const TrialSpec& spec, const TrialAnalysisOptions& options,
                           const std::function<void(int)>& progress) {
  const auto start = std::chrono::steady_clock::now();
  TrialAnalysis out;
  out.spec = spec;
  out.warnings = spec.warnings;
  try {
    auto source = OpenFrames(spec);
    out.tracks = tracking::TrackMarkers(*source, spec.specimen.markers_B_m, spec.camera.m_per_px,
                                        spec.camera.gravity_image, options.tracker, progress);
    for (const auto& w : out.tracks.warnings) out.warnings.push_back(w);
    for (const auto& row : out.tracks.frames)
      for (const auto& o : row)
        if (o.status == "lost_for_good" &&
            std::find(out.flags.begin(), out.flags.end(), "lost_marker") == out.flags.end())
          out.flags.push_back("lost_marker");

    std::vector<Eigen::Vector2d> layout;
    for (const auto& [name, p] : spec.specimen.markers_B_m) layout.push_back(p);
    out.m_per_px_used = spec.camera.m_per_px;
    // Scale from the marker spacing: median over frames before the lowest point.
    {
      const tracking::ImageToWorld unit = TrialCamera(spec, 1.0);
      std::vector<double> ratio;
      const double L = (layout[0] - layout[1]).norm();
      for (std::size_t f = 0; f < out.tracks.frames.size() / 3; ++f) {
        const auto& row = out.tracks.frames[f];
        if (row.size() >= 2 && row[0].found && row[1].found)
          ratio.push_back(L / (unit.ToWorld(row[0].p_I) - unit.ToWorld(row[1].p_I)).norm());
      }
      if (!ratio.empty()) out.m_per_px_from_markers = Median(ratio);
      if (options.scale_from_markers) {
        if (ratio.empty())
          throw std::runtime_error(spec.dir.string() +
                                   ": cannot take the scale "
                                   "from the markers: none seen together");
        out.m_per_px_used = out.m_per_px_from_markers;
      }
    }
    const tracking::ImageToWorld cam = TrialCamera(spec, out.m_per_px_used);
    CheckSurface(spec, source->Read(0), cam, options, out);

    std::vector<kinematics::PoseSample> samples;
    for (int f = 0; f < out.tracks.frame_count(); ++f) {
      const auto pose =
          tracking::FitPose(out.tracks.frames[static_cast<std::size_t>(f)], layout, cam);
      out.poses.push_back(pose);
      samples.push_back({f / spec.fps, pose.valid, pose.p_WE, pose.theta_W_rad});
    }
    out.impact = kinematics::MeasureImpact(samples, spec.fps, spec.surface_angle_deg, spec.specimen,
                                           options.kinematics);
    for (const auto& w : out.impact.warnings) out.warnings.push_back(w);
    for (const auto& f : out.impact.flags) out.flags.push_back(f);
    CheckOutOfPlane(spec, options, out);
    if (!out.impact.success) {
      out.error = (spec.dir / "trial.json").string() + ": " + out.impact.message;
    } else {
      out.success = true;
    }
  } catch (const std::exception& e) {
    out.error = e.what();
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace hoof::pipeline
