#pragma once
// Helpers shared by the synth tests: temporary folders and an independent dot centroid.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

namespace hoof::synth::testing {

/// A fresh folder under the build tree, removed first if it exists.
inline std::filesystem::path FreshDir(const std::string& name) {
  const std::filesystem::path p = std::filesystem::path(HOOF_BINARY_DIR) / "synth-test" / name;
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p.parent_path());
  return p;
}

inline nlohmann::json ReadJson(const std::filesystem::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

/// The test's own simple measurement, sharing nothing with the renderer: the intensity-
/// weighted centroid of the pixels within `window_px` of `guess`, after subtracting the mean
/// of the ring between window_px and window_px + 2 (the black patch around the dot).
inline cv::Point2d DotCentroid(const cv::Mat& image, cv::Point2d guess, double window_px) {
  cv::Mat f;
  image.convertTo(f, CV_64F);
  const int r_out = static_cast<int>(std::ceil(window_px + 2));
  double ring_sum = 0;
  int ring_n = 0;
  for (int y = static_cast<int>(guess.y) - r_out; y <= static_cast<int>(guess.y) + r_out + 1; ++y)
    for (int x = static_cast<int>(guess.x) - r_out; x <= static_cast<int>(guess.x) + r_out + 1;
         ++x) {
      const double d = std::hypot(x - guess.x, y - guess.y);
      if (d > window_px && d <= window_px + 2) {
        ring_sum += f.at<double>(y, x);
        ++ring_n;
      }
    }
  const double background = ring_sum / ring_n;
  double sw = 0, sx = 0, sy = 0;
  for (int y = static_cast<int>(guess.y) - r_out; y <= static_cast<int>(guess.y) + r_out + 1; ++y)
    for (int x = static_cast<int>(guess.x) - r_out; x <= static_cast<int>(guess.x) + r_out + 1;
         ++x) {
      if (std::hypot(x - guess.x, y - guess.y) > window_px) continue;
      const double w = std::max(f.at<double>(y, x) - background, 0.0);
      sw += w;
      sx += w * x;
      sy += w * y;
    }
  return {sx / sw, sy / sw};
}

}  // namespace hoof::synth::testing
