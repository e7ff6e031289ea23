#include "tracking/surface_line.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "tracking/frame_source.h"

namespace hoof::tracking {

namespace {

/// The rms distance of `pts` from `line` and their extent along it, into the line.
void MeasureAlong(const std::vector<cv::Point2f>& pts, ImageLine& line) {
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
}

/// The surface as a region's edge: the top edge of the region, unlike the background above it,
/// that fills the bottom of the frame (a textured strip seen against a bright back light, whose
/// texture gives Canny stronger lines inside it than at its edge). The frame is stretched
/// between its 1st and 99th percentiles and smoothed, split in two classes by Otsu's threshold;
/// the class that holds most of the bottom rows (and not of the top rows) is closed over its
/// texture, its component on the bottom row kept, and each column's topmost pixel of it is a
/// point of the edge. A line is fitted to them by least squares, dropping points more than
/// three robust deviations off (a body touching the surface) and refitting. nullopt when there
/// is no such region or its edge is not straight.
std::optional<ImageLine> FindSurfaceRegionEdge(const cv::Mat& grey) {
  const cv::Mat f = ToUnitFloat(grey);
  std::vector<float> v(f.begin<float>(), f.end<float>());
  const auto at = [&](double q) {
    auto it = v.begin() + static_cast<std::ptrdiff_t>(q * static_cast<double>(v.size() - 1));
    std::nth_element(v.begin(), it, v.end());
    return static_cast<double>(*it);
  };
  const double lo = at(0.01), hi = at(0.99);
  if (!(hi - lo > 1e-6)) return std::nullopt;
  cv::Mat img8;
  f.convertTo(img8, CV_8U, 255.0 / (hi - lo), -lo * 255.0 / (hi - lo));
  const double sigma = std::max(2.0, f.rows / 200.0);
  cv::GaussianBlur(img8, img8, cv::Size(), sigma);
  cv::Mat bright;
  cv::threshold(img8, bright, 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU);
  const int band = std::max(2, f.rows / 20);
  const double bottom = cv::mean(bright.rowRange(f.rows - band, f.rows))[0] / 255.0;
  const double top = cv::mean(bright.rowRange(0, band))[0] / 255.0;
  // The surface's class: most of the bottom rows, little of the top rows.
  cv::Mat region;
  if (bottom > 0.5 && top < 0.5)
    region = bright;
  else if (bottom < 0.5 && top > 0.5)
    region = 255 - bright;
  else
    return std::nullopt;
  const int k = std::max(3, f.rows / 50) | 1;
  cv::morphologyEx(region, region, cv::MORPH_CLOSE,
                   cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(k, k)));
  cv::Mat labels;
  const int n = cv::connectedComponents(region, labels, 8, CV_32S);
  std::vector<int> on_bottom(static_cast<std::size_t>(n), 0);
  for (int x = 0; x < f.cols; ++x)
    ++on_bottom[static_cast<std::size_t>(labels.at<int>(f.rows - 1, x))];
  on_bottom[0] = 0;  // the other class
  const int label =
      static_cast<int>(std::max_element(on_bottom.begin(), on_bottom.end()) - on_bottom.begin());
  if (label == 0 || on_bottom[static_cast<std::size_t>(label)] < f.cols / 3) return std::nullopt;
  std::vector<cv::Point2f> pts;
  for (int x = 0; x < f.cols; ++x)
    for (int y = 0; y < f.rows; ++y)
      if (labels.at<int>(y, x) == label) {
        if (y > 0) pts.emplace_back(static_cast<float>(x), static_cast<float>(y) - 0.5f);
        break;
      }
  ImageLine line;
  std::vector<cv::Point2f> kept = pts;
  for (int pass = 0; pass < 4; ++pass) {
    if (kept.size() < static_cast<std::size_t>(f.cols / 3)) return std::nullopt;
    cv::Vec4f fit;
    cv::fitLine(kept, fit, pass == 0 ? cv::DIST_HUBER : cv::DIST_L2, 0, 0.01, 0.01);
    line.direction_I = Eigen::Vector2d(fit[0], fit[1]).normalized();
    if (line.direction_I.x() < 0) line.direction_I = -line.direction_I;
    line.point_I = {fit[2], fit[3]};
    const Eigen::Vector2d nn(-line.direction_I.y(), line.direction_I.x());
    std::vector<double> res, abs_res;
    for (const auto& p : pts) res.push_back(nn.dot(Eigen::Vector2d(p.x, p.y) - line.point_I));
    for (double r : res) abs_res.push_back(std::abs(r));
    auto mid = abs_res.begin() + static_cast<std::ptrdiff_t>(abs_res.size() / 2);
    std::nth_element(abs_res.begin(), mid, abs_res.end());
    const double keep = std::max(1.0, 3 * 1.4826 * *mid);
    kept.clear();
    for (std::size_t i = 0; i < pts.size(); ++i)
      if (std::abs(res[i]) < keep) kept.push_back(pts[i]);
  }
  if (kept.size() < static_cast<std::size_t>(f.cols / 3)) return std::nullopt;
  MeasureAlong(kept, line);
  const double angle =
      std::abs(std::atan2(line.direction_I.y(), line.direction_I.x())) * 180 / CV_PI;
  if (line.length_px < f.cols / 3.0 || std::min(angle, 180 - angle) > 60 ||
      line.rms_residual_px > 3.0)
    return std::nullopt;
  return line;
}

}  // namespace

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
  if (best <= 0) return FindSurfaceRegionEdge(grey);
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
  MeasureAlong(pts, line);
  return line;
}

}  // namespace hoof::tracking
