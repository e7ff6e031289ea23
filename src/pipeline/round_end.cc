#include "pipeline/round_end.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Dense>

#include "core/frames.h"

namespace hoof::pipeline {
namespace {

constexpr double kPi = std::numbers::pi;

double MedianOf(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

/// Bilinear sample of a CV_32F image; false outside.
bool Sample(const cv::Mat& img, const Eigen::Vector2d& p, double& value) {
  const double x = p.x(), y = p.y();
  if (!(x >= 0 && y >= 0 && x <= img.cols - 1.0 && y <= img.rows - 1.0)) return false;
  const int x0 = std::min(static_cast<int>(x), img.cols - 2);
  const int y0 = std::min(static_cast<int>(y), img.rows - 2);
  const double fx = x - x0, fy = y - y0;
  const float* r0 = img.ptr<float>(y0);
  const float* r1 = img.ptr<float>(y0 + 1);
  value =
      (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x0 + 1]) + fy * ((1 - fx) * r1[x0] + fx * r1[x0 + 1]);
  return true;
}

/// Where the profile from `from` along `u` (unit) crosses `mid`, searched from `r_hi` down to
/// `r_lo` every 0.25 px: of several crossings the one nearest `r_near`; NaN when none.
double Crossing(const cv::Mat& f, const Eigen::Vector2d& from, const Eigen::Vector2d& u,
                double r_lo, double r_hi, double r_near, double mid) {
  double best = std::nan(""), best_gap = 1e300, prev_v = 0, prev_r = 0;
  bool have_prev = false;
  for (double r = r_hi; r >= r_lo; r -= 0.25) {
    double v = 0;
    if (!Sample(f, from + r * u, v)) {
      have_prev = false;
      continue;
    }
    if (have_prev && (prev_v - mid) * (v - mid) <= 0 && prev_v != v) {
      const double rc = prev_r + (r - prev_r) * (mid - prev_v) / (v - prev_v);
      if (std::abs(rc - r_near) < best_gap) {
        best_gap = std::abs(rc - r_near);
        best = rc;
      }
    }
    prev_v = v;
    prev_r = r;
    have_prev = true;
  }
  return best;
}

/// Geometric circle fit (Gauss-Newton on the distances) of the points in use from (c, r).
void GeometricCircle(const std::vector<Eigen::Vector2d>& p, const std::vector<char>& use,
                     Eigen::Vector2d& c, double& r) {
  for (int it = 0; it < 30; ++it) {
    Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();
    Eigen::Vector3d jtr = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (!use[i]) continue;
      const Eigen::Vector2d d = p[i] - c;
      const double dist = d.norm();
      if (!(dist > 0)) continue;
      const Eigen::Vector3d j{-d.x() / dist, -d.y() / dist, -1.0};
      jtj += j * j.transpose();
      jtr += j * (dist - r);
    }
    const Eigen::Vector3d step = -jtj.ldlt().solve(jtr);
    if (!step.allFinite()) return;
    c += step.head<2>();
    r += step(2);
    if (step.norm() < 1e-9) return;
  }
}

/// The circle through the edge points `p` from the start (c, r), points farther from it than
/// max(3.5 robust s.d., 0.05 px) dropped until the set stops changing (the silhouette
/// tracker's rule for a ball, tracking/silhouette_tracker.cc). Written by hand with Eigen: OpenCV
/// has no circle fit with outlier rejection.
bool RobustCircle(const std::vector<Eigen::Vector2d>& p, Eigen::Vector2d& c, double& r,
                  RoundEndFit& fit) {
  std::vector<char> use(p.size(), 1);
  if (p.size() < 8) return false;
  for (int round = 0; round < 12; ++round) {
    GeometricCircle(p, use, c, r);
    std::vector<double> d(p.size()), dev;
    for (std::size_t i = 0; i < p.size(); ++i) d[i] = (p[i] - c).norm() - r;
    const double med = MedianOf(d);
    for (double x : d) dev.push_back(std::abs(x - med));
    const double threshold = std::max(3.5 * 1.4826 * MedianOf(dev), 0.05);
    std::vector<char> next(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) next[i] = std::abs(d[i]) <= threshold;
    if (next == use || std::count(next.begin(), next.end(), 1) < 8) break;
    use = next;
  }
  double ss = 0;
  int n = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (use[i]) {
      ss += std::pow((p[i] - c).norm() - r, 2);
      ++n;
    }
  if (n < 8 || !(r > 0) || !c.allFinite()) return false;
  fit.points = n;
  fit.rejected = static_cast<int>(p.size()) - n;
  fit.rms_px = std::sqrt(ss / n);
  return true;
}

}  // namespace

