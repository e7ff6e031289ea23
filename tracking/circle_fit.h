#pragma once
/// @file
/// A circle fitted to weighted edge points with outliers rejected (docs/tracking.md, "Ball:
/// edge points and a robust circle"). Written with Eigen: OpenCV's fitEllipse and
/// minEnclosingCircle neither weight the points nor reject outliers.

#include <vector>

#include <Eigen/Core>

namespace hoof::tracking {

/// A circle fitted to edge points, with outliers rejected.
struct CircleFit {
  bool ok = false;
  Eigen::Vector2d c{0, 0};
  double r = 0;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();  ///< of (cx, cy, r), px^2
  int n = 0, rejected = 0;
  double rms = 0;            ///< unweighted rms distance of the inliers from the circle (px)
  std::vector<char> inlier;  ///< per point
};

/// Circle through `points`, point i weighted by `weights[i]` (> 0; its variance is taken as
/// proportional to 1 / weight; all 1 when `weights` is empty): algebraic (Kasa) start, geometric
/// fit (Gauss-Newton on the weighted distances), then points whose distance from the circle
/// exceeds max(outlier_sigmas sigma / sqrt(w_i / median w), min_outlier_px) dropped, sigma from
/// the median absolute deviation of all the points' weighted distances (so up to half of them
/// may be wrong), until the set of inliers stops changing. The covariance is s^2 (J^T W J)^-1
/// with s^2 the inliers' weighted residual variance. `ok` is false with fewer than 8 inliers.
CircleFit FitCircleRobust(const std::vector<Eigen::Vector2d>& points,
                          const std::vector<double>& weights, double outlier_sigmas,
                          double min_outlier_px);

}  // namespace hoof::tracking
