#include "synth/calibration_image.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "synth/camera_model.h"
#include "synth/frame_renderer.h"
#include "synth/projection.h"

namespace hoof::synth {
namespace {

constexpr float kBackground = 0.15f;  // the scene behind the target
constexpr float kWhite = 0.85f;       // the card's white squares and margin, the ruler
constexpr float kBlack = 0.06f;       // the black squares, the ticks
constexpr int kSupersampling = 8;     // samples per pixel side of the ideal image
constexpr double kTickWidth = 0.2;    // of the tick spacing
constexpr double kRulerWidth = 10.0;  // tick spacings across the ruler

double RoundSignificant(double x, int digits) {
  const double e = std::pow(10.0, std::floor(std::log10(x)) - (digits - 1));
  return std::round(x / e) * e;
}

/// The radiance at a point q of the target's own frame (m, origin its centre, x along it).
float Radiance(const CalibrationPlan& p, const Eigen::Vector2d& q) {
  if (p.target == CalibrationTarget::kCheckerboard) {
    const double s = p.square_m;
    // cols + 1 by rows + 1 squares, on a white card one square wider on every side.
    const double hx = 0.5 * (p.cols + 1) * s, hy = 0.5 * (p.rows + 1) * s;
    if (std::abs(q.x()) > hx + s || std::abs(q.y()) > hy + s) return kBackground;
    if (std::abs(q.x()) >= hx || std::abs(q.y()) >= hy) return kWhite;
    const auto i = static_cast<long>(std::floor((q.x() + hx) / s)),
               j = static_cast<long>(std::floor((q.y() + hy) / s));
    return (i + j) % 2 == 0 ? kBlack : kWhite;
  }
  // Ruler: ticks hang from its upper edge (y < 0 up in the image); every 5th longer, every
  // 10th longer still.
  const double t = p.tick_m, half_len = 0.5 * (p.ticks - 1 + 2) * t, w = kRulerWidth * t;
  if (std::abs(q.x()) > half_len || q.y() < -0.5 * w || q.y() > 0.5 * w) return kBackground;
  const double x = q.x() + 0.5 * (p.ticks - 1) * t;  // 0 at the first tick
  const long k = std::lround(x / t);
  if (k < 0 || k >= p.ticks || std::abs(x - static_cast<double>(k) * t) > 0.5 * kTickWidth * t)
    return kWhite;
  const double len = (k % 10 == 0 ? 0.6 : k % 5 == 0 ? 0.45 : 0.3) * w;
  return q.y() <= -0.5 * w + len ? kBlack : kWhite;
}

}  // namespace

CalibrationPlan PlanCalibration(const RenderOptions& o, std::uint64_t seed) {
  CalibrationPlan p;
  p.target = o.calibration;
  p.m_per_px = o.m_per_px;
  std::mt19937_64 rng(MixSeed(seed, 0xCA1B));
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  p.angle_deg = 8.0 * unit(rng);
  const double w = o.width_px, h = o.height_px;
  double span_x = 0, span_y = 0;  // the target's extent (px)
  if (p.target == CalibrationTarget::kCheckerboard) {
    const double square_px = std::min(0.75 * w / (p.cols + 3), 0.75 * h / (p.rows + 3));
    if (square_px < 6)
      throw std::invalid_argument("calibration: the frame is too small for a checkerboard of " +
                                  std::to_string(p.cols) + " x " + std::to_string(p.rows) +
                                  " inner corners (squares of " + std::to_string(square_px) +
                                  " px; 6 or more needed)");
    p.square_m = RoundSignificant(square_px * o.m_per_px, 3);
    span_x = (p.cols + 3) * p.square_m / o.m_per_px;
    span_y = (p.rows + 3) * p.square_m / o.m_per_px;
  } else if (p.target == CalibrationTarget::kRuler) {
    // The finest of 1, 2, 5 x 10^k m that is 4 px or more.
    const double min_m = 4 * o.m_per_px;
    const double decade = std::pow(10.0, std::floor(std::log10(min_m)));
    p.tick_m = 10 * decade;
    for (double f : {1.0, 2.0, 5.0})
      if (f * decade >= min_m) {
        p.tick_m = f * decade;
        break;
      }
    p.ticks = static_cast<int>(std::floor(0.8 * w * o.m_per_px / p.tick_m)) - 1;
    if (p.ticks < 8 || kRulerWidth * p.tick_m / o.m_per_px > 0.5 * h)
      throw std::invalid_argument("calibration: the frame is too small for a ruler");
    span_x = (p.ticks + 1) * p.tick_m / o.m_per_px;
    span_y = kRulerWidth * p.tick_m / o.m_per_px;
  } else {
    return p;
  }
  // A shift that keeps the turned target inside the middle of the frame.
  const double a = p.angle_deg * M_PI / 180;
  const double ex = 0.5 * (std::abs(std::cos(a)) * span_x + std::abs(std::sin(a)) * span_y),
               ey = 0.5 * (std::abs(std::sin(a)) * span_x + std::abs(std::cos(a)) * span_y);
  const double slack_x = std::max(0.0, 0.45 * w - ex), slack_y = std::max(0.0, 0.45 * h - ey);
  p.centre_px = {0.5 * (w - 1) + slack_x * unit(rng), 0.5 * (h - 1) + slack_y * unit(rng)};
  if (p.target == CalibrationTarget::kRuler) {
    // Across the short ticks, a fifth of the ruler's width below its upper edge, from half a
    // tick before the first to half a tick after the last; in the recorded image.
    const LensModel lens(o.camera, o.width_px, o.height_px);
    const Eigen::Vector2d ux(std::cos(a), std::sin(a)), uy(-std::sin(a), std::cos(a));
    const double y = (-0.5 * kRulerWidth + 0.2 * kRulerWidth) * p.tick_m / o.m_per_px;
    const double x = 0.5 * p.ticks * p.tick_m / o.m_per_px;
    const auto recorded = [&](const Eigen::Vector2d& u) {
      return lens.distorts() ? lens.Distort(u) : u;
    };
    p.from_px = recorded(p.centre_px - x * ux + y * uy);
    p.to_px = recorded(p.centre_px + x * ux + y * uy);
  }
  return p;
}

cv::Mat RenderCalibrationImage(const CalibrationPlan& p, const RenderOptions& o,
                               std::uint64_t seed) {
  const int w = o.width_px, h = o.height_px, s = kSupersampling;
  const double a = p.angle_deg * M_PI / 180, ca = std::cos(a), sa = std::sin(a);
  // The ideal image, each pixel the mean of s x s samples (pixel centres at integers).
  cv::Mat ideal(h, w, CV_32F);
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) {
      double sum = 0;
      for (int i = 0; i < s; ++i)
        for (int j = 0; j < s; ++j) {
          const double x = c - 0.5 + (j + 0.5) / s - p.centre_px.x(),
                       y = r - 0.5 + (i + 0.5) / s - p.centre_px.y();
          const Eigen::Vector2d q = Eigen::Vector2d(ca * x + sa * y, -sa * x + ca * y) * p.m_per_px;
          sum += Radiance(p, q);
        }
      ideal.at<float>(r, c) = static_cast<float>(sum / (s * s));
    }
  cv::Mat image = ideal.mul(IlluminationField(o.camera, w, h));
  const LensModel lens(o.camera, w, h);
  if (lens.distorts()) {
    cv::Mat map_x, map_y, recorded;
    lens.BuildRemapMaps(w, h, map_x, map_y);
    RemapBilinear(image, map_x, map_y, recorded);
    image = recorded;
  }
  const CameraEffects& cam = o.camera;
  if (cam.defocus)
    cv::GaussianBlur(image, image, cv::Size(0, 0), cam.defocus_sigma_px, cam.defocus_sigma_px,
                     cv::BORDER_REPLICATE);
  return Sensor(image, cam, o.bit_depth, MixSeed(seed, 0xCA1C));
}

}  // namespace hoof::synth
