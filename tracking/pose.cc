#include "tracking/pose.h"

#include <cmath>
#include <stdexcept>

#include <Eigen/SVD>
#include <opencv2/calib3d.hpp>

namespace hoof::tracking {

RigidFit FitRigid2D(const std::vector<Eigen::Vector2d>& model,
                    const std::vector<Eigen::Vector2d>& measured, bool allow_scale) {
  if (model.size() != measured.size() || model.size() < 2)
    throw std::invalid_argument("a rigid fit needs two or more matched point pairs");
  const double n = static_cast<double>(model.size());
  Eigen::Vector2d mu_p = Eigen::Vector2d::Zero(), mu_q = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < model.size(); ++i) {
    mu_p += model[i];
    mu_q += measured[i];
  }
  mu_p /= n;
  mu_q /= n;
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  double var_p = 0;
  for (std::size_t i = 0; i < model.size(); ++i) {
    cov += (measured[i] - mu_q) * (model[i] - mu_p).transpose();
    var_p += (model[i] - mu_p).squaredNorm();
  }
  // In 2-D the optimal rotation angle is atan2 of the antisymmetric over the symmetric part.
  const double angle = std::atan2(cov(1, 0) - cov(0, 1), cov(0, 0) + cov(1, 1));
  RigidFit fit;
  fit.rotation << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  if (allow_scale && var_p > 0) fit.scale = (fit.rotation.transpose() * cov).trace() / var_p;
  fit.translation = mu_q - fit.scale * fit.rotation * mu_p;
  double ss = 0;
  for (std::size_t i = 0; i < model.size(); ++i)
    ss += (fit.scale * fit.rotation * model[i] + fit.translation - measured[i]).squaredNorm();
  fit.rms_residual = std::sqrt(ss / n);
  return fit;
}

Eigen::Vector2d ImageToWorld::Undistort(const Eigen::Vector2d& p_I) const {
  if (!distortion || !camera_matrix) return p_I;
  const cv::Mat K(3, 3, CV_64F, const_cast<double*>(camera_matrix->data()));
  const cv::Mat D(1, 5, CV_64F, const_cast<double*>(distortion->data()));
  std::vector<cv::Point2d> in{{p_I.x(), p_I.y()}}, out;
  cv::undistortPoints(in, out, K, D, cv::noArray(), K);
  return {out[0].x, out[0].y};
}

double ImageToWorld::RotationToWorld() const {
  // Gravity in "image with y up" coordinates is (gx, -gy); W wants it along -y.
  const double g_angle = std::atan2(-gravity_I.y(), gravity_I.x());
  return -M_PI / 2 - g_angle;
}

Eigen::Vector2d ImageToWorld::ToWorld(const Eigen::Vector2d& p_I) const {
  const Eigen::Vector2d u = Undistort(p_I);
  const Eigen::Vector2d up{u.x(), -u.y()};  // y up
  const double a = RotationToWorld();
  const Eigen::Matrix2d R{{std::cos(a), -std::sin(a)}, {std::sin(a), std::cos(a)}};
  return m_per_px * (R * up);
}

Eigen::Vector2d ImageToWorld::ToImage(const Eigen::Vector2d& p_W) const {
  const double a = -RotationToWorld();
  const Eigen::Matrix2d R{{std::cos(a), -std::sin(a)}, {std::sin(a), std::cos(a)}};
  const Eigen::Vector2d up = R * (p_W / m_per_px);
  const Eigen::Vector2d u{up.x(), -up.y()};  // undistorted image point
  if (!distortion || !camera_matrix) return u;
  const auto& k = *camera_matrix;
  // Back to normalized camera coordinates, then through OpenCV's distortion model.
  std::vector<cv::Point3d> obj{{(u.x() - k[2]) / k[0], (u.y() - k[5]) / k[4], 1.0}};
  std::vector<cv::Point2d> img;
  const cv::Mat K(3, 3, CV_64F, const_cast<double*>(k.data()));
  const cv::Mat D(1, 5, CV_64F, const_cast<double*>(distortion->data()));
  cv::projectPoints(obj, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, D, img);
  return {img[0].x, img[0].y};
}

BodyPose FitPose(const std::vector<MarkerObservation>& observations,
                 const std::vector<Eigen::Vector2d>& layout_B_m, const ImageToWorld& camera) {
  BodyPose pose;
  std::vector<Eigen::Vector2d> model, measured;
  for (std::size_t i = 0; i < observations.size() && i < layout_B_m.size(); ++i) {
    if (!observations[i].found) continue;
    model.push_back(layout_B_m[i]);
    measured.push_back(camera.ToWorld(observations[i].p_I));
  }
  if (model.size() < 2) return pose;
  const RigidFit fit = FitRigid2D(model, measured, false);
  pose.valid = true;
  pose.p_WE = fit.translation;  // the image of the body origin E
  pose.theta_W_rad = std::atan2(fit.rotation(1, 0), fit.rotation(0, 0));
  pose.rms_residual_m = fit.rms_residual;
  pose.markers_used = static_cast<int>(model.size());
  if (observations.size() >= 2 && observations[0].found && observations[1].found)
    pose.marker_distance_m =
        (camera.ToWorld(observations[0].p_I) - camera.ToWorld(observations[1].p_I)).norm();
  return pose;
}

}  // namespace hoof::tracking
