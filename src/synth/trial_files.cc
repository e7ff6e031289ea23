#include "synth/trial_files.h"

#include <cmath>

#include "synth/calibration_image.h"
#include "synth/camera_model.h"

namespace hoof::synth {
namespace {

nlohmann::json Num(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}
nlohmann::json Vec(const Eigen::Vector2d& v) {
  return nlohmann::json::array({Num(v.x()), Num(v.y())});
}

nlohmann::json MarkerMap(const SpecimenGeometry& g, const std::vector<Eigen::Vector2d>& px) {
  nlohmann::json m = nlohmann::json::object();
  for (std::size_t i = 0; i < g.markers.size(); ++i) m[g.markers[i].name] = Vec(px[i]);
  return m;
}

nlohmann::json FrameJson(const FrameTruth& f, const SpecimenGeometry& g, int index) {
  nlohmann::json j = {
      {"index", index},
      {"capture_index", f.capture_index},
      {"t_s", f.t_s},
      {"p_WE_m", Vec(f.pose.p_WE)},
      {"theta_W_rad", f.pose.theta_W_rad},
      {"p_WC_m", Vec(f.p_WC)},
      {"out_of_plane_tilt_rad", f.pose.tilt_rad},
      {"out_of_plane_roll_rad", f.pose.roll_rad},
      {"phase", f.phase},
      {"center_px", Vec(f.center_px)},
      {"center_px_undistorted", Vec(f.center_px_undistorted)},
      {"light_factor", f.light_factor},
      {"impact", f.impact},
  };
  if (g.body == Body::kMarkers) {
    j["markers_px"] = MarkerMap(g, f.markers_px);
    j["markers_px_undistorted"] = MarkerMap(g, f.markers_px_undistorted);
  }
  if (!f.defect.empty()) j["defect"] = f.defect;
  if (f.defect == "duplicate") j["duplicate"] = true;
  return j;
}

nlohmann::json ImpactJson(const ImpactTruth& it) {
  const dynamics::ImpactResult& r = it.result;
  return {{"touch_time_s", it.touch_time_s},
          {"x_S_m", it.x_S_m},
          {"v_SC_before_m_s", Vec(r.at_touch.v_SC)},
          {"v_SC_after_m_s", Vec(r.at_separation.v_SC)},
          {"w_before_rad_s", r.at_touch.w_rad_s},
          {"w_after_rad_s", r.at_separation.w_rad_s},
          {"v_ST_before_m_s", Vec(r.v_ST_before)},
          {"v_ST_after_m_s", Vec(r.v_ST_after)},
          {"theta_S_touch_rad", r.at_touch.theta_S_rad},
          {"e", Num(r.e)},
          {"mu_eff", Num(r.mu_eff)},
          {"contact_duration_s", r.t_separation_s},
          {"energy_loss_J", r.energy_loss_J}};
}

nlohmann::json BodyJson(const SpecimenGeometry& g) {
  nlohmann::json j = {{"kind", ToString(g.body)}};
  if (g.body == Body::kBall) {
    const dynamics::SpecimenParameters b = g.Simulated();
    j["diameter_m"] = g.ball_diameter_m;
    j["mass_kg"] = b.mass_kg;
    j["inertia_kg_m2"] = b.inertia_kg_m2;
  }
  return j;
}

}  // namespace

std::string SpecimenId(const SpecimenGeometry& g) { return g.body == Body::kBall ? "ball" : "A"; }

nlohmann::json SpecimenJson(const SpecimenGeometry& g) {
  if (g.body == Body::kBall)  // Simulated(): a solid sphere of ball_mass_kg
    return {{"shape", "ball"},
            {"diameter_m", g.ball_diameter_m},
            {"mass_kg", g.ball_mass_kg},
            {"inertia", "solid"}};
  nlohmann::json markers = nlohmann::json::object();
  for (const Marker& m : g.markers) markers[m.name] = Vec(m.p_BM_m);
  const dynamics::SpecimenParameters body = g.Simulated();  // the ball's, for a ball
  return {{"mass_kg", body.mass_kg},
          {"inertia_kg_m2", body.inertia_kg_m2},
          {"end_radius_m", body.end_radius_m},
          {"d_EC_m", body.d_EC_m},
          {"length_m", g.length_m},
          {"width_m", g.width_m},
          {"thickness_m", g.thickness_m},
          {"markers_B_m", markers}};
}

nlohmann::json TrialJson(const TrialTruth& t, const RenderOptions& o, const SpecimenGeometry& g,
                         bool in_study) {
  nlohmann::json camera = {{"m_per_px", o.m_per_px}, {"gravity_image", {0.0, 1.0}}};
  const LensModel lens(o.camera, o.width_px, o.height_px);
  if (lens.distorts()) {
    const auto k = lens.coefficients();
    camera["distortion"] = {k[0], k[1], k[2], k[3], k[4]};
    const Eigen::Vector2d c = lens.principal_point_px();
    camera["camera_matrix"] = {
        {lens.focal_px(), 0.0, c.x()}, {0.0, lens.focal_px(), c.y()}, {0.0, 0.0, 1.0}};
  }
  std::string notes = "synthetic trial rendered by hoofimpact synth (seed " +
                      std::to_string(t.spec.seed) + "); ground truth in truth.json";
  if (g.body != Body::kMarkers || o.lighting != Lighting::kFront)
    notes += std::string("; body: ") + ToString(g.body) + ", lighting: " + ToString(o.lighting);
  nlohmann::json trial = {
      {"format", "hoofimpact-trial/1"},
      {"id", t.spec.id},
      {"specimen", "A"},
      {"surface", dynamics::SurfaceName(t.spec.surface)},
      {"surface_angle_deg", t.spec.angle_deg},
      {"fps", o.fps},
      {"frames", {{"pattern", "frames/%06d.png"}, {"first", 0}, {"count", t.frames.size()}}},
      {"camera", camera},
      {"surface_line_px", {Vec(t.surface_line_px[0]), Vec(t.surface_line_px[1])}},
      {"nominal_speed_m_s", t.spec.speed_m_s},
      {"notes", notes},
  };
  if (o.frame_format != FrameFormat::kPng) {
    // The camera file records its frame rate, so trial.json leaves it to the file.
    trial.erase("fps");
    trial["frames"] = {
        {"camera_file", ClipFileName(o.frame_format)}, {"first", 0}, {"count", t.frames.size()}};
  }
  // A body without markers is tracked by its silhouette (docs/format.md, "body"); the ball's
  // known diameter is what a user would write, the scale stays camera.m_per_px.
  // A ball alone is its own specimen (its radius and mass centre from the diameter), so it
  // names none; in a study it names the study's ball, whose mass and inertia study.json gives.
  if (g.body == Body::kBall) {
    if (in_study)
      trial["specimen"] = SpecimenId(g);
    else
      trial.erase("specimen");
    trial["body"] = {{"model", "silhouette"}, {"shape", "ball"}, {"diameter_m", g.ball_diameter_m}};
  } else if (g.body == Body::kUnmarked)
    trial["body"] = {{"model", "silhouette"}, {"shape", "outline"}};
  // With a calibration image the scale comes from it, as a user's would: no stated m_per_px.
  if (o.calibration != CalibrationTarget::kNone) {
    const CalibrationPlan p = PlanCalibration(o, t.spec.seed);
    nlohmann::json& cam = trial["camera"];
    cam.erase("m_per_px");
    cam["scale_from"] = ToString(o.calibration);
    if (o.calibration == CalibrationTarget::kCheckerboard)
      cam["checkerboard"] = {
          {"image", p.file}, {"inner_corners", {p.cols, p.rows}}, {"square_m", p.square_m}};
    else
      cam["ruler"] = {{"image", p.file},
                      {"from_px", Vec(p.from_px)},
                      {"to_px", Vec(p.to_px)},
                      {"tick_m", p.tick_m}};
  }
  return trial;
}

nlohmann::json HiddenEffectsJson(const HiddenEffects& h) {
  const OutOfPlane& o = h.out_of_plane;
  nlohmann::json j = nlohmann::json::object();
  for (const auto& f : dynamics::ContactExtensionFields()) j[f.key] = h.contact.*f.member;
  j["out_of_plane"] = {{"tilt_deg", o.tilt_deg},
                       {"roll_deg", o.roll_deg},
                       {"tilt_rate_deg_s", o.tilt_rate_deg_s},
                       {"roll_rate_deg_s", o.roll_rate_deg_s}};
  return j;
}

nlohmann::json CameraEffectsJson(const CameraEffects& c) {
  return {{"noise",
           {{"on", c.noise}, {"full_well_e", c.full_well_e}, {"read_noise_e", c.read_noise_e}}},
          {"black_level", c.black_level},
          {"motion_blur",
           {{"on", c.motion_blur}, {"exposure_s", c.exposure_s}, {"samples", c.blur_samples}}},
          {"distortion",
           {{"on", c.distortion},
            {"k1", c.k1},
            {"k2", c.k2},
            {"p1", c.p1},
            {"p2", c.p2},
            {"k3", c.k3},
            {"focal_px", c.focal_px},
            {"principal_offset_px", Vec(c.principal_offset_px)}}},
          {"defocus", {{"on", c.defocus}, {"sigma_px", c.defocus_sigma_px}}},
          {"vignetting", {{"on", c.vignetting}, {"fraction", c.vignetting_fraction}}},
          {"lighting_gradient",
           {{"on", c.lighting_gradient}, {"fraction", c.lighting_gradient_fraction}}},
          {"subpixel_jitter", c.subpixel_jitter},
          {"drop_frame_probability", c.drop_frame_probability},
          {"duplicate_frame_probability", c.duplicate_frame_probability},
          {"drop_frames", c.drop_frames},
          {"duplicate_frames", c.duplicate_frames},
          {"flicker", {{"hz", c.flicker_hz}, {"depth", c.flicker_depth}}}};
}

nlohmann::json TruthJson(const TrialTruth& t, const SpecimenGeometry& g, const RenderOptions& o) {
  const dynamics::ImpactResult& r = t.impact;
  const dynamics::ContactParameters& c = t.draw.contact;
  nlohmann::json frames = nlohmann::json::array();
  nlohmann::json defects = nlohmann::json::array();
  nlohmann::json duplicates = nlohmann::json::array();
  for (std::size_t i = 0; i < t.frames.size(); ++i) {
    frames.push_back(FrameJson(t.frames[i], g, static_cast<int>(i)));
    if (!t.frames[i].defect.empty())
      defects.push_back({{"frame", i}, {"defect", t.frames[i].defect}});
    if (t.frames[i].defect == "duplicate") duplicates.push_back(i);
  }
  nlohmann::json impacts = nlohmann::json::array();
  for (const ImpactTruth& it : t.impacts) impacts.push_back(ImpactJson(it));
  nlohmann::json effects = CameraEffectsJson(o.camera);
  effects["motion_blur"]["samples_used"] = t.blur_samples_used;
  effects["flicker"]["phase_rad"] = t.flicker_phase_rad;
  nlohmann::json truth = {
      {"body", BodyJson(g)},
      {"lighting", ToString(o.lighting)},
      {"impacts", impacts},
      {"duplicate_frames", duplicates},
      {"dropped_captures", t.dropped_captures},
      {"bounces", t.spec.bounces},
      {"format", "hoofimpact-truth/1"},
      {"impact_time_s", t.impact_time_s},
      {"v_SC_before_m_s", Vec(r.at_touch.v_SC)},
      {"v_SC_after_m_s", Vec(r.at_separation.v_SC)},
      {"w_before_rad_s", r.at_touch.w_rad_s},
      {"w_after_rad_s", r.at_separation.w_rad_s},
      {"v_ST_before_m_s", Vec(r.v_ST_before)},
      {"v_ST_after_m_s", Vec(r.v_ST_after)},
      {"e", Num(r.e)},
      {"mu_eff", Num(r.mu_eff)},
      {"contact_duration_s", r.t_separation_s},
      {"energy_loss_J", r.energy_loss_J},
      {"model",
       {{"k_N_m", c.k_N_m},
        {"b_N_s_m", c.b_N_s_m},
        {"mu", c.mu},
        {"zeta", t.draw.zeta},
        {"e_drawn", t.draw.e_drawn},
        {"scatter_parameters", t.spec.scatter_parameters},
        {"scatter_scale", t.spec.scatter_scale},
        {"gravity_m_s2", dynamics::kStandardGravity_m_s2},
        {"hidden_effects", HiddenEffectsJson(t.spec.hidden)}}},
      {"specimen", SpecimenJson(g)},
      {"seed", t.spec.seed},
      {"surface", dynamics::SurfaceName(t.spec.surface)},
      {"surface_angle_deg", t.spec.angle_deg},
      {"speed_m_s", t.spec.speed_m_s},
      {"contact_point_px_undistorted", Vec(t.contact_px)},
      {"first_frame_after_touch", t.first_frame_after_touch},
      {"camera_effects", effects},
      {"image", {{"width_px", o.width_px}, {"height_px", o.height_px}, {"bit_depth", o.bit_depth}}},
      {"frame_defects", defects},
      {"frames", frames},
  };
  if (o.frame_format != FrameFormat::kPng) {
    // What the camera file records beyond the frames: its stamps (CINE) are the capture slots'
    // times, frames[i].t_s except on a duplicate (docs/synthetic-trials.md, "Frame files").
    nlohmann::json file = {{"format", ToString(o.frame_format)},
                           {"file", ClipFileName(o.frame_format)},
                           {"bit_depth", o.bit_depth}};
    if (o.frame_format == FrameFormat::kCine) {
      nlohmann::json stamps = nlohmann::json::array();
      for (const FrameTruth& f : t.frames) stamps.push_back(f.stamp_s);
      file["time_stamps_s"] = stamps;
    }
    truth["frame_file"] = file;
  }
  if (o.calibration != CalibrationTarget::kNone) {
    // The calibration image's truth (docs/synthetic-trials.md, "Calibration images").
    const CalibrationPlan p = PlanCalibration(o, t.spec.seed);
    nlohmann::json cal = {{"target", ToString(p.target)},
                          {"file", p.file},
                          {"m_per_px", p.m_per_px},
                          {"centre_px_undistorted", Vec(p.centre_px)},
                          {"angle_deg", p.angle_deg}};
    if (p.target == CalibrationTarget::kCheckerboard) {
      cal["inner_corners"] = {p.cols, p.rows};
      cal["square_m"] = p.square_m;
    } else {
      cal["tick_m"] = p.tick_m;
      cal["ticks"] = p.ticks;
      cal["from_px"] = Vec(p.from_px);
      cal["to_px"] = Vec(p.to_px);
    }
    truth["calibration"] = cal;
  }
  return truth;
}

nlohmann::json StudyJson(const std::string& name, const SpecimenGeometry& g,
                         const std::vector<std::string>& trial_ids) {
  return {{"format", "hoofimpact-study/1"},
          {"name", name},
          {"specimens", {{SpecimenId(g), SpecimenJson(g)}}},
          {"trials", trial_ids}};
}

}  // namespace hoof::synth
