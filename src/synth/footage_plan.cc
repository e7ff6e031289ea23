#include "synth/footage_plan.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace hoof::synth {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string Num(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

std::string Num(const Eigen::Vector3d& v) {
  return Num(v.x()) + "," + Num(v.y()) + "," + Num(v.z());
}

/// A spec that cannot be drawn: "FootageSpec.field = value is invalid: why".
[[noreturn]] void Refuse(const std::string& field, const std::string& value,
                         const std::string& why) {
  throw std::invalid_argument("FootageSpec." + field + " = " + value + " is invalid: " + why);
}

/// The ellipse's half extents along x and y (px).
Eigen::Vector2d HalfExtents(const SphereImage& s) {
  const double a = s.semi_major_px, b = s.semi_minor_px, th = s.major_angle_rad;
  return {std::hypot(a * std::cos(th), b * std::sin(th)),
          std::hypot(a * std::sin(th), b * std::cos(th))};
}

/// The reference point of the scale and gravity's direction (FootageTruth::reference_p_W_m).
Eigen::Vector3d ReferencePoint(const FootageSpec& spec, const BallPath& path,
                               const HandModel& hand) {
  if (!path.bounces.empty()) return path.bounces.front().p_WC_m;
  if (path.present && std::isfinite(path.release_time_s))
    return path.At(path.release_time_s).p_WC_m;
  if (path.present) return path.At(0).p_WC_m;
  if (hand.present()) return hand.GripAt(spec.launch.release_time_s);
  return {spec.launch.x_m, spec.ball.radius_m, spec.launch.z_m};
}

/// Two image points, at the frame's left and right edges, of the line y = 0, z = z_line.
std::vector<Eigen::Vector2d> EdgeLine(const PinholeCamera& cam, double z_line) {
  const Eigen::Vector2d a = cam.Project({-1.0, 0.0, z_line}), b = cam.Project({1.0, 0.0, z_line});
  if (!a.allFinite() || !b.allFinite() || (b - a).norm() < 1e-9) return {};
  const Eigen::Vector2d d = (b - a).normalized();
  if (std::abs(d.x()) < 1e-9) return {a, b};
  const double s0 = (0 - a.x()) / d.x(), s1 = (cam.width_px() - 1 - a.x()) / d.x();
  return {a + s0 * d, a + s1 * d};
}

FootageFrameTruth FrameTruth(const FootagePlan& plan, const DeliveredFrame& f) {
  FootageFrameTruth t;
  t.frame = f;
  const PinholeCamera& cam = plan.camera;
  const HandShape hand = plan.hand.ShapeAt(f.t_s);
  t.hand_in_view = hand.InView(cam.width_px(), cam.height_px());
  t.blur_samples = ExposureSamples(plan, f.capture_index);
  if (!plan.path.present) return t;
  const BallState s = plan.path.At(f.t_s);
  t.phase = s.phase;
  t.p_WC_m = s.p_WC_m;
  t.v_WC_m_s = s.v_WC_m_s;
  t.w_W_rad_s = s.w_W_rad_s;
  for (const BallBounce& b : plan.path.bounces) t.arc += b.t_s <= f.t_s ? 1 : 0;
  const SphereImage img = cam.ImageOfSphere(s.p_WC_m, plan.path.radius_m);
  t.image_valid = img.valid;
  t.projection_px = img.projection_px;
  t.m_per_px = cam.MetresPerPixel(s.p_WC_m);
  t.visibility = BallVisibility::kOutOfView;
  if (!img.valid) return t;
  t.center_px = img.center_px;
  t.radius_px = img.radius_px;
  t.semi_major_px = img.semi_major_px;
  t.semi_minor_px = img.semi_minor_px;
  t.major_angle_rad = img.major_angle_rad;
  VisibleFractions(img, hand, cam.width_px(), cam.height_px(), t.in_view_fraction,
                   t.occluded_fraction);
  t.visible_fraction = t.in_view_fraction - t.occluded_fraction;
  if (t.in_view_fraction <= 0)
    t.visibility = BallVisibility::kOutOfView;
  else if (t.occluded_fraction > 0)
    t.visibility = BallVisibility::kOccluded;
  else if (t.in_view_fraction < 1)
    t.visibility = BallVisibility::kPartlyOutOfView;
  else
    t.visibility = BallVisibility::kVisible;
  return t;
}

