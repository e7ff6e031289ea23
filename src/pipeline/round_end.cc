#include "pipeline/round_end.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Dense>

#include "core/frames.h"
#include "tracking/circle_fit.h"
#include "tracking/image_sample.h"

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
  return tracking::SampleBilinear(img, p.x(), p.y(), value);
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
    // Points farther from the circle than max(3.5 robust s.d., 0.05 px) are dropped until the
    // set stops changing: the silhouette tracker's rule for a ball (tracking/circle_fit.h).
    const tracking::CircleFit circle = tracking::FitCircleRobust(points, {}, 3.5, 0.05);
    if (!circle.ok || !(circle.r > 0) || !circle.c.allFinite()) {
      fit.status = "too few edge points on the round end";
      return fit;
    }
    c = circle.c;
    r = circle.r;
    fit.points = circle.n;
    fit.rejected = circle.rejected;
    fit.rms_px = circle.rms;
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
  out.radius_se_px = robust_se(radius, out.radius_px);
  return out;
}

EndRadiusScale ScaleOfEndRadius(double end_radius_m, const RoundEndOffset& end) {
  constexpr double kEdgeOffsetSdPx = 0.5;
  EndRadiusScale s;
  s.m_per_px = end_radius_m / end.radius_px;
  s.m_per_px_se = s.m_per_px * std::hypot(end.radius_se_px, kEdgeOffsetSdPx) / end.radius_px;
  return s;
}

RoundEndOffset MeasureRoundEnd(tracking::FrameSource& source,
                               const tracking::SilhouetteTrack& track, double radius_guess_px,
                               int frames, const tracking::ImageToWorld& unit) {
  std::vector<int> found;
  for (int f = 0; f < track.frame_count(); ++f)
    if (track.frames[static_cast<std::size_t>(f)].found) found.push_back(f);
  std::vector<std::optional<RoundEndFit>> fits(track.frames.size());
  const std::size_t tried = std::min(found.size(), static_cast<std::size_t>(std::max(1, frames)));
  for (std::size_t k = 0; k < tried; ++k) {
    const int f = found[tried > 1 ? k * (found.size() - 1) / (tried - 1) : 0];
    fits[static_cast<std::size_t>(f)] =
        FitRoundEnd(tracking::ToGrey(source.Read(f), source.Describe(f)),
                    track.frames[static_cast<std::size_t>(f)], track.polarity, radius_guess_px);
  }
  return EstimateRoundEndOffset(track.frames, fits, unit);
}

}  // namespace hoof::pipeline
