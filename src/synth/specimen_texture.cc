#include "synth/specimen_texture.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace hoof::synth {
namespace {

/// Zero-mean, unit-variance noise blurred anisotropically (sigmas in texels).
cv::Mat StreakNoise(cv::Size size, double sigma_x, double sigma_y, cv::RNG& rng) {
  cv::Mat n(size, CV_32F);
  rng.fill(n, cv::RNG::NORMAL, 0.0, 1.0);
  cv::GaussianBlur(n, n, cv::Size(0, 0), sigma_x, sigma_y, cv::BORDER_REFLECT);
  cv::Scalar mean, sd;
  cv::meanStdDev(n, mean, sd);
  n = (n - mean[0]) / std::max(sd[0], 1e-12);
  return n;
}

struct Outline {
  double r, x_end, half_w;
  /// Inside the bar: the band |y| <= w/2 from x = -R to L - R, rounded by the circle of
  /// radius R about E for x < 0.
  bool Inside(double x, double y) const {
    if (std::abs(y) > half_w || x > x_end) return false;
    return x >= 0 || x * x + y * y <= r * r;
  }
  /// Distance inside from the outline (m), approximate, for edge shading.
  double Depth(double x, double y) const {
    double d = std::min({half_w - std::abs(y), x_end - x});
    if (x < 0) d = std::min(d, r - std::hypot(x, y));
    return d;
  }
};

}  // namespace

SpecimenTexture BuildBallTexture(const SpecimenGeometry& g, double m_per_px, int oversampling,
                                 Lighting lighting) {
  SpecimenTexture t;
  t.texel_m = m_per_px / oversampling;
  const double r = g.ball_diameter_m / 2, margin = 3 * m_per_px;
  t.origin_B_m = {-r - margin, -r - margin};
  const int n = static_cast<int>(std::ceil((2 * r + 2 * margin) / t.texel_m)) + 1;
  // Light from the upper left, in front (W axes: x right, y up, z toward the camera).
  const double norm = std::sqrt(0.45 * 0.45 + 0.55 * 0.55 + 0.7 * 0.7);
  const double lx = -0.45 / norm, ly = 0.55 / norm, lz = 0.7 / norm;
  const double spot = kBallSpotSigma * r;
  constexpr int kSub = 4;
  t.premultiplied.create(n, n, CV_32FC2);
  for (int j = 0; j < n; ++j) {
    auto* out = t.premultiplied.ptr<cv::Vec2f>(j);
    for (int i = 0; i < n; ++i) {
      double alpha = 0, value = 0;
      for (int sj = 0; sj < kSub; ++sj)
        for (int si = 0; si < kSub; ++si) {
          const double x = t.origin_B_m.x() + (i + (si + 0.5) / kSub - 0.5) * t.texel_m;
          const double y = t.origin_B_m.y() + (j + (sj + 0.5) / kSub - 0.5) * t.texel_m;
          const double rho2 = x * x + y * y;
          if (rho2 > r * r) continue;
          alpha += 1;
          if (lighting == Lighting::kBacklit) {
            value += kSilhouetteRadiance + kBallSpotRadiance * std::exp(-rho2 / (2 * spot * spot));
          } else {
            const double z = std::sqrt(r * r - rho2);
            value += kBallAmbient + kBallDiffuse * std::max(0.0, (x * lx + y * ly + z * lz) / r);
          }
        }
      out[i] = cv::Vec2f(static_cast<float>(value / (kSub * kSub)),
                         static_cast<float>(alpha / (kSub * kSub)));
    }
  }
  cv::blur(t.premultiplied, t.premultiplied, cv::Size(oversampling, oversampling),
           cv::Point(-1, -1), cv::BORDER_CONSTANT);
  return t;
}

SpecimenTexture BuildSpecimenTexture(const SpecimenGeometry& g, double m_per_px, int oversampling,
                                     std::uint64_t seed, Lighting lighting) {
  if (g.body == Body::kBall) return BuildBallTexture(g, m_per_px, oversampling, lighting);
  const bool markers = g.body == Body::kMarkers && lighting == Lighting::kFront;
  const bool silhouette = lighting == Lighting::kBacklit;
  SpecimenTexture t;
  t.texel_m = m_per_px / oversampling;
  const Outline outline{g.dynamics.end_radius_m, g.length_m - g.dynamics.end_radius_m,
                        g.width_m / 2};
  const double margin = 3 * m_per_px;  // zero border wider than the box prefilter
  const double half_h = std::max(outline.half_w, outline.r) + margin;
  t.origin_B_m = {-outline.r - margin, -half_h};
  const int cols =
      static_cast<int>(std::ceil((outline.x_end + outline.r + 2 * margin) / t.texel_m));
  const int rows = static_cast<int>(std::ceil(2 * half_h / t.texel_m));
  const cv::Size size(cols, rows);

  // Hoof-wall grey: tubules ~0.1-0.2 mm wide running along x_B, slower pigment variation.
  cv::RNG rng(seed * 0x9E3779B97F4A7C15ull + 17);
  const double mm = 1e-3 / t.texel_m;  // texels per mm
  const cv::Mat tubules = StreakNoise(size, 2.5 * mm, 0.07 * mm, rng);
  const cv::Mat bands = StreakNoise(size, 6.0 * mm, 0.8 * mm, rng);
  const cv::Mat mottle = StreakNoise(size, 1.5 * mm, 1.5 * mm, rng);

  const double dot_r = g.dot_diameter_m / 2, patch_h = g.patch_size_m / 2;
  constexpr int kSub = 4;
  t.premultiplied.create(size, CV_32FC2);
  for (int j = 0; j < rows; ++j) {
    auto* out = t.premultiplied.ptr<cv::Vec2f>(j);
    for (int i = 0; i < cols; ++i) {
      const double xc = t.origin_B_m.x() + i * t.texel_m, yc = t.origin_B_m.y() + j * t.texel_m;
      const double depth_mm = outline.Depth(xc, yc) * 1e3;
      const double edge = 1 - 0.35 * std::exp(-std::max(depth_mm, 0.0) / 0.5);
      const float wall =
          static_cast<float>((0.40 + 0.045 * tubules.at<float>(j, i) +
                              0.035 * bands.at<float>(j, i) + 0.02 * mottle.at<float>(j, i)) *
                             edge);
      double alpha = 0, value = 0;
      for (int sj = 0; sj < kSub; ++sj)
        for (int si = 0; si < kSub; ++si) {
          const double x = xc + ((si + 0.5) / kSub - 0.5) * t.texel_m;
          const double y = yc + ((sj + 0.5) / kSub - 0.5) * t.texel_m;
          if (!outline.Inside(x, y)) continue;
          alpha += 1;
          double v = silhouette ? kSilhouetteRadiance : wall;
          if (markers)
            for (const Marker& m : g.markers) {
              const double dx = x - m.p_BM_m.x(), dy = y - m.p_BM_m.y();
              if (std::abs(dx) <= patch_h && std::abs(dy) <= patch_h)
                v = dx * dx + dy * dy <= dot_r * dot_r ? kDotRadiance : kPatchRadiance;
            }
          value += v;
        }
      out[i] = cv::Vec2f(static_cast<float>(value / (kSub * kSub)),
                         static_cast<float>(alpha / (kSub * kSub)));
    }
  }
  // One-pixel box prefilter (odd size, so centred): bilinear samples become pixel areas.
  cv::blur(t.premultiplied, t.premultiplied, cv::Size(oversampling, oversampling),
           cv::Point(-1, -1), cv::BORDER_CONSTANT);
  return t;
}

}  // namespace hoof::synth