FootageBounceTruth BounceTruth(const FootagePlan& plan, const BallBounce& b) {
  FootageBounceTruth t;
  t.world = b;
  const PinholeCamera& cam = plan.camera;
  const double r = plan.path.radius_m;
  t.contact_px = cam.Project(b.p_WT_m);
  const SphereImage img = cam.ImageOfSphere(b.p_WC_m, r);
  t.center_px = img.center_px;
  t.radius_px = img.radius_px;
  t.v_before_px_s = cam.ImageVelocity(b.p_WC_m, r, b.v_before_m_s);
  t.v_after_px_s = cam.ImageVelocity(b.p_WC_m, r, b.v_after_m_s);
  double in_view = 0, occluded = 0;
  if (img.valid)
    VisibleFractions(img, HandShape{}, cam.width_px(), cam.height_px(), in_view, occluded);
  const bool contact_inside = t.contact_px.allFinite() && t.contact_px.x() >= -0.5 &&
                              t.contact_px.x() <= cam.width_px() - 0.5 &&
                              t.contact_px.y() >= -0.5 && t.contact_px.y() <= cam.height_px() - 0.5;
  t.in_view = contact_inside && in_view >= 0.5;
  for (const DeliveredFrame& f : plan.schedule.frames)
    if (f.t_s >= b.t_s) {
      t.first_frame_after = f.index;
      break;
    }
  return t;
}

/// Refuses a ball that, in view, is inside a wall or the table's edge is not under it.
void CheckScene(const FootagePlan& plan) {
  const FootageSpec& spec = plan.spec;
  const double r = plan.path.radius_m;
  for (const FootageFrameTruth& f : plan.truth.frames) {
    if (f.in_view_fraction <= 0) continue;
    const Eigen::Vector3d& p = f.p_WC_m;
    if (p.z() - r < spec.room.wall_z_m - 1e-9)
      Refuse("launch.v_W_m_s", Num(spec.launch.v_W_m_s),
             "the ball reaches the back wall in view at t = " + Num(f.frame.t_s) + " s");
    if (spec.room.clutter && p.x() - r < spec.room.side_wall_x_m)
      Refuse("launch.v_W_m_s", Num(spec.launch.v_W_m_s),
             "the ball reaches the side wall in view at t = " + Num(f.frame.t_s) + " s");
    const bool on_surface = f.phase == BallPhase::kSliding || f.phase == BallPhase::kRolling ||
                            f.phase == BallPhase::kRest;
    if (spec.room.surface == ContactSurface::kTable && on_surface &&
        (std::abs(p.x()) > spec.room.table_half_width_m || p.z() > spec.room.table_front_z_m))
      Refuse("launch.v_W_m_s", Num(spec.launch.v_W_m_s),
             "the ball rolls off the table at t = " + Num(f.frame.t_s) + " s");
  }
  for (const FootageBounceTruth& b : plan.truth.bounces) {
    const Eigen::Vector3d& p = b.world.p_WT_m;
    if (spec.room.surface == ContactSurface::kTable &&
        (std::abs(p.x()) > spec.room.table_half_width_m || p.z() > spec.room.table_front_z_m))
      Refuse("launch.v_W_m_s", Num(spec.launch.v_W_m_s),
             "the ball lands off the table at t = " + Num(b.world.t_s) + " s");
    if (spec.scenario == FootageScenario::kNeverLands && b.in_view)
      Refuse("launch.v_W_m_s", Num(spec.launch.v_W_m_s),
             "the ball lands in view at t = " + Num(b.world.t_s) +
                 " s: a never-lands clip needs it to leave the view first");
  }
}

}  // namespace

const char* ToString(BallVisibility v) {
  switch (v) {
    case BallVisibility::kAbsent:
      return "absent";
    case BallVisibility::kOutOfView:
      return "out_of_view";
    case BallVisibility::kOccluded:
      return "occluded";
    case BallVisibility::kPartlyOutOfView:
      return "partly_out_of_view";
    case BallVisibility::kVisible:
      return "visible";
  }
  return "absent";
}

void VisibleFractions(const SphereImage& image, const HandShape& hand, int w, int h,
                      double& in_view, double& occluded) {
  in_view = occluded = 0;
  if (!image.valid) return;
  const Eigen::Vector2d half = HalfExtents(image), c = image.center_px;
  const double x0 = c.x() - half.x(), x1 = c.x() + half.x();
  const double y0 = c.y() - half.y(), y1 = c.y() + half.y();
  if (x1 < -0.5 || x0 > w - 0.5 || y1 < -0.5 || y0 > h - 0.5) return;
  const bool inside = x0 >= -0.5 && x1 <= w - 0.5 && y0 >= -0.5 && y1 <= h - 0.5;
  const bool touches_hand = hand.present && x1 >= hand.bounds.x &&
                            x0 <= hand.bounds.x + hand.bounds.width && y1 >= hand.bounds.y &&
                            y0 <= hand.bounds.y + hand.bounds.height;
  if (inside && !touches_hand) {
    in_view = 1;
    return;
  }
  const double step = std::max(half.x(), half.y()) / 20;
  const Eigen::Matrix3d& Q = image.conic;
  int all = 0, seen = 0, covered = 0;
  for (double y = y0 + step / 2; y < y1; y += step)
    for (double x = x0 + step / 2; x < x1; x += step) {
      const Eigen::Vector3d u{x, y, 1};
      if (u.dot(Q * u) < 0) continue;
      ++all;
      if (x < -0.5 || x > w - 0.5 || y < -0.5 || y > h - 0.5) continue;
      ++seen;
      if (touches_hand && hand.Distance(x, y) < 0) ++covered;
    }
  if (all == 0) return;
  in_view = static_cast<double>(seen) / all;
  occluded = static_cast<double>(covered) / all;
}

