#pragma once
// Test-side drawing of white dots on black patches, independent of the renderer in src/synth:
// each pixel's value is the exact fraction of it covered by the disk, estimated on a 16 x 16
// sub-pixel grid.
#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace hoof::testing {

/// A grey background with black square patches and white disks on them (8-bit).
inline cv::Mat DrawDots(int width, int height, const std::vector<Eigen::Vector2d>& centres,
                        double radius, double patch_half, double noise_sd = 0.0,
                        unsigned seed = 1) {
  cv::Mat img(height, width, CV_32F, cv::Scalar(0.45f));
  for (const auto& c : centres) {
    for (int y = static_cast<int>(c.y() - patch_half); y <= static_cast<int>(c.y() + patch_half);
         ++y)
      for (int x = static_cast<int>(c.x() - patch_half); x <= static_cast<int>(c.x() + patch_half);
           ++x)
        if (x >= 0 && y >= 0 && x < width && y < height) img.at<float>(y, x) = 0.05f;
    for (int y = static_cast<int>(c.y() - radius - 2); y <= static_cast<int>(c.y() + radius + 2);
         ++y)
      for (int x = static_cast<int>(c.x() - radius - 2); x <= static_cast<int>(c.x() + radius + 2);
           ++x) {
        int inside = 0;
        for (int sy = 0; sy < 16; ++sy)
          for (int sx = 0; sx < 16; ++sx) {
            const double px = x - 0.5 + (sx + 0.5) / 16, py = y - 0.5 + (sy + 0.5) / 16;
            inside += (px - c.x()) * (px - c.x()) + (py - c.y()) * (py - c.y()) <= radius * radius;
          }
        if (x >= 0 && y >= 0 && x < width && y < height)
          img.at<float>(y, x) = static_cast<float>(0.05 + 0.85 * inside / 256.0);
      }
  }
  if (noise_sd > 0) {
    std::mt19937 rng(seed);
    std::normal_distribution<float> g(0.0f, static_cast<float>(noise_sd));
    for (auto it = img.begin<float>(); it != img.end<float>(); ++it) *it += g(rng);
  }
  cv::Mat out;
  img.convertTo(out, CV_8U, 255.0);
  return out;
}

}  // namespace hoof::testing
