#include "synth/camera_model.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

namespace hoof::synth {

LensModel::LensModel(const CameraEffects& camera, int width_px, int height_px)
    : distorts_(camera.distortion),
      focal_px_(camera.focal_px),
      c_px_(Eigen::Vector2d{(width_px - 1) / 2.0, (height_px - 1) / 2.0} +
            camera.principal_offset_px) {
  if (distorts_) {
    k1_ = camera.k1;
    k2_ = camera.k2;
    p1_ = camera.p1;
    p2_ = camera.p2;
    k3_ = camera.k3;
  }
}

Eigen::Vector2d LensModel::Distort(const Eigen::Vector2d& u_px) const {
  if (!distorts_) return u_px;
  const double x = (u_px.x() - c_px_.x()) / focal_px_;
  const double y = (u_px.y() - c_px_.y()) / focal_px_;
  const double r2 = x * x + y * y;
  const double radial = 1 + r2 * (k1_ + r2 * (k2_ + r2 * k3_));
  const double xd = x * radial + 2 * p1_ * x * y + p2_ * (r2 + 2 * x * x);
  const double yd = y * radial + p1_ * (r2 + 2 * y * y) + 2 * p2_ * x * y;
  return {c_px_.x() + focal_px_ * xd, c_px_.y() + focal_px_ * yd};
}

Eigen::Vector2d LensModel::Undistort(const Eigen::Vector2d& d_px) const {
  if (!distorts_) return d_px;
  const double xd = (d_px.x() - c_px_.x()) / focal_px_;
  const double yd = (d_px.y() - c_px_.y()) / focal_px_;
  double x = xd, y = yd;
  for (int i = 0; i < 50; ++i) {
    const double r2 = x * x + y * y;
    const double radial = 1 + r2 * (k1_ + r2 * (k2_ + r2 * k3_));
    const double dx = 2 * p1_ * x * y + p2_ * (r2 + 2 * x * x);
    const double dy = p1_ * (r2 + 2 * y * y) + 2 * p2_ * x * y;
    const double xn = (xd - dx) / radial, yn = (yd - dy) / radial;
    const bool done = std::abs(xn - x) + std::abs(yn - y) < 1e-13;
    x = xn;
    y = yn;
    if (done) break;
  }
  return {c_px_.x() + focal_px_ * x, c_px_.y() + focal_px_ * y};
}

void LensModel::BuildRemapMaps(int width_px, int height_px, cv::Mat& map_x, cv::Mat& map_y) const {
  map_x.create(height_px, width_px, CV_32F);
  map_y.create(height_px, width_px, CV_32F);
  for (int r = 0; r < height_px; ++r) {
    auto* mx = map_x.ptr<float>(r);
    auto* my = map_y.ptr<float>(r);
    for (int c = 0; c < width_px; ++c) {
      const Eigen::Vector2d u = Undistort({c, r});
      mx[c] = static_cast<float>(u.x());
      my[c] = static_cast<float>(u.y());
    }
  }
}

cv::Mat IlluminationField(const CameraEffects& camera, int width_px, int height_px) {
  cv::Mat field(height_px, width_px, CV_32F);
  const double cx = (width_px - 1) / 2.0, cy = (height_px - 1) / 2.0;
  const double r2_corner = cx * cx + cy * cy;
  const double v = camera.vignetting ? camera.vignetting_fraction : 0.0;
  const double g = camera.lighting_gradient ? camera.lighting_gradient_fraction : 0.0;
  // Light from the upper left: brightness falls along (1, 0.6) normalized.
  const double lx = 1 / std::sqrt(1.36), ly = 0.6 / std::sqrt(1.36);
  const double span = std::abs(lx) * width_px + std::abs(ly) * height_px;
  for (int r = 0; r < height_px; ++r) {
    auto* f = field.ptr<float>(r);
    for (int c = 0; c < width_px; ++c) {
      const double dx = c - cx, dy = r - cy;
      const double vignette = 1 - v * (dx * dx + dy * dy) / r2_corner;
      const double ramp = 1 - g * ((dx * lx + dy * ly) / span);
      f[c] = static_cast<float>(vignette * ramp);
    }
  }
  return field;
}

namespace {

/// Standard normal quantiles at the 65536 mid-points (k + 0.5) / 65536: a table lookup with
/// 16 random bits gives a normal deviate (tails cut at 4.3 s.d.), far faster than sampling.
const std::vector<float>& NormalQuantiles() {
  static const std::vector<float> table = [] {
    std::vector<float> t(65536);
    for (int k = 0; k < 65536; ++k) {
      const double p = (k + 0.5) / 65536.0;
      // Acklam's rational approximation refined by one Newton step on erfc.
      double x = std::sqrt(-2 * std::log(p < 0.5 ? p : 1 - p));
      x = x - (2.515517 + 0.802853 * x + 0.010328 * x * x) /
                  (1 + 1.432788 * x + 0.189269 * x * x + 0.001308 * x * x * x);
      x = p < 0.5 ? -x : x;
      for (int it = 0; it < 3; ++it) {
        const double cdf = 0.5 * std::erfc(-x / std::sqrt(2.0));
        x -= (cdf - p) / (std::exp(-x * x / 2) / std::sqrt(2 * M_PI));
      }
      t[k] = static_cast<float>(x);
    }
    return t;
  }();
  return table;
}

/// SplitMix64 stream.
struct Bits {
  std::uint64_t state;
  std::uint64_t Next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
};

}  // namespace

cv::Mat Sensor(const cv::Mat& radiance, const CameraEffects& camera, int bit_depth,
               std::uint64_t noise_seed) {
  CV_Assert(radiance.type() == CV_32F && radiance.isContinuous());
  const float full = static_cast<float>((1 << bit_depth) - 1);  // 255, 4095 or 65535
  const float black = static_cast<float>(camera.black_level);
  const float gain = full * (1 - black), offset = full * black;
  const float fw = static_cast<float>(camera.full_well_e);
  const float read2 = static_cast<float>(camera.read_noise_e * camera.read_noise_e);
  const std::vector<float>& quantile = NormalQuantiles();
  cv::Mat out(radiance.size(), bit_depth > 8 ? CV_16U : CV_8U);
  const float* in = radiance.ptr<float>();
  const std::size_t n = radiance.total();
  Bits bits{noise_seed};
  std::uint64_t word = 0;
  for (std::size_t i = 0; i < n; ++i) {
    float v = std::max(in[i], 0.0f);
    if (camera.noise) {
      // Electrons e = v * full_well; a deviate of variance e + read^2 (Poisson-like shot noise).
      if (i % 4 == 0) word = bits.Next();
      const float z = quantile[(word >> (16 * (i % 4))) & 0xFFFF];
      const float electrons = v * fw;
      v = (electrons + z * std::sqrt(electrons + read2)) / fw;
    }
    const float dn = std::clamp(std::nearbyint(offset + gain * v), 0.0f, full);
    if (bit_depth > 8)
      out.ptr<std::uint16_t>()[i] = static_cast<std::uint16_t>(dn);
    else
      out.ptr<std::uint8_t>()[i] = static_cast<std::uint8_t>(dn);
  }
  return out;
}

}  // namespace hoof::synth
