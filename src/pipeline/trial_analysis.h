#pragma once
/// @file
/// One trial, end to end: frames -> marker tracks -> body poses -> impact kinematics, with the
/// calibration checks (surface angle, scale) and the out-of-plane rotation check.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "kinematics/impact_kinematics.h"
#include "pipeline/study_format.h"
#include "tracking/marker_tracker.h"
#include "tracking/pose.h"

namespace hoof::pipeline {

/// Settings of a trial's analysis.
struct TrialAnalysisOptions {
  tracking::TrackerOptions tracker;
  kinematics::KinematicsOptions kinematics;
  /// Take the scale from the known marker spacing (median over the frames before the impact)
  /// instead of camera.m_per_px.
  bool scale_from_markers = false;
  /// Flag out-of-plane rotation when the projected marker distance changes by more than this
  /// fraction, or by more than 8 noise standard deviations if that is larger.
  double out_of_plane_threshold = 0.003;
  /// Warn when the measured surface angle differs from trial.json by more than this (deg).
  double surface_angle_tolerance_deg = 1.0;
};

/// What a trial's analysis produced. On failure `error` says why, naming the file or frame;
/// whatever was measured before the failure is kept.
struct TrialAnalysis {
  TrialSpec spec;
  bool success = false;
  std::string error;
  tracking::MarkerTracks tracks;
  std::vector<tracking::BodyPose> poses;  ///< per frame, in W
  kinematics::ImpactKinematics impact;
  double m_per_px_used = 0.0;
  double m_per_px_from_markers = 0.0;  ///< 0 when it could not be measured
  std::optional<double> surface_angle_measured_deg;
  std::vector<double>
      marker_distance_ratio;         ///< projected / layout distance per frame (NaN = missing)
  double out_of_plane_change = 0.0;  ///< range of the ratio over the fit windows
  double out_of_plane_noise = 0.0;   ///< its noise standard deviation
  std::vector<std::string> flags;    ///< "out_of_plane", "surface_angle", "lost_marker", ...
  std::vector<std::string> warnings;
  double seconds = 0.0;  ///< wall time of the analysis
};

/// The trial's image-to-world calibration at the scale `m_per_px`.
tracking::ImageToWorld TrialCamera(const TrialSpec& spec, double m_per_px);

/// Analyses one trial. Never throws for bad trial data: failures are recorded in the result.
/// `progress(frame)` is called as frames are tracked.
TrialAnalysis AnalyzeTrial(const TrialSpec& spec, const TrialAnalysisOptions& options = {},
                           const std::function<void(int)>& progress = {});

}  // namespace hoof::pipeline
