#pragma once
/// @file
/// Bilinear sampling of a unit-float image at a sub-pixel position, shared by the silhouette
/// tracker's edge profiles (tracking/silhouette_tracker.cc) and the round end's arc
/// (src/pipeline/round_end.cc). OpenCV's getRectSubPix samples a whole patch and cv::remap a
/// whole map; a profile needs one value at a time.

#include <algorithm>

#include <opencv2/core.hpp>

namespace hoof::tracking {

/// The CV_32F image `img` at (x, y) (px, the centre of pixel (0, 0) at (0, 0)), interpolated
/// bilinearly, into `value`; false (and `value` unchanged) outside the pixel centres' hull.
inline bool SampleBilinear(const cv::Mat& img, double x, double y, double& value) {
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

}  // namespace hoof::tracking
