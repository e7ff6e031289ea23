#pragma once
// Test-side drawing of silhouettes, independent of the renderer in src/synth and of the
// tracker: each pixel's value is the exact fraction of it covered by the shape, estimated on a
// 16 x 16 sub-pixel grid wherever the shape's edge may pass through the pixel.
#include <cmath>
#include <functional>
#include <random>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace hoof::testing {

/// A shape: true where a point (px, image frame) is inside.
using Inside = std::function<bool(double, double)>;

/// Fraction of the pixel (x, y) (centre at integer coordinates) inside `shape`: 5 probes
/// decide whether the pixel is all in or all out, else a 16 x 16 grid.
inline double Coverage(const Inside& shape, int x, int y) {
  const bool c = shape(x, y);
  if (shape(x - 0.5, y - 0.5) == c && shape(x + 0.5, y - 0.5) == c &&
      shape(x - 0.5, y + 0.5) == c && shape(x + 0.5, y + 0.5) == c && shape(x, y - 0.5) == c &&
      shape(x, y + 0.5) == c && shape(x - 0.5, y) == c && shape(x + 0.5, y) == c)
    return c ? 1.0 : 0.0;
  int n = 0;
  for (int sy = 0; sy < 16; ++sy)
    for (int sx = 0; sx < 16; ++sx)
      n += shape(x - 0.5 + (sx + 0.5) / 16, y - 0.5 + (sy + 0.5) / 16);
  return n / 256.0;
}

/// Adds `level` x coverage of `shape` (over the box [x0, x1] x [y0, y1]) to `img` (CV_64F).
inline void Paint(cv::Mat& img, const Inside& shape, double level, int x0, int y0, int x1, int y1) {
  for (int y = std::max(0, y0); y <= std::min(img.rows - 1, y1); ++y)
    for (int x = std::max(0, x0); x <= std::min(img.cols - 1, x1); ++x) {
      const double a = Coverage(shape, x, y);
      if (a > 0) img.at<double>(y, x) += level * a;
    }
}

inline Inside Disc(Eigen::Vector2d c, double r) {
  return [c, r](double x, double y) {
    return (x - c.x()) * (x - c.x()) + (y - c.y()) * (y - c.y()) <= r * r;
  };
}

/// Paints a disc replacing the background `bg` by `level` (coverage-weighted).
inline void PaintDisc(cv::Mat& img, const Eigen::Vector2d& c, double r, double level, double bg) {
  Paint(img, Disc(c, r), level - bg, static_cast<int>(c.x() - r - 2),
        static_cast<int>(c.y() - r - 2), static_cast<int>(c.x() + r + 2),
        static_cast<int>(c.y() + r + 2));
}

/// A bar with one rounded end: a half-disc of radius w/2 about E and a rectangle of length
/// `rect_length` and width w beyond it, its axis x_B at `angle` (image frame, y down).
inline Inside RoundedBar(Eigen::Vector2d E, double angle, double w, double rect_length) {
  const double c = std::cos(angle), s = std::sin(angle), R = w / 2;
  return [=](double x, double y) {
    const double dx = x - E.x(), dy = y - E.y();
    const double u = c * dx + s * dy, v = -s * dx + c * dy;
    if (u >= 0) return u <= rect_length && std::abs(v) <= R;
    return u * u + v * v <= R * R;
  };
}

/// Distance from E along x_B to the rounded bar's area centroid (closed form).
inline double RoundedBarCentroid(double w, double rect_length) {
  const double R = w / 2, pi = 3.14159265358979323846;
  const double a_rect = w * rect_length, a_half = pi * R * R / 2;
  return (a_rect * rect_length / 2 - a_half * 4 * R / (3 * pi)) / (a_rect + a_half);
}

/// A frame (CV_64F, in the caller's units) to 8-bit or to 16-bit holding 12-bit values, with
/// Gaussian noise of s.d. `noise` (same units) from a fixed seed.
inline cv::Mat Quantize(const cv::Mat& img, int depth, double noise = 0.0, unsigned seed = 1) {
  cv::Mat noisy = img.clone();
  if (noise > 0) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> g(0.0, noise);
    for (auto it = noisy.begin<double>(); it != noisy.end<double>(); ++it) *it += g(rng);
  }
  cv::Mat out;
  if (depth == CV_8U) {
    noisy.convertTo(out, CV_8U);
  } else {
    cv::Mat clipped = cv::min(cv::max(noisy, 0.0), 4095.0);
    clipped.convertTo(out, CV_16U);
  }
  return out;
}

}  // namespace hoof::testing
