#pragma once
/// @file
/// One trial, end to end: frames -> marker tracks -> body poses -> impact kinematics, with the
/// calibration checks (surface angle, scale) and the out-of-plane rotation check.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "kinematics/arc_impacts.h"
#include "kinematics/capture_rate.h"
#include "kinematics/flight_arcs.h"
#include "kinematics/gravity_scale.h"
#include "kinematics/impact_kinematics.h"
#include "pipeline/round_end.h"
#include "pipeline/study_format.h"
#include "tracking/calibration_target.h"
#include "tracking/frame_timing.h"
#include "tracking/marker_tracker.h"
#include "tracking/pose.h"
#include "tracking/silhouette_tracker.h"

namespace hoof::pipeline {

/// Settings of a trial's analysis.
struct TrialAnalysisOptions {
  tracking::TrackerOptions tracker;
  /// The silhouette tracker's settings; its shape, polarity and gravity come from the trial.
  tracking::SilhouetteOptions silhouette;
  kinematics::KinematicsOptions kinematics;
  /// Repeated frames and dropped captures (tracking/frame_timing.h); `enabled = false` takes
  /// every frame as a new capture at index / fps.
  tracking::FrameTimingOptions timing;
  /// Take the scale from the known marker spacing (median over the frames before the impact)
  /// instead of camera.m_per_px.
  bool scale_from_markers = false;
  /// Flag out-of-plane rotation when the projected marker distance changes by more than this
  /// fraction, or by more than 8 noise standard deviations if that is larger.
  double out_of_plane_threshold = 0.003;
  /// Warn when the measured surface angle differs from trial.json by more than this (deg).
  double surface_angle_tolerance_deg = 1.0;
  /// An outline: the frames (spread evenly over those where it was found) whose round end is
  /// fitted to place E (pipeline/round_end.h); >= 1.
  int round_end_frames = 40;
};

/// The body's motion over the clip as a straight line in the image (with gravity's known
/// curve taken out where the scale is known): what a clip that holds no impact still tells.
struct TrackSummary {
  int frames_tracked = 0;    ///< frames where the body was found
  bool gravity_fit = false;  ///< true: p(t) = p0 + v t + g t^2 / 2 with g known; else a line
  Eigen::Vector2d v_px_per_frame{0, 0};  ///< mean velocity over the tracked frames (image, px)
  double speed_px_per_frame = 0.0, speed_se_px_per_frame = 0.0;
  double speed_m_s = 0.0, speed_se_m_s = 0.0;  ///< with the scale's uncertainty; NaN unscaled
  double rms_residual_px = 0.0;                ///< rms distance of the centres from the fit
};

/// What a trial's analysis produced. On failure `error` says why, naming the file or frame;
/// whatever was measured before the failure is kept.
struct TrialAnalysis {
  TrialSpec spec;
  bool success = false;
  std::string error;
  /// The clip holds no impact (the body never comes down and rebounds): `error` says so, and
  /// `motion` what was measured of it; not a fault of the data.
  bool no_impact = false;
  tracking::MarkerTracks tracks;          ///< markers model
  tracking::SilhouetteTrack silhouette;   ///< silhouette model, per frame (image frame, px)
  std::vector<tracking::BodyPose> poses;  ///< per frame, in W
  /// Per frame: its capture slot and time (t_s, what the kinematics use), and whether it
  /// repeats the previous image (then its pose is no sample of the motion).
  tracking::FrameTiming timing;
  /// The trial's main result: the clip's impact, or with several the first one measured
  /// (pipeline/trial_impacts.h).
  kinematics::ImpactKinematics impact;
  /// Every impact found in the clip, in time order, each measured on its own (or found but not
  /// measured: success false with the reason); empty when the clip holds none.
  std::vector<kinematics::ImpactKinematics> impacts;
  /// The method that measured `impacts` (pipeline/trial_impacts.h): kWindows or kArcs.
  kinematics::KinematicsMethod kinematics_method = kinematics::KinematicsMethod::kWindows;
  /// The joint arc fit and the contact line through the impacts' meeting points, when the
  /// joint arcs measured the impacts.
  std::optional<kinematics::FlightArcs> arcs;
  std::optional<kinematics::ContactLine> contact_line;
  /// The capture rate the arcs' acceleration implies (kinematics/capture_rate.h), when the
  /// joint arcs ran and the scale does not come from gravity.
  std::optional<kinematics::CaptureRate> capture_rate;
  TrackSummary motion;  ///< silhouette model, and every trial with no impact
  double m_per_px_used = 0.0;
  /// Where m_per_px_used comes from: "camera.m_per_px", "markers" (--scale-from-markers or
  /// camera.scale_from), "body.diameter_m" (a ball's known diameter over its fitted diameter)
  /// "gravity" (the free-flight parabola; NaN when it could not be measured), "checkerboard" or
  /// "ruler" (a calibration image). Its s.e.
  /// is carried into every velocity and kinetic energy (kinematics::AddScaleUncertainty).
  std::string scale_source = "camera.m_per_px";
  double m_per_px_se = 0.0;               ///< its standard error; 0 for a stated scale
  double m_per_px_from_markers = 0.0;     ///< 0 when it could not be measured
  double m_per_px_from_markers_se = 0.0;  ///< the median's standard error
  /// The gravity fit, when camera.scale_from is "gravity" (kinematics/gravity_scale.h).
  std::optional<kinematics::GravityScale> gravity_scale;
  /// The calibration image's measurement, when camera.scale_from is "checkerboard" or "ruler"
  /// (pipeline/calibration_scale.h).
  std::optional<tracking::CalibrationScale> calibration_scale;
  /// An outline: where its round end's centre E lies from the area centroid (nullopt for markers
  /// and balls). When not measured, the area centroid is taken as C.
  std::optional<RoundEndOffset> round_end;
  /// Ball: the median fitted diameter (px) over the frames and its standard error (the
  /// scatter of the frames' diameters over sqrt(n)); NaN for other bodies.
  double body_diameter_px = core::kNaN, body_diameter_se_px = core::kNaN;
  /// Ball with a known diameter: the scale it gives (m/px), beside a stated one; NaN otherwise.
  double m_per_px_from_body = core::kNaN;
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

/// The straight-line (or, with `gravity_px_per_frame2` > 0, gravity) fit of the body's
/// positions `p_px` (px, one per frame, invalid ones skipped) with gravity along the unit
/// `gravity_dir` of the same frame; speeds scaled by `fps` and `m_per_px` (with its s.e.; 0
/// leaves the speed in m/s NaN). Needs 3 or more valid positions (else frames_tracked says how
/// many and the speeds are NaN).
TrackSummary SummarizeTrack(const std::vector<std::optional<Eigen::Vector2d>>& p_px, double fps,
                            double m_per_px, double m_per_px_se, const Eigen::Vector2d& gravity_dir,
                            double gravity_px_per_frame2);

/// Analyses one trial. Never throws for bad trial data: failures are recorded in the result.
/// `progress(frame)` is called as frames are tracked.
TrialAnalysis AnalyzeTrial(const TrialSpec& spec, const TrialAnalysisOptions& options = {},
                           const std::function<void(int)>& progress = {});

}  // namespace hoof::pipeline