RoundEndFit FitRoundEnd(const cv::Mat& grey, const tracking::SilhouetteObservation& o,
                        tracking::Polarity polarity, double radius_guess_px) {
  RoundEndFit fit;
  fit.status = "not found";
  if (!o.found || !o.has_orientation || !(o.width_px > 0) || !(o.length_px > 0)) {
    fit.status = "no outline with an axis";
    return fit;
  }
  const Eigen::Vector2d x_B{std::cos(o.angle_I_rad), std::sin(o.angle_I_rad)};
  double r0 = radius_guess_px > 0 ? radius_guess_px : 0.5 * o.width_px;
  // A window about the round end.
  const double reach = 0.5 * o.length_px + 0.25 * o.width_px + 8;
  const Eigen::Vector2d tip_guess = o.p_I - 0.5 * o.length_px * x_B;
  const int half = static_cast<int>(std::ceil(reach));
  const cv::Rect box =
      cv::Rect(static_cast<int>(std::floor(tip_guess.x())) - half,
               static_cast<int>(std::floor(tip_guess.y())) - half, 2 * half + 1, 2 * half + 1) &
      cv::Rect(0, 0, grey.cols, grey.rows);
  if (box.width < 8 || box.height < 8) {
    fit.status = "the round end is outside the frame";
    return fit;
  }
  cv::Mat f;
  grey(box).convertTo(f, CV_32F);
  const Eigen::Vector2d origin(box.x, box.y);
  const Eigen::Vector2d c_w = o.p_I - origin;
  // The levels: inside, along the axis between the centroid and the tip; outside, beyond it.
  std::vector<double> inside, outside;
  for (double s = 0.1; s <= 0.35; s += 0.01) {
    double v = 0;
    if (Sample(f, c_w - s * o.length_px * x_B, v)) inside.push_back(v);
  }
  for (double s = 0.58; s <= 0.7; s += 0.01) {
    double v = 0;
    if (Sample(f, c_w - s * o.length_px * x_B, v)) outside.push_back(v);
  }
  if (inside.size() < 4 || outside.size() < 4) {
    fit.status = "the round end is outside the frame";
    return fit;
  }
  const double in = MedianOf(inside), out = MedianOf(outside);
  if ((polarity == tracking::Polarity::kDarkOnBright && !(in < out)) ||
      (polarity == tracking::Polarity::kBrightOnDark && !(in > out)) || in == out) {
    fit.status = "no contrast at the round end";
    return fit;
  }
  const double mid = 0.5 * (in + out);
  // The tip: where the axis leaves the body; E is r0 inside it.
  const double tip =
      Crossing(f, c_w, -x_B, 0.3 * o.length_px, 0.7 * o.length_px, 0.5 * o.length_px, mid);
  if (!std::isfinite(tip)) {
    fit.status = "no edge on the axis at the round end";
    return fit;
  }
  Eigen::Vector2d c = c_w - (tip - r0) * x_B;
  double r = r0;
  for (int pass = 0; pass < 2; ++pass) {
    const double h = pass == 0 ? std::max(4.0, 0.2 * r) : 3.0;
    // The arc: the directions from E whose edge lies on the circle, within the half width of
    // the axis (less a margin for the corners where the arc meets the sides).
    const double half_w = 0.5 * o.width_px;
    const double reach_angle =
        std::min(80.0 * kPi / 180, std::asin(std::min(1.0, half_w / r)) - 10.0 * kPi / 180);
    if (!(reach_angle > 15.0 * kPi / 180)) {
      fit.status = "the outline is too narrow for its round end";
      return fit;
    }
    const int rays = std::max(16, static_cast<int>(std::lround(2 * reach_angle * r / 1.5)));
    std::vector<Eigen::Vector2d> points;
    for (int k = 0; k < rays; ++k) {
      const double a = -reach_angle + 2 * reach_angle * (k + 0.5) / rays;
      const Eigen::Vector2d u = core::BodyRotation(a).ToW(-x_B);  // a rotation by a in the image
      const double rc = Crossing(f, c, u, std::max(0.4 * r, r - h), r + h, r, mid);
      if (std::isfinite(rc)) points.push_back(c + rc * u);
    }
    if (!RobustCircle(points, c, r, fit)) {
      fit.status = "too few edge points on the round end";
      return fit;
    }
  }
  fit.ok = true;
  fit.status = "ok";
  fit.centre_I = c + origin;
  fit.radius_px = r;
  return fit;
}

RoundEndOffset EstimateRoundEndOffset(const std::vector<tracking::SilhouetteObservation>& obs,
                                      const std::vector<std::optional<RoundEndFit>>& fits,
                                      const tracking::ImageToWorld& unit) {
  RoundEndOffset out;
  std::vector<double> x, y, radius;
  for (std::size_t f = 0; f < obs.size() && f < fits.size(); ++f) {
    if (!fits[f]) continue;
    ++out.frames_tried;
    if (!fits[f]->ok) continue;
    const auto& o = obs[f];
    const Eigen::Vector2d a_I(std::cos(o.angle_I_rad), std::sin(o.angle_I_rad));
    const Eigen::Vector2d c_W = unit.ToWorld(o.p_I);
    const Eigen::Vector2d x_W = (unit.ToWorld(o.p_I + a_I) - c_W).normalized();
    const Eigen::Vector2d d_W = unit.ToWorld(fits[f]->centre_I) - c_W;
    // In B: along x_B, and along y_B (x_B turned by +90 deg in W).
    x.push_back(d_W.dot(x_W));
    y.push_back(d_W.dot(Eigen::Vector2d(-x_W.y(), x_W.x())));
    radius.push_back(fits[f]->radius_px);
  }
  out.frames_used = static_cast<int>(x.size());
  if (out.frames_used < 5) {
    out.message = "the round end was fitted in " + std::to_string(out.frames_used) + " of " +
                  std::to_string(out.frames_tried) + " frames (5 needed)";
    return out;
  }
  const auto robust_se = [](const std::vector<double>& v, double median) {
    std::vector<double> dev;
    for (double a : v) dev.push_back(std::abs(a - median));
    // The median's standard error: 1.2533 s / sqrt(n), s from the MAD.
    return 1.2533 * 1.4826 * MedianOf(dev) / std::sqrt(static_cast<double>(v.size()));
  };
  out.measured = true;
  out.p_BE_px = {MedianOf(x), MedianOf(y)};
  out.p_BE_se_px = {robust_se(x, out.p_BE_px.x()), robust_se(y, out.p_BE_px.y())};
  out.radius_px = MedianOf(radius);
  return out;
}

}  // namespace hoof::pipeline