int ExposureSamples(const FootagePlan& plan, int capture) {
  if (!plan.spec.sensor.motion_blur) return 1;
  const double t = plan.schedule.capture_times_s[static_cast<std::size_t>(capture)];
  const double T = plan.schedule.exposure_s;
  double longest = 0;
  Eigen::Vector2d ball_prev = Eigen::Vector2d::Zero(), hand_prev = Eigen::Vector2d::Zero();
  for (int i = 0; i <= 8; ++i) {
    const double ti = t + T * (i / 8.0 - 0.5);
    Eigen::Vector2d ball = Eigen::Vector2d::Zero(), hand = Eigen::Vector2d::Zero();
    if (plan.path.present) ball = plan.camera.Project(plan.path.At(ti).p_WC_m);
    if (plan.hand.present()) hand = plan.camera.Project(plan.hand.GripAt(ti));
    if (i > 0) {
      const double step = std::max((ball - ball_prev).norm(), (hand - hand_prev).norm());
      longest += std::isfinite(step) ? step : 0.0;
    }
    ball_prev = ball;
    hand_prev = hand;
  }
  if (longest == 0) return 1;
  return std::min(plan.spec.sensor.max_blur_samples,
                  std::max(2, static_cast<int>(std::ceil(longest / 0.4))));
}

FootagePlan PlanFootage(const FootageSpec& spec) {
  spec.Validate();
  if (spec.camera.p_W_m.y() <= 0.02)
    Refuse("camera.p_W_m", Num(spec.camera.p_W_m),
           "the camera must be above the contact surface (> 0.02 m)");
  const PinholeCamera camera(spec.camera);
  const FrameSchedule schedule = PlanFrameSchedule(spec.timing, spec.seed);
  const double end_s = schedule.capture_times_s.back() + schedule.exposure_s + 1e-6;
  BallPath path =
      PlanBallPath(spec.scenario, spec.ball, spec.launch, spec.bounce, end_s, spec.seed);
  HandModel hand(spec, path, camera);
  const Eigen::Vector3d reference = ReferencePoint(spec, path, hand);
  const RoomLight light(spec.room, {reference.x(), 0.0, reference.z()});
  FootagePlan plan{spec, camera, std::move(path), schedule, light, hand, {}};
  FootageTruth& t = plan.truth;
  t.spec = spec;
  t.width_px = camera.width_px();
  t.height_px = camera.height_px();
  const bool sideways = spec.camera.rotation_tag_deg == 90 || spec.camera.rotation_tag_deg == 270;
  t.stored_width_px = sideways ? t.height_px : t.width_px;
  t.stored_height_px = sideways ? t.width_px : t.height_px;
  t.focal_px = camera.focal_px();
  t.principal_point_px = camera.principal_point_px();
  t.R_CW = camera.R_CW();
  t.schedule = schedule;
  t.release_time_s = plan.path.release_time_s;
  t.carry_start_s = plan.path.carry_start_s;
  t.settle_time_s = plan.path.settle_time_s;
  t.rolling_time_s = plan.path.rolling_time_s;
  t.reference_p_W_m = reference;
  t.m_per_px = camera.MetresPerPixel(reference);
  t.gravity_image = camera.ImageDirection(reference, -Eigen::Vector3d::UnitY());
  t.reference_px = camera.Project(reference);
  t.surface_edge_px =
      EdgeLine(camera, spec.room.surface == ContactSurface::kTable ? spec.room.table_front_z_m
                                                                   : spec.room.wall_z_m);
  for (const DeliveredFrame& f : schedule.frames) t.frames.push_back(FrameTruth(plan, f));
  for (const BallBounce& b : plan.path.bounces) t.bounces.push_back(BounceTruth(plan, b));
  CheckScene(plan);
  if (!std::isfinite(t.release_time_s)) t.release_time_s = t.carry_start_s = kNaN;
  return plan;
}

}  // namespace hoof::synth
