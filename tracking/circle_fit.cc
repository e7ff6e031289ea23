#include "tracking/circle_fit.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace hoof::tracking {
namespace {

double MedianOf(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

/// Weighted algebraic (Kasa) circle: x^2 + y^2 + D x + E y + F = 0 in least squares.
bool KasaFit(const std::vector<Eigen::Vector2d>& p, const std::vector<double>& w,
             const std::vector<char>& use, Eigen::Vector2d& c, double& r) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  int n = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!use[i]) continue;
    const Eigen::Vector3d row{p[i].x(), p[i].y(), 1.0};
    A += w[i] * row * row.transpose();
    b -= w[i] * row * p[i].squaredNorm();
    ++n;
  }
  if (n < 3) return false;
  const Eigen::Vector3d s = A.ldlt().solve(b);
  c = {-s(0) / 2, -s(1) / 2};
  const double r2 = c.squaredNorm() - s(2);
  if (!(r2 > 0) || !s.allFinite()) return false;
  r = std::sqrt(r2);
  return true;
}

/// Weighted geometric circle fit (Gauss-Newton on the distances to the circle) of the points in
/// use, starting from (c, r). Returns J^T W J of the last step.
Eigen::Matrix3d GeometricFit(const std::vector<Eigen::Vector2d>& p, const std::vector<double>& w,
                             const std::vector<char>& use, Eigen::Vector2d& c, double& r) {
  Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();
  for (int it = 0; it < 20; ++it) {
    jtj.setZero();
    Eigen::Vector3d jtr = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (!use[i]) continue;
      const Eigen::Vector2d d = p[i] - c;
      const double dist = d.norm();
      if (!(dist > 0)) continue;
      const Eigen::Vector3d j{-d.x() / dist, -d.y() / dist, -1.0};
      jtj += w[i] * j * j.transpose();
      jtr += w[i] * j * (dist - r);
    }
    const Eigen::Vector3d step = -jtj.ldlt().solve(jtr);
    if (!step.allFinite()) break;
    c += step.head<2>();
    r += step(2);
    if (step.norm() < 1e-9) break;
  }
  return jtj;
}

}  // namespace

CircleFit FitCircleRobust(const std::vector<Eigen::Vector2d>& p, const std::vector<double>& weights,
                          double outlier_sigmas, double min_outlier_px) {
  CircleFit fit;
  std::vector<double> w = weights;
  if (w.empty()) w.assign(p.size(), 1.0);
  if (w.size() != p.size()) return fit;
  // Weights relative to their median, so that sigma below is in px for a typical point.
  const double w_med = MedianOf(w);
  if (!(w_med > 0)) return fit;
  for (double& x : w) x = std::max(x, 0.0) / w_med;
  std::vector<char> use(p.size(), 1);
  Eigen::Vector2d c;
  double r = 0;
  if (p.size() < 8 || !KasaFit(p, w, use, c, r)) return fit;
  Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();
  for (int round = 0; round < 12; ++round) {
    jtj = GeometricFit(p, w, use, c, r);
    std::vector<double> d(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) d[i] = ((p[i] - c).norm() - r) * std::sqrt(w[i]);
    const double med = MedianOf(d);
    std::vector<double> dev;
    dev.reserve(d.size());
    for (double x : d) dev.push_back(std::abs(x - med));
    const double sigma = 1.4826 * MedianOf(dev);
    std::vector<char> next(p.size());
    for (std::size_t i = 0; i < p.size(); ++i)
      next[i] = w[i] > 0 && std::abs(d[i]) <=
                                std::max(outlier_sigmas * sigma, min_outlier_px * std::sqrt(w[i]));
    if (next == use) break;
    if (std::count(next.begin(), next.end(), 1) < 8) break;
    use = next;
  }
  double ss = 0, ss_plain = 0;
  int n = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (use[i]) {
      const double e = (p[i] - c).norm() - r;
      ss += w[i] * e * e;
      ss_plain += e * e;
      ++n;
    }
  if (n < 8 || !(r > 0)) return fit;
  fit.ok = true;
  fit.c = c;
  fit.r = r;
  fit.n = n;
  fit.rejected = static_cast<int>(p.size()) - n;
  fit.rms = std::sqrt(ss_plain / n);
  // Each edge point comes from its own ray, spaced about 2 px apart along the edge, so their
  // errors are taken as independent: the covariance is s^2 (J^T W J)^-1.
  fit.cov = ss / (n - 3) * jtj.inverse();
  fit.inlier = use;
  return fit;
}

}  // namespace hoof::tracking
