#include "synth/hand_model.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hoof::synth {
namespace {

/// The hand in its own plane (m): x to the camera's right, y up, origin at the grip point on
/// the ball; the fingertips reach just below it, the forearm goes up and to the right.
struct LocalPart {
  double ax, ay, bx, by, radius;
};
constexpr LocalPart kParts[] = {
    {-0.027, 0.055, -0.027, 0.004, 0.0085},   // index finger
    {-0.009, 0.055, -0.009, -0.006, 0.0090},  // middle
    {0.009, 0.055, 0.009, -0.008, 0.0088},    // ring
    {0.026, 0.052, 0.026, -0.001, 0.0078},    // little
    {-0.042, 0.064, -0.052, 0.014, 0.0105},   // thumb
    {-0.012, 0.082, 0.012, 0.082, 0.032},     // palm
    {0.004, 0.105, 0.060, 0.40, 0.033},       // forearm
};

double SegmentDistance(const Eigen::Vector2d& p, const Capsule& c) {
  const Eigen::Vector2d ab = c.b - c.a;
  const double len2 = ab.squaredNorm();
  const double s = len2 > 0 ? std::clamp((p - c.a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (c.a + s * ab)).norm();
}

double Smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3 - 2 * x);
}

}  // namespace

double HandShape::Distance(double x, double y, double* shade) const {
  double best = std::numeric_limits<double>::infinity();
  double rim = 0;
  const Eigen::Vector2d p{x, y};
  for (const Capsule& c : parts) {
    const double d = SegmentDistance(p, c) - c.radius_px;
    if (d < best) {
      best = d;
      rim = std::clamp(-d / c.radius_px, 0.0, 1.0);
    }
  }
  if (shade) *shade = rim;
  return best;
}

bool HandShape::InView(int w, int h) const {
  if (!present) return false;
  for (const Capsule& c : parts)
    for (int i = 0; i <= 32; ++i) {
      const Eigen::Vector2d p = c.a + (c.b - c.a) * (i / 32.0);
      const double dx = std::max({-0.5 - p.x(), p.x() - (w - 0.5), 0.0});
      const double dy = std::max({-0.5 - p.y(), p.y() - (h - 0.5), 0.0});
      if (std::hypot(dx, dy) < c.radius_px) return true;
    }
  return false;
}

HandModel::HandModel(const FootageSpec& spec, const BallPath& path, const PinholeCamera& camera)
    : path_(path), camera_(camera) {
  const FootageScenario s = spec.scenario;
  present_ =
      spec.hand.enabled && (s == FootageScenario::kBounce || s == FootageScenario::kNeverLands ||
                            s == FootageScenario::kHandOnly);
  hand_only_ = s == FootageScenario::kHandOnly;
  const double r = spec.ball.radius_m;
  grip_offset_ = {0.0, 0.55 * r + 0.012, 0.9 * r};
  rest_ = Eigen::Vector3d{spec.launch.x_m, spec.launch.drop_height_m + r, spec.launch.z_m} +
          grip_offset_;
  away_ =
      Eigen::Vector3d(spec.hand.leave_direction.x(), spec.hand.leave_direction.y(), 0).normalized();
  leave_speed_ = spec.hand.leave_speed_m_s;
  release_s_ = spec.launch.release_time_s;
  leave_s_ = hand_only_ ? release_s_ + 0.3 : release_s_;
  const Eigen::Vector3d light{0.70, 0.48, 0.38}, dark{0.22, 0.12, 0.08};
  skin_ = light + (dark - light) * spec.hand.skin_tone;
}

Eigen::Vector3d HandModel::Withdraw(const Eigen::Vector3d& from, double since) const {
  return from + away_ * (leave_speed_ * since + 2.0 * since * since);
}

Eigen::Vector3d HandModel::GripAt(double t) const {
  if (hand_only_) {
    if (t < release_s_) {
      const double enter = release_s_ > 0 ? Smoothstep(t / release_s_) : 1.0;
      return rest_ + Eigen::Vector3d(0, 0.6, 0) * (1 - enter);
    }
    return t < leave_s_ ? rest_ : Withdraw(rest_, t - leave_s_);
  }
  if (t < release_s_) return path_.At(t).p_WC_m + grip_offset_;
  // The hand follows through with the ball's release velocity for 50 ms as it withdraws.
  const BallState at_release = path_.At(release_s_);
  const double since = t - release_s_;
  return Withdraw(at_release.p_WC_m + grip_offset_, since) +
         at_release.v_WC_m_s * std::min(since, 0.05);
}

HandShape HandModel::ShapeAt(double t) const {
  HandShape shape;
  if (!present_) return shape;
  shape.p_W_m = GripAt(t);
  const Eigen::Vector3d c = camera_.ToCamera(shape.p_W_m);
  if (!(c.z() > 0.05)) return shape;  // behind the camera: not drawn
  shape.present = true;
  const Eigen::Vector2d origin = camera_.Project(shape.p_W_m);
  const double scale = camera_.focal_px() / c.z();
  const Eigen::Vector2d up = camera_.ImageDirection(shape.p_W_m, Eigen::Vector3d::UnitY());
  const Eigen::Vector2d right{-up.y(), up.x()};
  double x0 = origin.x(), y0 = origin.y(), x1 = x0, y1 = y0;
  for (const LocalPart& p : kParts) {
    Capsule cap{origin + scale * (p.ax * right + p.ay * up),
                origin + scale * (p.bx * right + p.by * up), scale * p.radius};
    for (const Eigen::Vector2d& e : {cap.a, cap.b}) {
      x0 = std::min(x0, e.x() - cap.radius_px);
      y0 = std::min(y0, e.y() - cap.radius_px);
      x1 = std::max(x1, e.x() + cap.radius_px);
      y1 = std::max(y1, e.y() + cap.radius_px);
    }
    shape.parts.push_back(cap);
  }
  const auto lo = [](double v) { return static_cast<int>(std::max(-1e6, std::floor(v))) - 2; };
  const auto hi = [](double v) { return static_cast<int>(std::min(1e6, std::ceil(v))) + 2; };
  shape.bounds = cv::Rect(cv::Point(lo(x0), lo(y0)), cv::Point(hi(x1), hi(y1)));
  return shape;
}

}  // namespace hoof::synth
