// truth.json of an everyday clip (FootageTruthJson, declared in synth/footage_renderer.h).
#include <cmath>

#include "synth/footage_renderer.h"

namespace hoof::synth {
namespace {

using nlohmann::json;

json Num(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }
json Vec(const Eigen::Vector2d& v) { return json::array({Num(v.x()), Num(v.y())}); }
json Vec(const Eigen::Vector3d& v) { return json::array({Num(v.x()), Num(v.y()), Num(v.z())}); }

json Timing(const FootageTruth& t) {
  const FrameSchedule& s = t.schedule;
  const FootageTimingOptions& o = t.spec.timing;
  json repeated = json::array();
  for (const DeliveredFrame& f : s.frames)
    if (f.repeated) repeated.push_back(f.index);
  return {{"capture_fps", s.capture_fps},
          {"container_fps", s.container_fps},
          {"delivery", ToString(s.delivery)},
          {"exposure_s", s.exposure_s},
          {"duration_s", o.duration_s},
          {"capture_jitter_fraction",
           s.delivery == FrameDelivery::kLatestCapture ? o.capture_jitter_fraction : 0.0},
          {"repeat_frames", o.repeat_frames},
          {"drop_frames", o.drop_frames},
          {"repeated_frames", repeated},
          {"dropped_captures", s.dropped_captures}};
}

json Camera(const FootageTruth& t) {
  const FootageCameraOptions& c = t.spec.camera;
  json R = json::array();
  for (int i = 0; i < 3; ++i) R.push_back({t.R_CW(i, 0), t.R_CW(i, 1), t.R_CW(i, 2)});
  const double f = t.focal_px, cx = t.principal_point_px.x(), cy = t.principal_point_px.y();
  return {{"model", "pinhole, no distortion"},
          {"focal_px", f},
          {"principal_point_px", Vec(t.principal_point_px)},
          {"camera_matrix", json::array({{f, 0, cx}, {0, f, cy}, {0, 0, 1}})},
          {"p_W_m", Vec(c.p_W_m)},
          {"R_CW", R},
          {"pan_deg", c.pan_deg},
          {"tilt_deg", c.tilt_deg},
          {"roll_deg", c.roll_deg}};
}

json Ball(const FootageTruth& t) {
  const BallOptions& b = t.spec.ball;
  return {{"present", t.spec.scenario != FootageScenario::kHandOnly},
          {"radius_m", b.radius_m},
          {"diameter_m", 2 * b.radius_m},
          {"inertia", ToString(b.inertia)},
          {"inertia_factor", InertiaFactor(b.inertia)},
          {"color", ToString(b.color)},
          {"albedo_rgb", Vec(BallAlbedoRgb(b.color))},
          {"texture", ToString(b.texture)},
          {"specular", b.specular}};
}

json Scene(const FootageTruth& t) {
  const RoomOptions& r = t.spec.room;
  json edge = json::array();
  for (const Eigen::Vector2d& p : t.surface_edge_px) edge.push_back(Vec(p));
  return {{"surface", ToString(r.surface)},
          {"surface_y_W_m", 0.0},
          {"wall_z_m", r.wall_z_m},
          {"table_front_z_m",
           r.surface == ContactSurface::kTable ? Num(r.table_front_z_m) : json(nullptr)},
          {"surface_edge_px", edge},
          {"clutter", r.clutter},
          {"light_p_W_m", Vec(r.light_p_W_m)},
          {"light_radius_m", r.light_radius_m},
          {"ambient", r.ambient},
          {"hand", t.spec.hand.enabled},
          {"skin_tone", t.spec.hand.skin_tone}};
}

json Physics(const FootageTruth& t) {
  const BounceOptions& b = t.spec.bounce;
  const LaunchOptions& l = t.spec.launch;
  return {
      {"g_m_s2", b.g_m_s2},
      {"e_mean", b.e_mean},
      {"e_sd", b.e_sd},
      {"mu", b.mu},
      {"min_rebound_height_m", b.min_rebound_height_m},
      {"release_p_W_m", Vec(Eigen::Vector3d(l.x_m, l.drop_height_m + t.spec.ball.radius_m, l.z_m))},
      {"release_v_W_m_s", Vec(l.v_W_m_s)},
      {"release_w_W_rad_s", Vec(l.w_W_rad_s)}};
}

json Bounce(const FootageBounceTruth& b, int index) {
  const BallBounce& w = b.world;
  return {{"index", index},
          {"t_s", w.t_s},
          {"first_frame_after", b.first_frame_after},
          {"in_view", b.in_view},
          {"p_WT_m", Vec(w.p_WT_m)},
          {"p_WC_m", Vec(w.p_WC_m)},
          {"contact_px", Vec(b.contact_px)},
          {"center_px", Vec(b.center_px)},
          {"radius_px", Num(b.radius_px)},
          {"v_before_m_s", Vec(w.v_before_m_s)},
          {"v_after_m_s", Vec(w.v_after_m_s)},
          {"v_before_px_s", Vec(b.v_before_px_s)},
          {"v_after_px_s", Vec(b.v_after_px_s)},
          {"w_before_rad_s", Vec(w.w_before_rad_s)},
          {"w_after_rad_s", Vec(w.w_after_rad_s)},
          {"e", w.e},
          {"mu_eff", w.mu_eff},
          {"rolling", w.rolling}};
}

json Frame(const FootageFrameTruth& f) {
  const DeliveredFrame& d = f.frame;
  json j = {{"index", d.index},
            {"container_time_s", d.container_time_s},
            {"capture_index", d.capture_index},
            {"t_s", d.t_s},
            {"repeated", d.repeated},
            {"fault", ToString(d.fault)},
            {"phase", ToString(f.phase)},
            {"visibility", ToString(f.visibility)},
            {"hand_in_view", f.hand_in_view},
            {"blur_samples", f.blur_samples}};
  if (f.phase == BallPhase::kAbsent) return j;
  const bool img = f.image_valid;
  j["arc"] = f.arc;
  j["p_WC_m"] = Vec(f.p_WC_m);
  j["v_WC_m_s"] = Vec(f.v_WC_m_s);
  j["w_W_rad_s"] = Vec(f.w_W_rad_s);
  j["center_px"] = img ? Vec(f.center_px) : json(nullptr);
  j["projection_px"] = Vec(f.projection_px);
  j["radius_px"] = img ? Num(f.radius_px) : json(nullptr);
  j["semi_axes_px"] = img ? json::array({f.semi_major_px, f.semi_minor_px}) : json(nullptr);
  j["major_angle_rad"] = img ? Num(f.major_angle_rad) : json(nullptr);
  j["m_per_px"] = Num(f.m_per_px);
  j["in_view_fraction"] = f.in_view_fraction;
  j["occluded_fraction"] = f.occluded_fraction;
  j["visible_fraction"] = f.visible_fraction;
  return j;
}

}  // namespace

json FootageTruthJson(const FootageTruth& t) {
  json j;
  j["format"] = kFootageTruthFormat;
  j["note"] =
      "Image quantities are for the frames as delivered upright: as a player shows them once "
      "the file carries rotation_tag_deg (tools/tag-rotation), or as the PNG frames are "
      "stored. Pixels: x right, y down, origin at the centre of the top-left pixel. World W: x "
      "right, y up, z toward the camera, m; the contact surface is y = 0. center_px is the "
      "centre of the ball's true (elliptical) image, not the projection of its centre.";
  j["scenario"] = ToString(t.spec.scenario);
  j["seed"] = t.spec.seed;
  j["file"] = {{"codec", ToString(t.spec.codec)},
               {"name", FootageClipName(t.spec.codec)},
               {"frames", t.schedule.frames.size()},
               {"container_fps", t.schedule.container_fps},
               {"rotation_tag_deg", t.spec.camera.rotation_tag_deg},
               {"stored_size_px", {t.stored_width_px, t.stored_height_px}}};
  j["image"] = {{"width_px", t.width_px}, {"height_px", t.height_px}};
  j["timing"] = Timing(t);
  j["camera"] = Camera(t);
  j["gravity_image"] = Vec(t.gravity_image);
  j["scale"] = {{"m_per_px", t.m_per_px},
                {"p_W_m", Vec(t.reference_p_W_m)},
                {"image_px", Vec(t.reference_px)},
                {"depth_m", t.m_per_px * t.focal_px}};
  j["ball"] = Ball(t);
  j["scene"] = Scene(t);
  j["physics"] = Physics(t);
  j["release_time_s"] = Num(t.release_time_s);
  j["carry_start_s"] = Num(t.carry_start_s);
  j["settle_time_s"] = Num(t.settle_time_s);
  j["rolling_time_s"] = Num(t.rolling_time_s);
  j["bounces"] = json::array();
  for (std::size_t i = 0; i < t.bounces.size(); ++i)
    j["bounces"].push_back(Bounce(t.bounces[i], static_cast<int>(i)));
  j["frames"] = json::array();
  for (const FootageFrameTruth& f : t.frames) j["frames"].push_back(Frame(f));
  return j;
}

}  // namespace hoof::synth
