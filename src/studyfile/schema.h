#pragma once
/// @file
/// The fields of each struct the study file keeps in a group of its own (docs/hdf5-schema.md),
/// declared once: dataset name, units and description (internal to hoof::study_file). An
/// archive of studyfile/archive.h visits them: H5Writer writes the group, H5Reader reads it.
/// `T` is the struct, const when writing.
///
/// The tracks and poses of a trial are per-frame arrays: the fields of one marker in one frame
/// and of one frame's pose are declared here too, and the archives of studyfile/frame_archive.h
/// turn each into one dataset over all the frames, with NaN for what a frame did not measure.
#include <type_traits>

#include "kinematics/impact_kinematics.h"
#include "pipeline/study_format.h"
#include "pipeline/trial_analysis.h"
#include "studyfile/archive.h"
#include "studyfile/file_util.h"
#include "studyfile/frame_archive.h"
#include "studyfile/table_archive.h"
#include "tracking/marker_tracker.h"
#include "tracking/pose.h"

namespace hoof::studyfile::internal {

/// A specimen of study.json: `/study/specimens/<id>`.
template <class Archive, class T>
requires std::is_same_v<std::remove_const_t<T>, pipeline::SpecimenSpec>
void Serialize(Archive&& a, T& s) {
  static constexpr EnumNames<pipeline::SpecimenShape, 2> kShapes{
      {{pipeline::SpecimenShape::kBar, "bar"}, {pipeline::SpecimenShape::kBall, "ball"}}};
  static constexpr EnumNames<pipeline::BallInertia, 4> kInertia{
      {{pipeline::BallInertia::kSolid, "solid"},
       {pipeline::BallInertia::kHollow, "hollow"},
       {pipeline::BallInertia::kGiven, "given"},
       {pipeline::BallInertia::kUnknown, "unknown"}}};
  a.LaterChoice("shape", s.shape, kShapes,
                "bar (the hoof-wall specimen) or ball (R half its diameter, d = 0)");
  a.LaterChoice("inertia", s.inertia, kInertia,
                "a ball's inertia: solid (2/5 m R^2), hollow (2/3 m R^2), given, or unknown "
                "(no specimen: mass and inertia NaN); solid for the bar, unused");
  a.Number("mass_kg", s.mass_kg, "kg", "specimen mass (NaN: unknown)");
  a.Number("inertia_kg_m2", s.inertia_kg_m2, "kg m^2",
           "moment of inertia about the centre of mass C, out of the image plane");
  a.Number("end_radius_m", s.end_radius_m, "m", "radius of the round end (centre E)");
  a.Number("d_EC_m", s.d_EC_m, "m", "distance from E to the centre of mass C");
  a.Number("length_m", s.length_m, "m", "specimen length (0 when not given)");
  a.Number("width_m", s.width_m, "m", "specimen width (0 when not given)");
  a.Number("thickness_m", s.thickness_m, "m", "specimen thickness (0 when not given)");
  a.NamedPoints("marker_names", "markers_B_m", s.markers_B_m, "m", "marker names, layout order",
                "marker centres in the body frame B (origin E, x toward C), [marker, (x, y)]");
}

/// The tracker's options, in `/study/analysis_options`.
template <class Archive, class T>
requires std::is_same_v<std::remove_const_t<T>, tracking::TrackerOptions>
void Serialize(Archive&& a, T& t) {
  static constexpr EnumNames<tracking::CentreMethod, 2> kMethods{
      {{tracking::CentreMethod::kEllipseFit, "ellipse"},
       {tracking::CentreMethod::kWeightedCentroid, "centroid"}}};
  a.Choice("centre_method", t.detector.method, kMethods, "sub-pixel dot centre method");
  a.Number("min_significance", t.detector.min_significance, "1",
           "dot contrast over noise for a dot to count");
  a.Integer("centroid_iterations", t.detector.centroid_iterations, "1",
            "re-centring passes of the weighted centroid");
  a.Number("min_radius_px", t.detector.min_radius_px, "px",
           "smallest dot radius the full-frame search considers");
  a.Number("max_radius_px", t.detector.max_radius_px, "px",
           "largest dot radius the full-frame search considers");
  a.Number("search_radius_px", t.search_radius_px, "px", "tracker search radius (0 = automatic)");
  a.Integer("max_consecutive_misses", t.max_consecutive_misses, "frame",
            "a marker missing this many frames in a row is lost for good");
  a.Number("layout_tolerance", t.layout_tolerance, "1",
           "largest relative mismatch of the marker layout in the first frame");
}

/// The impact measurement's options, in `/study/analysis_options`.
template <class Archive, class T>
requires std::is_same_v<std::remove_const_t<T>, kinematics::KinematicsOptions>
void Serialize(Archive&& a, T& k) {
  a.Integer("fit_frames", k.fit_frames, "frame", "frames per flight fit");
  a.Integer("min_fit_frames", k.min_fit_frames, "frame", "fewest usable frames per fit");
  a.Number("max_contact_s", k.max_contact_s, "s", "longest contact assumed");
  a.Number("exposure_s", k.exposure_s, "s", "exposure time; < 0 = one frame period");
  a.Number("gravity_m_s2", k.gravity_m_s2, "m/s^2", "g along -y_W");
  a.Number("confidence", k.confidence, "1", "level of the reported intervals");
}

/// Every option a trial was analysed with: `/study/analysis_options`.
template <class Archive, class T>
requires std::is_same_v<std::remove_const_t<T>, pipeline::TrialAnalysisOptions>
void Serialize(Archive&& a, T& o) {
  Serialize(a, o.tracker);
  Serialize(a, o.kinematics);
  a.Flag("scale_from_markers", o.scale_from_markers,
         "scale taken from the marker spacing instead of camera.m_per_px");
  a.Number("out_of_plane_threshold", o.out_of_plane_threshold, "1",
           "relative change of the projected marker distance that flags out-of-plane rotation");
  a.Number("surface_angle_tolerance_deg", o.surface_angle_tolerance_deg, "deg",
           "largest accepted difference between measured and stated surface angle");
}

/// What trial.json said and the calibration checks: `/trials/<id>/metadata`. The frames'
/// source is written for the reader of the file and not read back.
template <class Archive, class T>
requires std::is_same_v<std::remove_const_t<T>, pipeline::TrialAnalysis>
void SerializeMetadata(Archive&& a, T& r) {
  auto& s = r.spec;
  a.Text("id", s.id, "trial id (trial.json)");
  a.Path("dir", s.dir, "trial folder");
  a.Text("specimen", s.specimen_id, "specimen id (study.json)");
  a.LaterText("specimen_origin", s.specimen_origin,
              "where the specimen was defined (study.json or trial.json, and the field)");
  a.LaterText("body_model", s.body.model, "how the body is tracked: markers or silhouette");
  a.LaterText("body_shape", s.body.shape, "a silhouette's shape: ball or outline (else empty)");
  a.LaterNumber("body_diameter_m", s.body.diameter_m, "m",
                "a ball's known diameter (trial.json's body.diameter_m; 0 when not given)");
  a.Text("surface", s.surface, "surface name");
  a.Number("surface_angle_deg", s.surface_angle_deg, "deg", "surface angle (trial.json)");
  a.Number("fps", s.fps, "1/s", "frame rate");
  a.MaybeNumber("nominal_speed_m_s", s.nominal_speed_m_s, "m/s",
                "nominal impact speed (trial.json; NaN when not given)");
  if constexpr (std::remove_cvref_t<Archive>::kWriting)
    a.Text("frames_source", s.frames.Source(),
           "image pattern or video file, relative to the trial folder");
  a.Integer("frames_first", s.frames.first, "frame", "first frame number");
  a.Integer("frames_count", s.frames.count, "frame", "number of frames");
  a.Number("camera_m_per_px", s.camera.m_per_px, "m/px", "scale stated in trial.json");
  a.Vec2("camera_gravity_image", s.camera.gravity_image, "1",
         "unit direction of gravity in the image (x right, y down)");
  a.MaybeArray("camera_distortion", s.camera.distortion, {5}, "1", "OpenCV k1 k2 p1 p2 k3");
  a.MaybeArray("camera_matrix", s.camera.camera_matrix, {3, 3}, "px",
               "camera matrix fx 0 cx / 0 fy cy / 0 0 1");
  a.MaybePoints("surface_line_px", s.surface_line_px, "px",
                "two image points on the surface, [point, (x, y)]");
  a.Text("notes", s.notes, "notes (trial.json)");
  a.TextList("input_warnings", s.warnings, "warnings from reading trial.json");
  a.Number("m_per_px_used", r.m_per_px_used, "m/px", "scale the analysis used");
  a.NumberZeroUnmeasured("m_per_px_from_markers", r.m_per_px_from_markers, "m/px",
                         "scale measured from the marker spacing (NaN when not measured)");
  a.MaybeNumber("surface_angle_measured_deg", r.surface_angle_measured_deg, "deg",
                "surface angle measured in the first frame (NaN when not measured)");
  a.Number("analysis_seconds", r.seconds, "s", "wall time of the analysis");
}

/// One marker in one frame: an element of the [frame, marker] datasets of
/// `/trials/<id>/tracks`. A marker not found has no centre or radius (NaN in the file).
template <class Archive, class T>
requires std::is_same_v<std::remove_const_t<T>, tracking::MarkerObservation>
void Serialize(Archive&& a, T& o) {
  a.Vec2If(o.found, "p_I_px", o.p_I, "px",
           "marker centre in the image frame I (x right, y down), [frame, marker, (x, y)]; "
           "NaN when not found");
  a.Flag("found", o.found, "marker found, [frame, marker]");
  a.Text("status", o.status, "ok, lost, merged or lost_for_good, [frame, marker]");
  a.Number("quality", o.quality, "1",
           "significance (contrast / noise), 0 when not found, [frame, marker]");
  a.NumberIf(o.found, "radius_px", o.radius_px, "px", "dot radius, NaN when not found");
}

/// The raw marker tracks of a trial: `/trials/<id>/tracks` (a FramesWriter or FramesReader).
template <class Archive, class T>
requires std::is_same_v<std::remove_const_t<T>, pipeline::TrialAnalysis>
void SerializeTracks(Archive&& a, T& r) {
  auto& t = r.tracks;
  a.TextList("marker_names", t.names, "marker names, layout order");
  a.FrameTimes("t_s", t.frames, r.spec.fps, "s", "frame time since frame 0 (frame index / fps)");
  a.PerFrameAndMarker(t.frames, t.names.size());
  a.TextList("warnings", t.warnings, "lost or merged markers, per frame");
}

/// The body pose in one frame: an element of the [frame] datasets of `/trials/<id>/poses`. An
/// invalid pose has no numbers (NaN in the file) but the count of markers it had; a marker
/// distance of 0 (not measured) is NaN in the file too.
template <class Archive, class T>
requires std::is_same_v<std::remove_const_t<T>, tracking::BodyPose>
void Serialize(Archive&& a, T& q) {
  a.Flag("valid", q.valid, "pose measured (enough markers found)");
  a.Vec2If(q.valid, "p_WE_m", q.p_WE, "m",
           "centre of the round end E in the world frame W (y up), [frame, (x, y)]; NaN when "
           "not valid");
  a.NumberIf(q.valid, "theta_W_rad", q.theta_W_rad, "rad",
             "angle of x_B from x_W, counter-clockwise");
  a.NumberIf(q.valid, "rms_residual_m", q.rms_residual_m, "m",
             "misfit of the marker layout to the markers");
  a.Int32("markers_used", q.markers_used, "1", "markers in the pose fit");
  a.NumberZeroUnmeasuredIf(q.valid, "marker_distance_m", q.marker_distance_m, "m",
                           "projected distance between the first two markers");
}

/// The body pose per frame of a trial: `/trials/<id>/poses` (a FramesWriter or FramesReader).
template <class Archive, class T>
requires std::is_same_v<std::remove_const_t<T>, pipeline::TrialAnalysis>
void SerializePoses(Archive&& a, T& r) {
  a.FrameTimes("t_s", r.poses, r.spec.fps, "s", "frame time since frame 0");
  a.PerFrame(r.poses);
  a.FrameNumbers("marker_distance_ratio", r.marker_distance_ratio, r.poses.size(), "1",
                 "projected / layout marker distance (out-of-plane rotation shrinks it); NaN = "
                 "missing");
  a.Number("out_of_plane_change", r.out_of_plane_change, "1",
           "range of marker_distance_ratio over the fit windows");
  a.Number("out_of_plane_noise", r.out_of_plane_noise, "1",
           "noise standard deviation of marker_distance_ratio");
}

/// A free-flight fit: `/trials/<id>/fits/before` and `.../after`.
template <class Archive, class T>
requires std::is_same_v<std::remove_const_t<T>, kinematics::FlightFit>
void Serialize(Archive&& a, T& fit) {
  a.Integer("first_frame", fit.first_frame, "frame", "first frame of the fit window");
  a.Integer("last_frame", fit.last_frame, "frame", "last frame of the fit window");
  a.Integer("n", fit.n, "1", "frames used in the fit");
  a.Vec2("p_WC_m", fit.p_WC, "m", "position of C at the impact time, W");
  a.Vec2("v_WC_m_s", fit.v_WC, "m/s", "velocity of C at the impact time, W");
  a.Matrix2("cov_v_WC_m2_s2", fit.cov_v_WC, "m^2/s^2", "covariance of v_WC");
  a.Number("theta_W_rad", fit.theta_W_rad, "rad", "angle at the impact time");
  a.Number("theta_se_rad", fit.theta_se_rad, "rad", "its standard error");
  a.Number("w_rad_s", fit.w_rad_s, "rad/s", "angular velocity");
  a.Number("w_se_rad_s", fit.w_se_rad_s, "rad/s", "its standard error");
  a.Number("rms_residual_m", fit.rms_residual_m, "m", "rms residual of the position fit");
  a.Number("rms_theta_residual_rad", fit.rms_theta_residual_rad, "rad",
           "rms residual of the angle fit");
}

/// The impact in the surface frame S: `/trials/<id>/results`.
template <class Archive, class T>
requires std::is_same_v<std::remove_const_t<T>, kinematics::ImpactKinematics>
void Serialize(Archive&& a, T& k) {
  const std::string S = ", S = [along the surface (down-slope), normal]";
  a.Number("impact_time_s", k.impact_time_s, "s", "impact time since frame 0 (sub-frame)");
  a.Integer("impact_frame", k.impact_frame, "frame", "last frame before the impact");
  a.Vec2("v_SC_before_m_s", k.v_SC_before, "m/s", "velocity of C before" + S);
  a.Vec2("v_SC_before_se_m_s", k.v_SC_before_se, "m/s", "its standard error");
  a.Vec2("v_SC_after_m_s", k.v_SC_after, "m/s", "velocity of C after" + S);
  a.Vec2("v_SC_after_se_m_s", k.v_SC_after_se, "m/s", "its standard error");
  a.Vec2("v_ST_before_m_s", k.v_ST_before, "m/s", "velocity of the body point at T before" + S);
  a.Vec2("v_ST_after_m_s", k.v_ST_after, "m/s", "velocity of the body point at T after" + S);
  a.Number("w_before_rad_s", k.w_before_rad_s, "rad/s", "angular velocity before");
  a.Number("w_before_se_rad_s", k.w_before_se_rad_s, "rad/s", "its standard error");
  a.Number("w_after_rad_s", k.w_after_rad_s, "rad/s", "angular velocity after");
  a.Number("w_after_se_rad_s", k.w_after_se_rad_s, "rad/s", "its standard error");
  a.Number("e", k.e, "1", "normal coefficient of restitution");
  a.Number("e_se", k.e_se, "1", "its standard error");
  a.Pair("e_ci", k.e_ci_low, k.e_ci_high, "1",
         "confidence interval of e (level: /study/analysis_options/confidence)");
  a.Number("mu_eff", k.mu_eff, "1", "effective friction coefficient");
  a.Number("mu_eff_se", k.mu_eff_se, "1", "its standard error");
  a.Pair("mu_eff_ci", k.mu_eff_ci_low, k.mu_eff_ci_high, "1", "confidence interval of mu_eff");
  a.Number("kinetic_energy_before_J", k.kinetic_energy_before_J, "J",
           "kinetic energy before (translation and rotation)");
  a.Number("kinetic_energy_after_J", k.kinetic_energy_after_J, "J", "kinetic energy after");
  a.TextList("warnings", k.warnings, "warnings of the impact measurement");
}

/// The outcome of a trial, in `/trials/<id>` beside its groups.
template <class Archive, class T>
requires std::is_same_v<std::remove_const_t<T>, pipeline::TrialAnalysis>
void SerializeOutcome(Archive&& a, T& r) {
  a.Flag("success", r.success, "1 when the impact was measured");
  a.Text("error", r.error, "why the trial failed (empty on success)");
  a.TextList("flags", r.flags, "short tags: out_of_plane, surface_angle, ...");
  a.TextList("warnings", r.warnings, "warnings in words");
}

/// The measured columns of one impact, shared by `/results` (the trial's main impact) and
/// `/impacts` (every impact): impact_time_s to kinetic_energy_after_J.
template <class Archive, class R>
void SerializeImpactMeasures(Archive& a, R& r) {
  const std::string S = " (S: x along the surface, down-slope; y the outward normal)";
  a.Number("impact_time_s", r.impact_time_s, "s", "impact time since frame 0");
  a.Number("e", r.e, "1", "normal coefficient of restitution");
  a.Number("e_se", r.e_se, "1", "standard error of e");
  a.Number("e_ci_low", r.e_ci_low, "1", "lower end of the confidence interval of e");
  a.Number("e_ci_high", r.e_ci_high, "1", "upper end of the confidence interval of e");
  a.Number("mu_eff", r.mu_eff, "1", "effective friction coefficient");
  a.Number("mu_eff_se", r.mu_eff_se, "1", "standard error of mu_eff");
  a.Number("mu_eff_ci_low", r.mu_eff_ci_low, "1", "lower end of the confidence interval of mu_eff");
  a.Number("mu_eff_ci_high", r.mu_eff_ci_high, "1",
           "upper end of the confidence interval of mu_eff");
  a.Number("v_SC_before_x_m_s", r.v_SC_before_m_s[0], "m/s",
           "velocity of C before, along the surface" + S);
  a.Number("v_SC_before_y_m_s", r.v_SC_before_m_s[1], "m/s", "velocity of C before, normal" + S);
  a.Number("v_SC_after_x_m_s", r.v_SC_after_m_s[0], "m/s",
           "velocity of C after, along the surface" + S);
  a.Number("v_SC_after_y_m_s", r.v_SC_after_m_s[1], "m/s", "velocity of C after, normal" + S);
  a.Number("v_SC_before_se_x_m_s", r.v_SC_before_se_m_s[0], "m/s",
           "standard error of v_SC_before_x_m_s");
  a.Number("v_SC_before_se_y_m_s", r.v_SC_before_se_m_s[1], "m/s",
           "standard error of v_SC_before_y_m_s");
  a.Number("v_SC_after_se_x_m_s", r.v_SC_after_se_m_s[0], "m/s",
           "standard error of v_SC_after_x_m_s");
  a.Number("v_SC_after_se_y_m_s", r.v_SC_after_se_m_s[1], "m/s",
           "standard error of v_SC_after_y_m_s");
  a.Number("w_before_rad_s", r.w_before_rad_s, "rad/s", "angular velocity before");
  a.Number("w_after_rad_s", r.w_after_rad_s, "rad/s", "angular velocity after");
  a.Number("w_before_se_rad_s", r.w_before_se_rad_s, "rad/s", "standard error of w_before_rad_s");
  a.Number("w_after_se_rad_s", r.w_after_se_rad_s, "rad/s", "standard error of w_after_rad_s");
  a.Number("kinetic_energy_before_J", r.kinetic_energy_before_J, "J", "kinetic energy before");
  a.Number("kinetic_energy_after_J", r.kinetic_energy_after_J, "J", "kinetic energy after");
}

/// The columns of `/results`, one row per trial (also what WriteResultsCsv writes). The
/// reader takes a trial's flags from its group, where each is one element: here they are
/// joined with ';'.
template <class Archive, class R>
requires std::is_same_v<std::remove_const_t<R>, TrialResult>
void SerializeResult(Archive& a, R& r) {
  a.Text("id", r.id, "trial id");
  a.Text("group", r.group, "the trial's group in this file");
  a.Text("dir", r.dir, "trial folder");
  a.Text("specimen", r.specimen, "specimen id");
  a.Text("surface", r.surface, "surface name");
  a.Number("surface_angle_deg", r.surface_angle_deg, "deg", "surface angle (trial.json)");
  a.Number("fps", r.fps, "1/s", "frame rate");
  a.Number("nominal_speed_m_s", r.nominal_speed_m_s, "m/s",
           "nominal impact speed (NaN when not given)");
  a.Flag("success", r.success, "1 when the impact was measured");
  a.Text("error", r.error, "why the trial failed (empty on success)");
  SerializeImpactMeasures(a, r);
  a.Number("m_per_px_used", r.m_per_px_used, "m/px", "scale the analysis used");
  a.Number("m_per_px_from_markers", r.m_per_px_from_markers, "m/px",
           "scale from the marker spacing (NaN when not measured)");
  a.Number("surface_angle_measured_deg", r.surface_angle_measured_deg, "deg",
           "surface angle measured (NaN when not measured)");
  a.Number("out_of_plane_change", r.out_of_plane_change, "1",
           "range of the projected marker distance ratio");
  if constexpr (std::remove_cvref_t<Archive>::kWriting) {
    a.Text("flags", Join(r.flags, ";"), "flags joined with ';'");
  } else {
    std::string joined;  // read from the trial's group instead (ReadStudyResults)
    a.Text("flags", joined, "flags joined with ';'");
  }
}

/// The columns of `/impacts`, one row per impact of each trial (also what WriteImpactsCsv writes).
template <class Archive, class R>
requires std::is_same_v<std::remove_const_t<R>, ImpactResult>
void SerializeImpact(Archive& a, R& r) {
  a.Text("trial", r.trial, "trial id");
  a.Text("group", r.group, "the trial's group in this file");
  a.Integer("impact_index", r.impact_index, "1", "place of the impact in the clip, 0 = first");
  a.Integer("lowest_frame", r.lowest_frame, "frame",
            "frame where the impact was found (the round end lowest near it)");
  a.Flag("main", r.is_main, "1 for the impact that is the trial's result in /results");
  a.Flag("success", r.success, "1 when the impact was measured");
  a.Text("error", r.error, "why the impact was not measured (empty when it was)");
  a.Integer("impact_frame", r.impact_frame, "frame",
            "last frame before the impact (the lowest frame when not measured)");
  SerializeImpactMeasures(a, r);
  a.Integer("fit_before_first_frame", r.fit_before_first_frame, "frame",
            "first frame of the fit before the impact (-1 when not measured)");
  a.Integer("fit_before_last_frame", r.fit_before_last_frame, "frame",
            "last frame of the fit before the impact");
  a.Integer("fit_after_first_frame", r.fit_after_first_frame, "frame",
            "first frame of the fit after the impact");
  a.Integer("fit_after_last_frame", r.fit_after_last_frame, "frame",
            "last frame of the fit after the impact");
  // Columns added after files were written: older files read with their defaults.
  constexpr auto kLater = Presence::kAddedLater;
  a.Text("method", r.method,
         "how it was measured: windows (about the impact) or arcs (the joint "
         "fit of every flight arc)",
         kLater);
  a.Number("impact_time_se_s", r.impact_time_se_s, "s",
           "standard error of impact_time_s (NaN from the windows)", kLater);
  a.Number("surface_angle_W_deg", r.surface_angle_W_deg, "deg",
           "the surface's angle in W that S was built from (the arcs add gravity's fitted roll)",
           kLater);
  a.Number("p_WT_x_m", r.p_WT_m[0], "m",
           "contact point where the arcs meet, x in W (NaN from the "
           "windows)",
           kLater);
  a.Number("p_WT_y_m", r.p_WT_m[1], "m", "contact point where the arcs meet, y in W", kLater);
  a.Integer("samples_before", r.samples_before, "frame", "positions fitted before the impact",
            kLater);
  a.Integer("samples_after", r.samples_after, "frame", "positions fitted after the impact", kLater);
  a.Integer("contact_frames", r.contact_frames, "frame",
            "frames beside the contact left out (touching, or blurred across it)", kLater);
  a.Integer("outlier_frames", r.outlier_frames, "frame",
            "frames of the two arcs left out as outliers", kLater);
  a.Integer("not_in_flight_frames", r.not_in_flight_frames, "frame",
            "frames before the first arc or after the last not on it (held, rolling)", kLater);
  a.Integer("missing_frames", r.missing_frames, "frame",
            "frames within the two arcs without a position", kLater);
  a.Integer("repeated_frames", r.repeated_frames, "frame",
            "frames within the two arcs that repeat the previous image", kLater);
  a.Flag("short_arc", r.short_arc, "1 when an arc beside it is too short to measure it", kLater);
  a.Number("depth_rate_before_per_s", r.depth_rate_before_per_s, "1/s",
           "relative rate of the depth's change before, from the apparent size (NaN without it)",
           kLater);
  a.Number("depth_rate_after_per_s", r.depth_rate_after_per_s, "1/s",
           "relative rate of the depth's change after", kLater);
  a.Flag("depth_corrected", r.depth_corrected, "1 when e is corrected for the depth motion",
         kLater);
  a.Number("e_depth_shift", r.e_depth_shift, "1",
           "e corrected for the depth motion minus e uncorrected (NaN when not measured)", kLater);
  a.Number("e_perspective_shift", r.e_perspective_shift, "1",
           "e from the arcs rectified for a plane seen at a slant minus e as seen (NaN when not "
           "applied)",
           kLater);
  a.Number("meeting_gap_m", r.meeting_gap_m, "m",
           "the arcs' distance along the surface where they meet (NaN from the windows)", kLater);
  a.Number("meeting_gap_se_m", r.meeting_gap_se_m, "m", "its standard error", kLater);
}

}  // namespace hoof::studyfile::internal
