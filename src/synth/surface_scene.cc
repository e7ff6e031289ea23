#include "synth/surface_scene.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

namespace hoof::synth {
namespace {

cv::Mat Noise(cv::Size size, double sigma_x, double sigma_y, cv::RNG& rng) {
  cv::Mat n(size, CV_32F);
  rng.fill(n, cv::RNG::NORMAL, 0.0, 1.0);
  if (sigma_x > 0) cv::GaussianBlur(n, n, cv::Size(0, 0), sigma_x, sigma_y, cv::BORDER_REFLECT);
  cv::Scalar mean, sd;
  cv::meanStdDev(n, mean, sd);
  return (n - mean[0]) / std::max(sd[0], 1e-12);
}

/// Random angular stones (irregular convex polygons, 5-9 corners) with radii in
/// [r_min, r_max] px and radiance drawn around `grey`, `count` of them, below row `top`.
/// Stones of more than 3 px get a lit upper rim and a darker lower part, as crushed
/// aggregate under lights from above.
void Scatter(cv::Mat& canvas, int top, int count, double r_min, double r_max, double grey,
             double grey_sd, cv::RNG& rng) {
  std::vector<cv::Point> poly;
  for (int i = 0; i < count; ++i) {
    const double r = rng.uniform(r_min, r_max);
    const cv::Point2d c(rng.uniform(0.0, canvas.cols * 1.0),
                        rng.uniform(top - r, canvas.rows * 1.0));
    const int corners = rng.uniform(5, 10);
    const double squash = rng.uniform(0.55, 1.0), turn = rng.uniform(0.0, 2 * M_PI);
    poly.clear();
    for (int k = 0; k < corners; ++k) {
      const double a = 2 * M_PI * (k + rng.uniform(-0.3, 0.3)) / corners;
      const double rr = r * rng.uniform(0.75, 1.15);
      const double x = rr * std::cos(a), y = rr * squash * std::sin(a);
      poly.emplace_back(
          static_cast<int>(std::lround(c.x + x * std::cos(turn) - y * std::sin(turn))),
          static_cast<int>(std::lround(c.y + x * std::sin(turn) + y * std::cos(turn))));
    }
    const double value = std::clamp(grey + grey_sd * rng.gaussian(1.0), 0.0, 1.0);
    cv::fillConvexPoly(canvas, poly, cv::Scalar(value), cv::LINE_8);
    if (r > 3) {
      cv::polylines(canvas, poly, true, cv::Scalar(value * 0.75), 1, cv::LINE_8);
      cv::ellipse(canvas, cv::Point(static_cast<int>(c.x), static_cast<int>(c.y - r * 0.25)),
                  cv::Size(static_cast<int>(r * 0.45), static_cast<int>(r * 0.2)), 0, 0, 360,
                  cv::Scalar(std::min(1.0, value * 1.18)), cv::FILLED, cv::LINE_8);
    }
  }
}

void Steel(cv::Mat& f, int top, double px_per_mm, cv::RNG& rng) {
  const int thick = static_cast<int>(std::lround(10 * px_per_mm));  // 10 mm plate
  const cv::Mat brushed = Noise(f.size(), 40, 0.6, rng);
  const cv::Mat fine = Noise(f.size(), 0.7, 0.7, rng);
  const cv::Mat bench = Noise(f.size(), 25, 25, rng);
  for (int r = 0; r < f.rows; ++r) {
    auto* p = f.ptr<float>(r);
    const double v = r - top;
    for (int c = 0; c < f.cols; ++c) {
      double x;
      if (v < thick) {
        x = 0.44 + 0.03 * brushed.at<float>(r, c) + 0.012 * fine.at<float>(r, c);
        x -= 0.18 * std::exp(-(thick - v) / 2.0);  // rounded lower edge in shadow
      } else {
        x = 0.05 + 0.01 * bench.at<float>(r, c);  // the bench the plate lies on
      }
      p[c] = static_cast<float>(x);
    }
  }
}

void Concrete(cv::Mat& f, int top, double px_per_mm, cv::RNG& rng) {
  const cv::Mat grain = Noise(f.size(), 0.8, 0.8, rng);
  const cv::Mat mottle = Noise(f.size(), 12 * px_per_mm / 5, 12 * px_per_mm / 5, rng);
  for (int r = 0; r < f.rows; ++r) {
    auto* p = f.ptr<float>(r);
    for (int c = 0; c < f.cols; ++c)
      p[c] =
          static_cast<float>(0.46 + 0.05 * grain.at<float>(r, c) + 0.03 * mottle.at<float>(r, c));
  }
  const double area = f.cols * 1.0 * (f.rows - top) / (px_per_mm * px_per_mm);  // mm^2
  Scatter(f, top, static_cast<int>(area * 0.06), 0.4 * px_per_mm, 1.6 * px_per_mm, 0.44, 0.12, rng);
  Scatter(f, top, static_cast<int>(area * 0.12), 0.12 * px_per_mm, 0.35 * px_per_mm, 0.22, 0.05,
          rng);
  cv::GaussianBlur(f, f, cv::Size(0, 0), 0.6);
  f += Noise(f.size(), 0.5, 0.5, rng) * 0.02;
}

void Asphalt(cv::Mat& f, int top, double px_per_mm, cv::RNG& rng) {
  const cv::Mat grain = Noise(f.size(), 0.7, 0.7, rng);
  for (int r = 0; r < f.rows; ++r) {
    auto* p = f.ptr<float>(r);
    for (int c = 0; c < f.cols; ++c) p[c] = static_cast<float>(0.10 + 0.02 * grain.at<float>(r, c));
  }
  const double area = f.cols * 1.0 * (f.rows - top) / (px_per_mm * px_per_mm);
  Scatter(f, top, static_cast<int>(area * 0.05), 0.6 * px_per_mm, 2.2 * px_per_mm, 0.24, 0.07, rng);
  Scatter(f, top, static_cast<int>(area * 0.10), 0.2 * px_per_mm, 0.6 * px_per_mm, 0.20, 0.06, rng);
  Scatter(f, top, static_cast<int>(area * 0.02), 0.05 * px_per_mm, 0.12 * px_per_mm, 0.55, 0.1,
          rng);
  cv::GaussianBlur(f, f, cv::Size(0, 0), 0.6);
  f += Noise(f.size(), 0.6, 0.6, rng) * 0.025;
}

}  // namespace

SurfaceTexture BuildSurfaceTexture(dynamics::Surface surface, double m_per_px, cv::Size frame,
                                   std::uint64_t seed) {
  SurfaceTexture t;
  t.surface = surface;
  const int diag = static_cast<int>(std::ceil(std::hypot(frame.width, frame.height)));
  t.radiance.create(cv::Size(2 * diag + 400, diag + t.top_row + 8), CV_32F);
  cv::RNG rng(seed * 0xD1B54A32D192ED03ull + static_cast<std::uint64_t>(surface) + 3);
  const double px_per_mm = 1e-3 / m_per_px;
  switch (surface) {
    case dynamics::Surface::kSteel:
      Steel(t.radiance, t.top_row, px_per_mm, rng);
      break;
    case dynamics::Surface::kConcrete:
      Concrete(t.radiance, t.top_row, px_per_mm, rng);
      break;
    case dynamics::Surface::kAsphalt:
      Asphalt(t.radiance, t.top_row, px_per_mm, rng);
      break;
  }
  cv::max(t.radiance, 0.0, t.radiance);
  return t;
}

cv::Mat RenderBackground(const SurfaceTexture& texture, const SurfacePlacement& placement,
                         cv::Size frame, std::uint64_t seed) {
  const double cs = std::cos(placement.angle_rad), sn = std::sin(placement.angle_rad);
  const Eigen::Vector2d c = placement.contact_px;
  // Image -> canvas: u = (p - c) . (cos, sin), v = (p - c) . (-sin, cos).
  const double u0 = texture.radiance.cols / 2.0 + placement.u_offset_px;
  const double v0 = texture.top_row;
  cv::Matx23d m(cs, sn, u0 - cs * c.x() - sn * c.y(), -sn, cs, v0 + sn * c.x() - cs * c.y());
  cv::Mat face;
  cv::warpAffine(texture.radiance, face, m, frame, cv::INTER_LINEAR | cv::WARP_INVERSE_MAP,
                 cv::BORDER_REFLECT);

  cv::RNG rng(seed * 0xA24BAED4963EE407ull + 5);
  const cv::Mat backdrop = Noise(frame, 40, 40, rng);
  const bool steel = texture.surface == dynamics::Surface::kSteel;
  const double edge_gain =
      steel ? 0.45 : (texture.surface == dynamics::Surface::kConcrete ? 0.10 : 0.05);
  const double spec_u = -0.18 * frame.width;  // specular lobe of the lights, left of contact
  cv::Mat out(frame, CV_32F);
  for (int r = 0; r < frame.height; ++r) {
    auto* o = out.ptr<float>(r);
    const auto* f = face.ptr<float>(r);
    for (int col = 0; col < frame.width; ++col) {
      const double dx = col - c.x(), dy = r - c.y();
      const double u = dx * cs + dy * sn, v = -dx * sn + dy * cs;
      const double lobe = std::exp(-std::pow((u - spec_u) / (0.25 * frame.width), 2));
      double block =
          f[col] + edge_gain * (0.35 + 0.65 * lobe) * std::exp(-std::pow(v - 1.2, 2) / 2.0);
      if (steel) block += 0.2 * lobe * std::exp(-std::max(v, 0.0) / 25.0);
      const double studio =
          0.035 + 0.01 * backdrop.at<float>(r, col) + 0.025 * std::exp(std::min(v, 0.0) / 40.0);
      const double alpha = std::clamp(v + 0.5, 0.0, 1.0);  // area coverage of the edge
      o[col] = static_cast<float>(alpha * block + (1 - alpha) * studio);
    }
  }
  return out;
}

cv::Mat RenderBacklitBackground(const SurfacePlacement& placement, cv::Size frame) {
  const double cs = std::cos(placement.angle_rad), sn = std::sin(placement.angle_rad);
  const Eigen::Vector2d c = placement.contact_px;
  cv::Mat out(frame, CV_32F);
  for (int r = 0; r < frame.height; ++r) {
    auto* o = out.ptr<float>(r);
    for (int col = 0; col < frame.width; ++col) {
      const double v = -(col - c.x()) * sn + (r - c.y()) * cs;  // depth below the surface line
      const double alpha = std::clamp(v + 0.5, 0.0, 1.0);       // area coverage of the edge
      o[col] = static_cast<float>(alpha * kBacklitBlockRadiance +
                                  (1 - alpha) * kBacklitBackgroundRadiance);
    }
  }
  return out;
}

}  // namespace hoof::synth
