#include "pipeline/out_of_plane.h"

#include <cmath>

#include <Eigen/Geometry>

#include "tracking/pose.h"

namespace hoof::pipeline {

Eigen::Vector2d ProjectOutOfPlane(const Eigen::Vector3d& p_B_m, double tilt_rad, double roll_rad,
                                  double d_EC_m) {
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(tilt_rad, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(roll_rad, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  const Eigen::Vector3d p_BC{d_EC_m, 0.0, 0.0};
  return (R * (p_B_m - p_BC) + p_BC).head<2>();
}

double MarkerDistanceRatio(const SpecimenSpec& specimen, double tilt_rad, double roll_rad) {
  const auto& m = specimen.markers_B_m;
  if (m.size() < 2) return 1.0;
  const double z = specimen.thickness_m / 2;
  const Eigen::Vector3d a{m[0].second.x(), m[0].second.y(), z},
      b{m[1].second.x(), m[1].second.y(), z};
  const double d = (a - b).head<2>().norm();
  if (!(d > 0)) return 1.0;
  return (ProjectOutOfPlane(a, tilt_rad, roll_rad, specimen.d_EC_m) -
          ProjectOutOfPlane(b, tilt_rad, roll_rad, specimen.d_EC_m))
             .norm() /
         d;
}

TrialAnalysis RemeasureOutOfPlane(const TrialAnalysis& trial, const OutOfPlaneMotion& motion,
                                  const kinematics::KinematicsOptions& options) {
  if (!trial.success || motion.IsZero()) return trial;
  TrialAnalysis out = trial;
  const TrialSpec& spec = trial.spec;
  const double z = spec.specimen.thickness_m / 2;
  const double t_star = trial.impact.impact_time_s;
  const tracking::ImageToWorld cam = TrialCamera(spec, trial.m_per_px_used);
  std::vector<kinematics::PoseSample> samples;
  const auto frames = static_cast<std::size_t>(trial.tracks.frame_count());
  out.poses.assign(frames, tracking::BodyPose{});
  for (std::size_t f = 0; f < frames; ++f) {
    const double t = static_cast<double>(f) / spec.fps;
    const double tilt = motion.TiltAt(t - t_star), roll = motion.RollAt(t - t_star);
    std::vector<Eigen::Vector2d> layout;
    for (const auto& [name, p] : spec.specimen.markers_B_m)
      layout.push_back(ProjectOutOfPlane({p.x(), p.y(), z}, tilt, roll, spec.specimen.d_EC_m));
    const auto pose = tracking::FitPose(trial.tracks.frames[f], layout, cam);
    out.poses[f] = pose;
    samples.push_back({t, pose.valid, pose.p_WE, pose.theta_W_rad});
    if (f < out.marker_distance_ratio.size() && std::isfinite(out.marker_distance_ratio[f]))
      out.marker_distance_ratio[f] /= MarkerDistanceRatio(spec.specimen, tilt, roll);
  }
  out.impact =
      kinematics::MeasureImpact(samples, spec.fps, spec.surface_angle_deg, spec.specimen, options);
  if (!out.impact.success) {
    out.success = false;
    out.error = (spec.dir / "trial.json").string() +
                ": re-measured with an out-of-plane rotation: " + out.impact.message;
  }
  return out;
}

}  // namespace hoof::pipeline
