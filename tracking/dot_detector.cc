#include "tracking/dot_detector.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include <opencv2/imgproc.hpp>

#include "tracking/frame_source.h"

namespace hoof::tracking {
namespace {

/// Mean over the integer box [x0, x1) x [y0, y1) from an integral image (CV_64F).
double BoxMean(const cv::Mat& integral, int x0, int y0, int x1, int y1) {
  const double s = integral.at<double>(y1, x1) - integral.at<double>(y0, x1) -
                   integral.at<double>(y1, x0) + integral.at<double>(y0, x0);
  return s / ((x1 - x0) * (y1 - y0));
}

/// "Inside minus ring" contrast map at radius r over the image (valid where the ring fits).
/// Inside: the square of half-size 0.7 r (inscribed-ish in the disk). Ring: the square of
/// half-size 2 r minus the square of half-size 1.3 r (the patch around the dot).
cv::Mat RingContrast(const cv::Mat& integral, int width, int height, double r) {
  cv::Mat out(height, width, CV_32F, cv::Scalar(-1.0f));
  const int a = std::max(1, static_cast<int>(std::lround(0.7 * r)));
  const int b = std::max(a + 1, static_cast<int>(std::lround(1.3 * r)));
  const int c = std::max(b + 1, static_cast<int>(std::lround(2.0 * r)));
  const double inner_area = 4.0 * a * a;
  (void)inner_area;
  for (int y = c; y < height - c; ++y) {
    for (int x = c; x < width - c; ++x) {
      const double inside = BoxMean(integral, x - a, y - a, x + a + 1, y + a + 1);
      const double big = BoxMean(integral, x - c, y - c, x + c + 1, y + c + 1);
      const double mid = BoxMean(integral, x - b, y - b, x + b + 1, y + b + 1);
      const double big_area = (2.0 * c + 1) * (2.0 * c + 1);
      const double mid_area = (2.0 * b + 1) * (2.0 * b + 1);
      const double ring = (big * big_area - mid * mid_area) / (big_area - mid_area);
      out.at<float>(y, x) = static_cast<float>(inside - ring);
    }
  }
  return out;
}

double Median(std::vector<float>& v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

/// Bilinear sample of a CV_32F image; returns false outside.
bool Sample(const cv::Mat& img, double x, double y, double& value) {
  if (x < 0 || y < 0 || x > img.cols - 1.001 || y > img.rows - 1.001) return false;
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const double fx = x - x0, fy = y - y0;
  const float* r0 = img.ptr<float>(y0);
  const float* r1 = img.ptr<float>(y0 + 1);
  value =
      (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x0 + 1]) + fy * ((1 - fx) * r1[x0] + fx * r1[x0 + 1]);
  return true;
}

/// Levels around a coarse centre in a unit-float window: bright = median inside 0.5 r,
/// dark = median of the ring 1.35 r .. 1.75 r, noise = robust s.d. on that ring.
bool MeasureLevels(const cv::Mat& win, const Eigen::Vector2d& c, double r, Dot& dot) {
  thread_local std::vector<float> inner, ring;
  inner.clear();
  ring.clear();
  const int R = static_cast<int>(std::ceil(1.75 * r)) + 1;
  const int cx = static_cast<int>(std::lround(c.x())), cy = static_cast<int>(std::lround(c.y()));
  const double in2 = 0.25 * r * r, lo2 = 1.35 * 1.35 * r * r, hi2 = 1.75 * 1.75 * r * r;
  for (int y = std::max(0, cy - R); y <= std::min(win.rows - 1, cy + R); ++y) {
    const float* row = win.ptr<float>(y);
    const double dy2 = (y - c.y()) * (y - c.y());
    for (int x = std::max(0, cx - R); x <= std::min(win.cols - 1, cx + R); ++x) {
      const double d2 = (x - c.x()) * (x - c.x()) + dy2;
      if (d2 <= in2)
        inner.push_back(row[x]);
      else if (d2 >= lo2 && d2 <= hi2)
        ring.push_back(row[x]);
    }
  }
  if (inner.size() < 3 || ring.size() < 8) return false;
  dot.bright = Median(inner);
  dot.dark = Median(ring);
  thread_local std::vector<float> dev;
  dev.clear();
  for (float v : ring) dev.push_back(std::abs(v - static_cast<float>(dot.dark)));
  // MAD -> sigma. On quantized patches the MAD can be 0 while the noise is not, so half the
  // ring's standard deviation and half an 8-bit step are floors.
  double ss = 0;
  for (float v : dev) ss += static_cast<double>(v) * v;
  const double sd = std::sqrt(ss / static_cast<double>(dev.size()));
  dot.noise = std::max({1.4826 * Median(dev), 0.5 * sd, 0.5 / 255.0});
  dot.significance = (dot.bright - dot.dark) / dot.noise;
  return true;
}

/// Intensity-weighted centroid, re-centred; updates dot.p_I (window coords) and radius.
void WeightedCentroid(const cv::Mat& win, Dot& dot, int iterations) {
  const double span = dot.bright - dot.dark;
  for (int it = 0; it < iterations; ++it) {
    const double rw = std::min(1.5 * dot.radius_px, dot.radius_px + 4.0);
    const int x0 = std::max(0, static_cast<int>(std::floor(dot.p_I.x() - rw)));
    const int x1 = std::min(win.cols - 1, static_cast<int>(std::ceil(dot.p_I.x() + rw)));
    const int y0 = std::max(0, static_cast<int>(std::floor(dot.p_I.y() - rw)));
    const int y1 = std::min(win.rows - 1, static_cast<int>(std::ceil(dot.p_I.y() + rw)));
    double sw = 0, sx = 0, sy = 0;
    for (int y = y0; y <= y1; ++y) {
      const float* row = win.ptr<float>(y);
      const double dy = y - dot.p_I.y();
      for (int x = x0; x <= x1; ++x) {
        const double dx = x - dot.p_I.x();
        if (dx * dx + dy * dy > rw * rw) continue;
        const double w = std::clamp((row[x] - dot.dark) / span, 0.0, 1.0);
        sw += w;
        sx += w * x;
        sy += w * y;
      }
    }
    if (sw <= 0) return;
    const Eigen::Vector2d moved = Eigen::Vector2d(sx / sw, sy / sw) - dot.p_I;
    dot.p_I += moved;
    dot.radius_px = std::sqrt(sw / std::numbers::pi);
    if (moved.squaredNorm() < 1e-8) return;  // converged to 1e-4 px
  }
}

/// Ellipse through the mid-level crossings along 64 rays; updates dot.p_I (window coords).
bool EllipseCentre(const cv::Mat& win, Dot& dot) {
  const double level = 0.5 * (dot.bright + dot.dark);
  std::vector<cv::Point2f> edge;
  for (int k = 0; k < 64; ++k) {
    const double a = 2 * std::numbers::pi * k / 64;
    const double ux = std::cos(a), uy = std::sin(a);
    double prev = 0;
    if (!Sample(win, dot.p_I.x(), dot.p_I.y(), prev)) continue;
    for (double s = 0.25; s < 2.0 * dot.radius_px; s += 0.25) {
      double v = 0;
      if (!Sample(win, dot.p_I.x() + s * ux, dot.p_I.y() + s * uy, v)) break;
      if (prev >= level && v < level) {
        const double t = s - 0.25 + 0.25 * (prev - level) / (prev - v);
        edge.emplace_back(static_cast<float>(dot.p_I.x() + t * ux),
                          static_cast<float>(dot.p_I.y() + t * uy));
        break;
      }
      prev = v;
    }
  }
  if (edge.size() < 16) return false;
  const cv::RotatedRect e = cv::fitEllipseDirect(edge);
  const Eigen::Vector2d centre{e.center.x, e.center.y};
  // Residual: distance of edge points to the fitted ellipse (approximate, radial).
  const double c = std::cos(e.angle * std::numbers::pi / 180),
               s = std::sin(e.angle * std::numbers::pi / 180);
  const double A = 0.5 * e.size.width, B = 0.5 * e.size.height;
  double ss = 0;
  for (const auto& p : edge) {
    const double dx = p.x - centre.x(), dy = p.y - centre.y();
    const double u = c * dx + s * dy, v = -s * dx + c * dy;
    const double rho = std::hypot(u, v);
    const double phi = std::atan2(v / B, u / A);
    ss += std::pow(rho - std::hypot(A * std::cos(phi), B * std::sin(phi)), 2);
  }
  dot.fit_residual_px = std::sqrt(ss / static_cast<double>(edge.size()));
  dot.p_I = centre;
  return true;
}

/// Refines a coarse dot (window coordinates) into a measured one; false if not significant.
bool Refine(const cv::Mat& win, const Eigen::Vector2d& coarse, double radius,
            const DotDetectorOptions& options, Dot& dot) {
  dot.p_I = coarse;
  dot.radius_px = radius;
  // The coarse radius may be a scale step off, so the first levels only seed the centroid,
  // whose weighted area gives the radius the significance is then judged at.
  if (!MeasureLevels(win, coarse, radius, dot) || !(dot.bright > dot.dark)) return false;
  WeightedCentroid(win, dot, options.centroid_iterations);
  if (!(dot.radius_px > 0.5)) return false;
  // Levels again about the refined centre and radius, then the final centre.
  if (!MeasureLevels(win, dot.p_I, dot.radius_px, dot)) return false;
  if (dot.significance < options.min_significance) return false;
  if (options.method == CentreMethod::kEllipseFit) {
    WeightedCentroid(win, dot, 1);
    return EllipseCentre(win, dot);
  }
  WeightedCentroid(win, dot, options.centroid_iterations);
  return true;
}

}  // namespace

void DotDetectorOptions::Validate() const {
  if (!(min_significance > 0))
    throw std::invalid_argument("dot detector min_significance must be > 0");
  if (centroid_iterations < 1)
    throw std::invalid_argument("dot detector centroid_iterations must be >= 1");
  if (!(min_radius_px > 1 && max_radius_px > min_radius_px))
    throw std::invalid_argument(
        "dot detector radii must satisfy 1 < min_radius_px < max_radius_px");
}

double EstimateNoise(const cv::Mat& unit_float) {
  std::vector<float> d;
  d.reserve(static_cast<std::size_t>(unit_float.rows) * static_cast<std::size_t>(unit_float.cols));
  for (int y = 0; y < unit_float.rows; ++y) {
    const float* row = unit_float.ptr<float>(y);
    for (int x = 0; x + 1 < unit_float.cols; ++x) d.push_back(std::abs(row[x + 1] - row[x]));
  }
  return 1.4826 * Median(d) / std::sqrt(2.0);
}

namespace {

/// A local maximum of the ring contrast, in full-resolution coordinates.
struct Peak {
  float v;
  double x, y;
};

/// The best ring contrast over the detector's scales at each pixel of `search` (`best`), and
/// the radius that gave it (`best_r`, full-resolution px; `search` is `to_full` times smaller).
void BestRingContrast(const cv::Mat& search, const DotDetectorOptions& options, double to_full,
                      cv::Mat& best, cv::Mat& best_r) {
  cv::Mat integral;
  cv::integral(search, integral, CV_64F);
  best = cv::Mat(search.size(), CV_32F, cv::Scalar(-1.0f));
  best_r = cv::Mat(search.size(), CV_32F, cv::Scalar(0));
  for (double r = options.min_radius_px; r <= options.max_radius_px; r *= 1.5) {
    const cv::Mat c = RingContrast(integral, search.cols, search.rows, r / to_full);
    for (int y = 0; y < search.rows; ++y) {
      const float* cr = c.ptr<float>(y);
      float* br = best.ptr<float>(y);
      float* rr = best_r.ptr<float>(y);
      for (int x = 0; x < search.cols; ++x)
        if (cr[x] > br[x]) {
          br[x] = cr[x];
          rr[x] = static_cast<float>(r);
        }
    }
  }
}

/// The local maxima of `best` (over 5 x 5), strongest first, in full-resolution coordinates.
std::vector<Peak> Peaks(const cv::Mat& best, double to_full, double offset) {
  cv::Mat dilated;
  cv::dilate(best, dilated, cv::Mat(5, 5, CV_8U, cv::Scalar::all(1)));
  std::vector<Peak> peaks;
  for (int y = 0; y < best.rows; ++y)
    for (int x = 0; x < best.cols; ++x) {
      const float v = best.at<float>(y, x);
      if (v > 0 && v >= dilated.at<float>(y, x))
        peaks.push_back({v, x * to_full + offset, y * to_full + offset});
    }
  std::sort(peaks.begin(), peaks.end(), [](const Peak& a, const Peak& b) { return a.v > b.v; });
  return peaks;
}

}  // namespace

std::vector<Dot> FindDots(const cv::Mat& grey, int count, const DotDetectorOptions& options) {
  options.Validate();
  const cv::Mat img = ToUnitFloat(grey);
  // The candidate search runs on a half-resolution image (4 times fewer pixels) when the dots
  // it looks for are at least 2.5 px in radius there too; candidates are then refined at full
  // resolution. Half-resolution pixel i covers full-resolution pixels 2i and 2i + 1.
  const bool half = options.min_radius_px >= 2.5 && std::min(img.cols, img.rows) >= 128;
  cv::Mat search;
  if (half)
    cv::resize(img, search, cv::Size(img.cols / 2, img.rows / 2), 0, 0, cv::INTER_AREA);
  else
    search = img;
  const double to_full = half ? 2.0 : 1.0;
  const double offset = half ? 0.5 : 0.0;
  // Best contrast over scales at each pixel, and its radius (full-resolution px).
  cv::Mat best, best_r;
  BestRingContrast(search, options, to_full, best, best_r);
  const std::vector<Peak> peaks = Peaks(best, to_full, offset);
  // Peaks far below the significance rule (judged against the image's own noise) cannot be
  // dots; stop there, and after a bounded number of refinements.
  const double floor = 0.5 * options.min_significance * std::max(EstimateNoise(img), 0.5 / 255.0);
  std::vector<Dot> dots;
  int attempts = 0;
  for (const Peak& p : peaks) {
    if (static_cast<int>(dots.size()) >= count || p.v < floor || ++attempts > 16 * count) break;
    const double r =
        best_r.at<float>(static_cast<int>(p.y / to_full), static_cast<int>(p.x / to_full));
    bool near = false;
    for (const Dot& d : dots)
      near = near || (d.p_I - Eigen::Vector2d(p.x, p.y)).norm() < 2.5 * std::max(r, d.radius_px);
    if (near) continue;
    Dot dot;
    if (!Refine(img, Eigen::Vector2d(p.x, p.y), r, options, dot)) continue;
    bool dup = false;
    for (const Dot& d : dots) dup = dup || (d.p_I - dot.p_I).norm() < 2.0 * d.radius_px;
    if (!dup) dots.push_back(dot);
    if (dots.size() > 64) break;
  }
  std::sort(dots.begin(), dots.end(),
            [](const Dot& a, const Dot& b) { return a.significance > b.significance; });
  return dots;
}

std::optional<Dot> FindDotNear(const cv::Mat& grey, const Eigen::Vector2d& predicted_I,
                               double search_radius_px, double expected_radius_px,
                               const DotDetectorOptions& options) {
  const double half = search_radius_px + 2.2 * expected_radius_px + 2;
  const int x0 = std::max(0, static_cast<int>(std::floor(predicted_I.x() - half)));
  const int y0 = std::max(0, static_cast<int>(std::floor(predicted_I.y() - half)));
  const int x1 = std::min(grey.cols, static_cast<int>(std::ceil(predicted_I.x() + half)) + 1);
  const int y1 = std::min(grey.rows, static_cast<int>(std::ceil(predicted_I.y() + half)) + 1);
  if (x1 - x0 < 8 || y1 - y0 < 8) return std::nullopt;
  const cv::Mat win = ToUnitFloat(grey(cv::Rect(x0, y0, x1 - x0, y1 - y0)));
  cv::Mat integral;
  cv::integral(win, integral, CV_64F);
  const cv::Mat c = RingContrast(integral, win.cols, win.rows, expected_radius_px);
  // Best contrast within the search disk around the prediction.
  const Eigen::Vector2d pw = predicted_I - Eigen::Vector2d(x0, y0);
  double best = 0;
  Eigen::Vector2d coarse = pw;
  const double r2 = search_radius_px * search_radius_px;
  for (int y = 0; y < win.rows; ++y)
    for (int x = 0; x < win.cols; ++x) {
      if ((x - pw.x()) * (x - pw.x()) + (y - pw.y()) * (y - pw.y()) > r2) continue;
      const float v = c.at<float>(y, x);
      if (v > best) {
        best = v;
        coarse = {x, y};
      }
    }
  if (best <= 0) return std::nullopt;
  Dot dot;
  if (!Refine(win, coarse, expected_radius_px, options, dot)) return std::nullopt;
  if ((dot.p_I - pw).norm() > search_radius_px + 1.0) return std::nullopt;
  dot.p_I += Eigen::Vector2d(x0, y0);
  return dot;
}

}  // namespace hoof::tracking
