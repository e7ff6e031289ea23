#include "cli/trial_output.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "cli/common_options.h"
#include "format/number_format.h"
#include "io/csv.h"
#include "report/figures.h"

namespace hoof::cli {

void AddAnalysisOptions(CLI::App* cmd, pipeline::TrialAnalysisOptions& options,
                        std::string& method) {
  cmd->add_option("--method", method, "Sub-pixel dot centre: centroid or ellipse")
      ->capture_default_str();
  cmd->add_option("--fit-frames", options.kinematics.fit_frames,
                  "Frames per flight fit before and after the impact")
      ->capture_default_str();
  cmd->add_option("--min-fit-frames", options.kinematics.min_fit_frames,
                  "Fewest usable frames per flight fit, before and after (fewer is an error)")
      ->capture_default_str();
  cmd->add_option("--max-contact-s", options.kinematics.max_contact_s,
                  "Longest contact assumed when leaving frames out of the fits (s)")
      ->capture_default_str();
  cmd->add_option("--exposure-s", options.kinematics.exposure_s,
                  "Exposure time (s); default one frame period")
      ->capture_default_str();
  cmd->add_option_function<std::string>(
         "--kinematics",
         [&options](const std::string& m) {
           options.kinematics.method = kinematics::ParseKinematicsMethod(m);
         },
         "How impacts are measured: auto (the windows of --fit-frames frames where every window "
         "fills, else the joint fit of every flight arc with one fitted acceleration), windows "
         "or arcs")
      ->check(CLI::IsMember({"auto", "windows", "arcs"}))
      ->default_str("auto");
  cmd->add_flag_callback(
      "--correct-depth", [&options] { options.kinematics.arcs.correct_depth = true; },
      "Joint arcs: correct the positions for a ball's motion in depth (from its apparent size "
      "and the principal point) where the size changes significantly; by default the shift of e "
      "it would make is only reported");
  cmd->add_flag_callback(
      "--no-perspective", [&options] { options.kinematics.arcs.correct_perspective = false; },
      "Joint arcs: fit the positions as seen, without the perspective of a plane seen at a "
      "slant (by default fitted along gravity and applied where it fits the arcs "
      "significantly better)");
  cmd->add_flag("--scale-from-markers", options.scale_from_markers,
                "Take the scale from the marker spacing instead of camera.m_per_px");
  cmd->add_flag_callback(
      "--no-frame-timing", [&options] { options.timing.enabled = false; },
      "Take every frame as a new capture at index / fps: no search for repeated frames or "
      "dropped captures");
  cmd->add_flag_callback(
      "--drops-from-motion", [&options] { options.timing.drops_from_motion = true; },
      "Where the file has no time stamps, look for dropped captures in the body's motion (a "
      "step a free-flight parabola explains only with a capture left out); off by default, as a "
      "contact's frames can be taken for a drop");
  // Out-of-range values are command-line errors (exit 2), found before any trial is read.
  cmd->parse_complete_callback([cmd, &options] {
    ValidateOptions(cmd, [&] {
      options.kinematics.Validate();
      options.tracker.Validate();
    });
  });
}

void ApplyMethod(const std::string& method, pipeline::TrialAnalysisOptions& options) {
  if (method == "centroid")
    options.tracker.detector.method = tracking::CentreMethod::kWeightedCentroid;
  else if (method == "ellipse")
    options.tracker.detector.method = tracking::CentreMethod::kEllipseFit;
  else
    throw CLI::ValidationError("--method", "\"" + method + "\" is invalid: centroid or ellipse");
}

namespace {

/// The measured quantities of one impact, with the names of the columns of /results and
/// results.csv (studyfile/schema.h).
nlohmann::json ImpactJson(const kinematics::ImpactKinematics& k) {
  return nlohmann::json({{"impact_time_s", k.impact_time_s},
                         {"impact_frame", k.impact_frame},
                         {"impact_index", k.index},
                         {"v_SC_before_m_s", JsonVector(k.v_SC_before)},
                         {"v_SC_after_m_s", JsonVector(k.v_SC_after)},
                         {"v_SC_before_se_m_s", JsonVector(k.v_SC_before_se)},
                         {"v_SC_after_se_m_s", JsonVector(k.v_SC_after_se)},
                         {"v_ST_before_m_s", JsonVector(k.v_ST_before)},
                         {"v_ST_after_m_s", JsonVector(k.v_ST_after)},
                         {"w_before_rad_s", JsonNumber(k.w_before_rad_s)},
                         {"w_after_rad_s", JsonNumber(k.w_after_rad_s)},
                         {"w_before_se_rad_s", JsonNumber(k.w_before_se_rad_s)},
                         {"w_after_se_rad_s", JsonNumber(k.w_after_se_rad_s)},
                         {"e", JsonNumber(k.e)},
                         {"e_se", JsonNumber(k.e_se)},
                         {"e_ci_low", JsonNumber(k.e_ci_low)},
                         {"e_ci_high", JsonNumber(k.e_ci_high)},
                         {"mu_eff", JsonNumber(k.mu_eff)},
                         {"mu_eff_se", JsonNumber(k.mu_eff_se)},
                         {"mu_eff_ci_low", JsonNumber(k.mu_eff_ci_low)},
                         {"mu_eff_ci_high", JsonNumber(k.mu_eff_ci_high)},
                         {"kinetic_energy_before_J", JsonNumber(k.kinetic_energy_before_J)},
                         {"kinetic_energy_after_J", JsonNumber(k.kinetic_energy_after_J)},
                         {"kinetic_energy_before_se_J", JsonNumber(k.kinetic_energy_before_se_J)},
                         {"kinetic_energy_after_se_J", JsonNumber(k.kinetic_energy_after_se_J)},
                         {"fit_frames_before", {k.before.first_frame, k.before.last_frame}},
                         {"fit_frames_after", {k.after.first_frame, k.after.last_frame}},
                         {"fit_rms_residual_m", {k.before.rms_residual_m, k.after.rms_residual_m}},
                         {"impact_time_se_s", JsonNumber(k.impact_time_se_s)},
                         {"surface_angle_W_deg", JsonNumber(k.surface_angle_W_deg)},
                         {"p_WT_m", JsonVector(k.p_WT)}});
}

/// What limited an impact (kinematics::ImpactLimits).
nlohmann::json LimitsJson(const kinematics::ImpactLimits& L) {
  return {{"samples_before", L.samples_before},
          {"samples_after", L.samples_after},
          {"contact_frames", L.contact_frames},
          {"outlier_frames", L.outlier_frames},
          {"not_in_flight_frames", L.not_in_flight_frames},
          {"missing_frames", L.missing_frames},
          {"repeated_frames", L.repeated_frames},
          {"short_arc", L.short_arc},
          {"depth_rate_before_per_s", JsonNumber(L.depth_rate_before_per_s)},
          {"depth_rate_after_per_s", JsonNumber(L.depth_rate_after_per_s)},
          {"depth_corrected", L.depth_corrected},
          {"e_depth_shift", JsonNumber(L.e_depth_shift)},
          {"e_perspective_shift", JsonNumber(L.e_perspective_shift)},
          {"meeting_gap_m", JsonNumber(L.meeting_gap_m)},
          {"meeting_gap_se_m", JsonNumber(L.meeting_gap_se_m)},
          {"spin_before", L.spin_before},
          {"spin_after", L.spin_after}};
}

/// The joint arc fit (kinematics/flight_arcs.h): gravity's fitted acceleration and direction,
/// the arcs, and every frame the fit left out with its reason.
nlohmann::json ArcsJson(const kinematics::FlightArcs& A) {
  nlohmann::json arcs = nlohmann::json::array(), left_out = nlohmann::json::array();
  for (const auto& a : A.arcs)
    arcs.push_back({{"first_frame", a.first_frame},
                    {"last_frame", a.last_frame},
                    {"samples", a.n},
                    {"fitted", a.fitted},
                    {"rms_residual", JsonNumber(a.rms_residual)},
                    {"depth_rate_per_s", JsonNumber(a.depth_rate_per_s)},
                    {"depth_rate_se_per_s", JsonNumber(a.depth_rate_se_per_s)}});
  for (std::size_t f = 0; f < A.frames.size(); ++f) {
    const auto role = A.frames[f].role;
    if (role == kinematics::ArcFrameRole::kArc) continue;
    left_out.push_back({{"frame", f}, {"reason", kinematics::ArcFrameRoleName(role)}});
  }
  return {{"fitted", A.status == kinematics::ArcFitStatus::kFitted},
          {"message", A.message},
          {"a_W", JsonVector(A.a_W)},
          {"a_norm", JsonNumber(A.a_norm)},
          {"a_norm_se", JsonNumber(A.a_norm_se)},
          {"roll_deg", JsonNumber(A.roll_deg)},
          {"roll_se_deg", JsonNumber(A.roll_se_deg)},
          {"sigma", JsonNumber(A.sigma)},
          {"weighted", A.weighted},
          {"samples_used", A.samples_used},
          {"dof", A.dof},
          {"depth_measured", A.depth_measured},
          {"depth_applied", A.depth_applied},
          {"perspective_applied", A.perspective_applied},
          {"perspective_h", JsonVector(A.perspective_h)},
          {"perspective_depth_range", JsonNumber(A.perspective_depth_range)},
          {"perspective_chi2_drop", JsonNumber(A.perspective_chi2_drop)},
          {"arcs", arcs},
          {"frames_left_out", left_out}};
}

}  // namespace

nlohmann::json ImpactEntryJson(const kinematics::ImpactKinematics& k) {
  nlohmann::json j = {{"impact_index", k.index},
                      {"lowest_frame", k.lowest_frame},
                      {"success", k.success},
                      {"error", k.success ? std::string() : k.message},
                      {"method", kinematics::KinematicsMethodName(k.method)},
                      {"limits", LimitsJson(k.limits)}};
  if (k.success)
    j.update(ImpactJson(k));
  else
    j.update({{"impact_time_s", k.impact_time_s}, {"impact_frame", k.impact_frame}});
  return j;
}

nlohmann::json FrameTimingJson(const tracking::FrameTiming& t) {
  nlohmann::json j = {{"source", tracking::TimingSourceName(t.source)},
                      {"repeated_frames", t.repeated_frames},
                      {"dropped_captures", t.dropped_captures},
                      {"capture_slots", t.slot},
                      {"notes", t.notes}};
  if (!t.differences.mean_abs_difference.empty()) {
    nlohmann::json d = nlohmann::json::array();
    for (double x : t.differences.mean_abs_difference) d.push_back(JsonNumber(x));
    j["mean_abs_difference"] = d;
    j["noise_mean_abs_difference"] = JsonNumber(t.differences.noise_mean_abs_difference);
  }
  return j;
}

nlohmann::json TrialJson(const pipeline::TrialAnalysis& r) {
  const auto& k = r.impact;
  nlohmann::json j = {
      {"id", r.spec.id},
      {"dir", r.spec.dir.string()},
      {"specimen", r.spec.specimen_id},
      {"surface", r.spec.surface},
      {"surface_angle_deg", r.spec.surface_angle_deg},
      {"fps", r.spec.fps},
      {"nominal_speed_m_s",
       r.spec.nominal_speed_m_s ? JsonNumber(*r.spec.nominal_speed_m_s) : nlohmann::json(nullptr)},
      {"success", r.success},
      {"error", r.error},
      {"flags", r.flags},
      {"warnings", r.warnings},
      {"seconds", r.seconds},
      {"m_per_px_used", JsonNumber(r.m_per_px_used)},
      {"m_per_px_from_markers", JsonNumber(r.m_per_px_from_markers)},
      {"surface_angle_measured_deg", r.surface_angle_measured_deg
                                         ? JsonNumber(*r.surface_angle_measured_deg)
                                         : nlohmann::json(nullptr)},
      {"out_of_plane_change", r.out_of_plane_change},
      {"out_of_plane_noise", r.out_of_plane_noise},
      {"body_model", r.spec.body.model},
      {"scale_source", r.scale_source},
      {"m_per_px_se", JsonNumber(r.m_per_px_se)},
      {"no_impact", r.no_impact}};
  if (r.gravity_scale) {
    const auto& g = *r.gravity_scale;
    nlohmann::json arcs = nlohmann::json::array();
    for (const auto& a : g.arcs) arcs.push_back({a.first_frame, a.last_frame});
    j["gravity_scale"] = {{"measured", g.measured},
                          {"message", g.message},
                          {"a_px_s2", JsonVector(g.a_px_s2)},
                          {"a_norm_px_s2", JsonNumber(g.a_norm_px_s2)},
                          {"a_norm_se_px_s2", JsonNumber(g.a_norm_se_px_s2)},
                          {"m_per_px", JsonNumber(g.m_per_px)},
                          {"m_per_px_se", JsonNumber(g.m_per_px_se)},
                          {"direction_error_deg", JsonNumber(g.direction_error_deg)},
                          {"arcs", arcs},
                          {"contact_frames", g.contact_frames},
                          {"frames_used", g.frames_used},
                          {"rms_residual_px", JsonNumber(g.rms_residual_px)}};
  }
  if (r.calibration_scale) {
    const auto& c = *r.calibration_scale;
    j["calibration_scale"] = {{"kind", r.spec.camera.scale_from},
                              {"m_per_px", JsonNumber(c.m_per_px)},
                              {"m_per_px_se", JsonNumber(c.m_per_px_se)},
                              {"points", c.points},
                              {"rms_residual_px", JsonNumber(c.rms_residual_px)},
                              {"angle_deg", JsonNumber(c.angle_deg)}};
  }
  j["frame_timing"] = FrameTimingJson(r.timing);
  if (r.spec.body.is_silhouette()) {
    j["body_shape"] = r.spec.body.shape;
    j["polarity"] = tracking::PolarityName(r.silhouette.polarity);
    j["body_diameter_px"] = JsonNumber(r.body_diameter_px);
    j["body_diameter_se_px"] = JsonNumber(r.body_diameter_se_px);
    j["m_per_px_from_body"] = JsonNumber(r.m_per_px_from_body);
    if (r.round_end) {
      const auto& e = *r.round_end;
      j["round_end"] = {{"measured", e.measured},
                        {"message", e.message},
                        {"p_BE_px", JsonVector(e.p_BE_px)},
                        {"p_BE_se_px", JsonVector(e.p_BE_se_px)},
                        {"radius_px", JsonNumber(e.radius_px)},
                        {"radius_se_px", JsonNumber(e.radius_se_px)},
                        {"frames_used", e.frames_used},
                        {"frames_tried", e.frames_tried}};
    }
  }
  if (r.no_impact) {
    const auto& m = r.motion;
    j["motion"] = {{"frames_tracked", m.frames_tracked},
                   {"fit", m.gravity_fit ? "gravity" : "straight line"},
                   {"v_px_per_frame", JsonVector(m.v_px_per_frame)},
                   {"speed_px_per_frame", JsonNumber(m.speed_px_per_frame)},
                   {"speed_se_px_per_frame", JsonNumber(m.speed_se_px_per_frame)},
                   {"speed_m_s", JsonNumber(m.speed_m_s)},
                   {"speed_se_m_s", JsonNumber(m.speed_se_m_s)},
                   {"rms_residual_px", JsonNumber(m.rms_residual_px)}};
  }
  if (k.success) j.update(ImpactJson(k));
  j["kinematics_method"] = kinematics::KinematicsMethodName(r.kinematics_method);
  if (r.arcs) j["arcs"] = ArcsJson(*r.arcs);
  if (r.contact_line) {
    const auto& L = *r.contact_line;
    j["contact_line"] = {{"measured", L.measured},
                         {"message", L.message},
                         {"impacts", L.impacts},
                         {"p_W_m", JsonVector(L.p_W)},
                         {"level_m", JsonNumber(L.level_m)},
                         {"level_se_m", JsonNumber(L.level_se_m)},
                         {"angle_measured", L.angle_measured},
                         {"angle_deg", JsonNumber(L.angle_deg)},
                         {"angle_se_deg", JsonNumber(L.angle_se_deg)},
                         {"rms_residual_m", JsonNumber(L.rms_residual_m)}};
  }
  if (r.capture_rate) {
    const auto& c = *r.capture_rate;
    j["capture_rate"] = {{"measured", c.measured},
                         {"message", c.message},
                         {"container_fps", JsonNumber(c.container_fps)},
                         {"capture_fps", JsonNumber(c.capture_fps)},
                         {"capture_fps_se", JsonNumber(c.capture_fps_se)},
                         {"ratio", JsonNumber(c.ratio)},
                         {"ratio_se", JsonNumber(c.ratio_se)},
                         {"nearest_ratio", c.nearest_ratio},
                         {"nearest_ratio_z", JsonNumber(c.nearest_ratio_z)}};
  }
  // Every impact of the clip, each measured on its own (pipeline/trial_impacts.h).
  j["impacts"] = nlohmann::json::array();
  for (const auto& i : r.impacts) j["impacts"].push_back(ImpactEntryJson(i));
  return j;
}

namespace {

/// What limited an impact, in words: its samples, the frames left out and why, the depth.
std::string LimitsText(const kinematics::ImpactLimits& L) {
  std::ostringstream os;
  os << L.samples_before << " + " << L.samples_after << " frames";
  const auto frames = [&](const char* what, const std::vector<int>& v) {
    if (v.empty()) return;
    os << "; " << what << " ";
    for (std::size_t i = 0; i < v.size(); ++i) os << (i ? "," : "") << v[i];
  };
  frames("contact frames left out", L.contact_frames);
  frames("outliers", L.outlier_frames);
  frames("not in flight", L.not_in_flight_frames);
  frames("no position", L.missing_frames);
  frames("repeated", L.repeated_frames);
  if (std::isfinite(L.e_depth_shift))
    os << "; depth motion: e " << (L.depth_corrected ? "corrected by " : "would move by ")
       << format::Number(L.e_depth_shift, format::Kind::kCoefficient);
  if (std::isfinite(L.e_perspective_shift))
    os << "; slanted view: e corrected by "
       << format::Number(L.e_perspective_shift, format::Kind::kCoefficient);
  if (!L.spin_before.empty() || !L.spin_after.empty())
    os << "; spin before " << L.spin_before << ", after " << L.spin_after;
  return os.str();
}

}  // namespace

std::string ImpactsText(const pipeline::TrialAnalysis& r) {
  using format::Kind;
  std::ostringstream os;
  os << "  impacts: " << r.impacts.size() << " in the clip ("
     << kinematics::KinematicsMethodName(r.kinematics_method)
     << "); the trial's result above is impact " << r.impact.index << "\n";
  for (const auto& k : r.impacts) {
    os << "    " << k.index << ": ";
    if (!k.success) {
      os << "near frame " << k.lowest_frame << ", not measured: " << k.message << "\n";
      continue;
    }
    os << "t* " << format::WithError(k.impact_time_s * 1e3, k.impact_time_se_s * 1e3)
       << " ms (after frame " << k.impact_frame << "), v_SC_y "
       << format::Number(k.v_SC_before.y(), Kind::kMeasured) << " -> "
       << format::Number(k.v_SC_after.y(), Kind::kMeasured) << " m/s, e "
       << format::WithError(k.e, k.e_se, Kind::kCoefficient) << ", mu_eff "
       << format::WithError(k.mu_eff, k.mu_eff_se, Kind::kCoefficient);
    if (std::isfinite(k.w_before_rad_s) || std::isfinite(k.w_after_rad_s))
      os << ", w " << format::WithError(k.w_before_rad_s, k.w_before_se_rad_s) << " -> "
         << format::WithError(k.w_after_rad_s, k.w_after_se_rad_s) << " rad/s";
    os << "; " << LimitsText(k.limits) << "\n";
  }
  return os.str();
}

std::string TrialText(const pipeline::TrialAnalysis& r) {
  using format::Kind;
  const auto num = [](double v, Kind kind = Kind::kMeasured) { return format::Number(v, kind); };
  const auto vec = [&](const Eigen::Vector2d& v, Kind kind = Kind::kMeasured) {
    return "[" + num(v.x(), kind) + ", " + num(v.y(), kind) + "]";
  };
  std::ostringstream os;
  os << "Trial " << r.spec.id << " (" << r.spec.surface << ", " << num(r.spec.surface_angle_deg)
     << " deg): ";
  if (r.no_impact) {
    os << "no impact in the clip (e is not measured): " << r.error << "\n";
  } else if (!r.success) {
    os << "FAILED: " << r.error << "\n";
  } else {
    const auto& k = r.impact;
    os << "impact at " << num(k.impact_time_s * 1e3) << " ms (after frame " << k.impact_frame
       << ")\n";
    os << "  v_SC before  " << vec(k.v_SC_before) << " m/s, s.e. "
       << vec(k.v_SC_before_se, Kind::kError) << "\n";
    os << "  v_SC after   " << vec(k.v_SC_after) << " m/s, s.e. "
       << vec(k.v_SC_after_se, Kind::kError) << "\n";
    os << "  w before/after  " << format::WithError(k.w_before_rad_s, k.w_before_se_rad_s) << " / "
       << format::WithError(k.w_after_rad_s, k.w_after_se_rad_s) << " rad/s\n";
    if (!k.limits.spin_before.empty() || !k.limits.spin_after.empty())
      os << "  spin    before " << k.limits.spin_before << "; after " << k.limits.spin_after
         << "\n";
    os << "  e       " << format::WithError(k.e, k.e_se, Kind::kCoefficient) << "  (95 % "
       << format::Interval(k.e_ci_low, k.e_ci_high, Kind::kCoefficient) << ")\n";
    os << "  mu_eff  " << format::WithError(k.mu_eff, k.mu_eff_se, Kind::kCoefficient) << "  (95 % "
       << format::Interval(k.mu_eff_ci_low, k.mu_eff_ci_high, Kind::kCoefficient) << ")\n";
    os << "  fits    frames " << k.before.first_frame << "-" << k.before.last_frame << " and "
       << k.after.first_frame << "-" << k.after.last_frame << ", rms residual "
       << num(k.before.rms_residual_m * 1e6, Kind::kError) << " / "
       << num(k.after.rms_residual_m * 1e6, Kind::kError) << " µm\n";
  }
  if (r.impacts.size() > 1 || r.kinematics_method == kinematics::KinematicsMethod::kArcs)
    os << ImpactsText(r);
  if (r.arcs && r.arcs->status == kinematics::ArcFitStatus::kFitted) {
    const auto& A = *r.arcs;
    os << "  arcs    " << A.arcs.size() << " flight arcs, " << A.samples_used
       << " frames fitted; |a| " << format::WithError(A.a_norm, A.a_norm_se)
       << (std::isfinite(r.m_per_px_used) ? " m/s^2" : " px/s^2") << ", up "
       << format::WithError(A.roll_deg, A.roll_se_deg) << " deg from the image's up\n";
  }
  if (r.contact_line && r.contact_line->measured) {
    const auto& L = *r.contact_line;
    os << "  contact line  level " << format::WithError(L.level_m, L.level_se_m) << " along up";
    if (L.angle_measured)
      os << ", angle " << format::WithError(L.angle_deg, L.angle_se_deg) << " deg";
    os << " (" << L.impacts << " impacts)\n";
  }
  if (r.capture_rate && r.capture_rate->measured)
    os << "  time base  gravity implies "
       << format::WithError(r.capture_rate->capture_fps, r.capture_rate->capture_fps_se)
       << " captures a second (trial.json: " << num(r.spec.fps) << ")\n";
  if (r.no_impact) {
    const auto& m = r.motion;
    os << "  motion  " << m.frames_tracked << " frames tracked; speed "
       << format::WithError(m.speed_px_per_frame, m.speed_se_px_per_frame) << " px per frame, "
       << format::WithError(m.speed_m_s, m.speed_se_m_s) << " m/s; rms residual about its "
       << (m.gravity_fit ? "gravity" : "straight-line") << " fit "
       << num(m.rms_residual_px, Kind::kError) << " px\n";
  }
  if (r.surface_angle_measured_deg)
    os << "  surface angle measured " << num(*r.surface_angle_measured_deg) << " deg\n";
  if (r.spec.body.is_silhouette()) {
    os << "  body    silhouette, " << r.spec.body.shape << ", "
       << tracking::PolarityName(r.silhouette.polarity);
    if (r.spec.body.is_ball())
      os << ", diameter " << format::WithError(r.body_diameter_px, r.body_diameter_se_px) << " px";
    os << "\n";
    os << "  scale " << format::WithError(r.m_per_px_used, r.m_per_px_se) << " m/px from "
       << r.scale_source;
    if (r.scale_source != "body.diameter_m" && std::isfinite(r.m_per_px_from_body))
      os << " (from the ball's diameter: " << num(r.m_per_px_from_body) << ")";
    os << "\n";
  } else {
    os << "  scale " << format::WithError(r.m_per_px_used, r.m_per_px_se) << " m/px from "
       << r.scale_source << " (from the markers: " << num(r.m_per_px_from_markers) << ")\n";
    os << "  projected marker distance changes by "
       << num(100 * r.out_of_plane_change, Kind::kError) << " % (noise "
       << num(100 * r.out_of_plane_noise, Kind::kError) << " %)\n";
  }
  if (r.calibration_scale) {
    const auto& c = *r.calibration_scale;
    os << "  " << r.scale_source << ": " << c.points
       << (r.scale_source == "checkerboard" ? " corners" : " ticks") << ", rms residual "
       << num(c.rms_residual_px, Kind::kError) << " px\n";
  }
  if (!r.timing.slot.empty()) {
    const auto list = [](const std::vector<int>& v) {
      std::string s;
      for (int x : v) s += (s.empty() ? "" : ", ") + std::to_string(x);
      return v.empty() ? std::string("none") : s;
    };
    os << "  timing  slots from " << tracking::TimingSourceName(r.timing.source)
       << "; repeated frames: " << list(r.timing.repeated_frames)
       << "; dropped captures: " << list(r.timing.dropped_captures) << "\n";
  }
  if (!r.flags.empty()) {
    os << "  flags:";
    for (const auto& f : r.flags) os << " " << f;
    os << "\n";
  }
  for (const auto& w : r.warnings) os << "  warning: " << w << "\n";
  return os.str();
}

std::string TracksCsv(const pipeline::TrialAnalysis& r) {
  std::ostringstream os;
  if (r.spec.body.is_silhouette()) {
    // Per frame: the silhouette's centre (px) with its s.d., its orientation and diameter.
    os << "trial,frame,t_s,status,x_px,y_px,sd_x_px,sd_y_px,angle_I_rad,angle_se_rad,"
          "diameter_px,diameter_se_px,edge_points,edge_points_rejected,rms_residual_px,"
          "pose_valid,p_WE_x_m,p_WE_y_m,theta_W_rad\n";
    for (std::size_t f = 0; f < r.silhouette.frames.size(); ++f) {
      const auto& o = r.silhouette.frames[f];
      os << io::CsvEscape(r.spec.id) << "," << f << ","
         << io::CsvNumber(static_cast<double>(f) / r.spec.fps) << "," << io::CsvEscape(o.status);
      if (o.found) {
        os << "," << io::CsvNumber(o.p_I.x()) << "," << io::CsvNumber(o.p_I.y()) << ","
           << io::CsvNumber(std::sqrt(o.cov_p_I(0, 0))) << ","
           << io::CsvNumber(std::sqrt(o.cov_p_I(1, 1))) << ","
           << (o.has_orientation ? io::CsvNumber(o.angle_I_rad) : "") << ","
           << (o.has_orientation ? io::CsvNumber(o.angle_se_rad) : "") << ","
           << (o.has_orientation ? "" : io::CsvNumber(o.diameter_px)) << ","
           << (o.has_orientation ? "" : io::CsvNumber(o.diameter_se_px)) << "," << o.edge_points
           << "," << o.edge_points_rejected << "," << io::CsvNumber(o.rms_residual_px);
      } else {
        os << ",,,,,,,,,,,";
      }
      if (f < r.poses.size() && r.poses[f].valid)
        os << ",1," << io::CsvNumber(r.poses[f].p_WE.x()) << ","
           << io::CsvNumber(r.poses[f].p_WE.y()) << "," << io::CsvNumber(r.poses[f].theta_W_rad);
      else
        os << ",0,,,";
      os << "\n";
    }
    return os.str();
  }
  os << "trial,frame,t_s";
  for (const auto& n : r.tracks.names)
    os << "," << n << "_x_px," << n << "_y_px," << n << "_status," << n << "_quality";
  os << ",pose_valid,p_WE_x_m,p_WE_y_m,theta_W_rad,pose_rms_m\n";
  for (std::size_t f = 0; f < r.tracks.frames.size(); ++f) {
    os << io::CsvEscape(r.spec.id) << "," << f << ","
       << io::CsvNumber(static_cast<double>(f) / r.spec.fps);
    for (std::size_t m = 0; m < r.tracks.names.size(); ++m) {
      const auto& row = r.tracks.frames[f];
      if (m < row.size() && row[m].found)
        os << "," << io::CsvNumber(row[m].p_I.x()) << "," << io::CsvNumber(row[m].p_I.y()) << ","
           << row[m].status << "," << io::CsvNumber(row[m].quality);
      else
        os << ",,," << (m < row.size() ? row[m].status : "") << ",0";
    }
    if (f < r.poses.size() && r.poses[f].valid)
      os << ",1," << io::CsvNumber(r.poses[f].p_WE.x()) << "," << io::CsvNumber(r.poses[f].p_WE.y())
         << "," << io::CsvNumber(r.poses[f].theta_W_rad) << ","
         << io::CsvNumber(r.poses[f].rms_residual_m);
    else
      os << ",0,,,,";
    os << "\n";
  }
  return os.str();
}

}  // namespace hoof::cli
