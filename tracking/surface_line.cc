#include "tracking/surface_line.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "tracking/frame_source.h"

namespace hoof::tracking {

std::optional<ImageLine> FindSurfaceLine(const cv::Mat& grey) {
  cv::Mat img8;
  ToUnitFloat(grey).convertTo(img8, CV_8U, 255.0);
  cv::GaussianBlur(img8, img8, cv::Size(5, 5), 1.5);
  // Thresholds from the gradient magnitudes: the strongest 10 % are edges (upper), half of
  // that value continues them (lower).
  cv::Mat gx, gy, mag;
  cv::Sobel(img8, gx, CV_32F, 1, 0);
  cv::Sobel(img8, gy, CV_32F, 0, 1);
  cv::magnitude(gx, gy, mag);
  std::vector<float> m(mag.begin<float>(), mag.end<float>());
  auto q = m.begin() + static_cast<std::ptrdiff_t>(0.9 * static_cast<double>(m.size()));
  std::nth_element(m.begin(), q, m.end());
  const double upper = std::max(20.0, static_cast<double>(*q));
  cv::Mat edges;
  cv::Canny(img8, edges, 0.5 * upper, upper);
  std::vector<cv::Vec4i> segments;
  cv::HoughLinesP(edges, segments, 1, CV_PI / 720, 60, grey.cols / 3.0, 8);
  double best = 0;
  cv::Vec4i pick;
  for (const auto& s : segments) {
    const double dx = s[2] - s[0], dy = s[3] - s[1];
    const double len = std::hypot(dx, dy);
    const double angle = std::abs(std::atan2(dy, dx)) * 180 / CV_PI;
    const double from_horizontal = std::min(angle, 180 - angle);
    if (from_horizontal > 60 || len < best) continue;
    best = len;
    pick = s;
  }
  if (best <= 0) return std::nullopt;
  // Refine with the edge points within 3 px of the segment's line.
  const Eigen::Vector2d a(pick[0], pick[1]), b(pick[2], pick[3]);
  const Eigen::Vector2d u = (b - a).normalized();
  const Eigen::Vector2d n(-u.y(), u.x());
  std::vector<cv::Point2f> pts;
  for (int y = 0; y < edges.rows; ++y)
    for (int x = 0; x < edges.cols; ++x)
      if (edges.at<uchar>(y, x) && std::abs(n.dot(Eigen::Vector2d(x, y) - a)) < 3.0)
        pts.emplace_back(static_cast<float>(x), static_cast<float>(y));
  if (pts.size() < 10) return std::nullopt;
  cv::Vec4f fit;
  cv::fitLine(pts, fit, cv::DIST_HUBER, 0, 0.01, 0.01);
  ImageLine line;
  line.direction_I = Eigen::Vector2d(fit[0], fit[1]).normalized();
  if (line.direction_I.x() < 0) line.direction_I = -line.direction_I;
  line.point_I = {fit[2], fit[3]};
  const Eigen::Vector2d nn(-line.direction_I.y(), line.direction_I.x());
  double ss = 0, lo = 1e18, hi = -1e18;
  for (const auto& p : pts) {
    const Eigen::Vector2d d = Eigen::Vector2d(p.x, p.y) - line.point_I;
    ss += std::pow(nn.dot(d), 2);
    lo = std::min(lo, line.direction_I.dot(d));
    hi = std::max(hi, line.direction_I.dot(d));
  }
  line.rms_residual_px = std::sqrt(ss / static_cast<double>(pts.size()));
  line.length_px = hi - lo;
  return line;
}

}  // namespace hoof::tracking
