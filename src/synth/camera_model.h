#pragma once
/// @file
/// What the lens and sensor do to the ideal image: OpenCV's distortion model (k1 k2 p1 p2 k3),
/// light fall-off, defocus and shot/read noise with quantization. The renderer draws an ideal
/// (undistorted, noise-free) radiance image in [0, 1] and hands it here.

#include <array>
#include <cstdint>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "synth/options.h"

namespace hoof::synth {

/// Pinhole camera matrix and distortion of one trial, in OpenCV's convention (pixel centres at
/// integer coordinates, the origin at the centre of the top-left pixel).
class LensModel {
 public:
  /// Distortion from `camera` when camera.distortion is on, else none, for a frame of
  /// width x height pixels (the principal point is the image centre plus the offset).
  LensModel(const CameraEffects& camera, int width_px, int height_px);

  bool distorts() const { return distorts_; }
  double focal_px() const { return focal_px_; }
  const Eigen::Vector2d& principal_point_px() const { return c_px_; }
  /// k1 k2 p1 p2 k3.
  std::array<double, 5> coefficients() const { return {k1_, k2_, p1_, p2_, k3_}; }

  /// Where an ideal (undistorted) image point appears in the recorded image (px).
  Eigen::Vector2d Distort(const Eigen::Vector2d& u_px) const;
  /// Inverse of Distort by fixed-point iteration (as OpenCV's undistortPoints), to 1e-9 px.
  Eigen::Vector2d Undistort(const Eigen::Vector2d& d_px) const;
  /// Maps for cv::remap: for each recorded pixel, the ideal image point it sees (CV_32FC1).
  void BuildRemapMaps(int width_px, int height_px, cv::Mat& map_x, cv::Mat& map_y) const;

 private:
  bool distorts_ = false;
  double focal_px_ = 1.0;
  Eigen::Vector2d c_px_{0.0, 0.0};
  double k1_ = 0, k2_ = 0, p1_ = 0, p2_ = 0, k3_ = 0;
};

/// Illumination times lens fall-off over the frame (CV_32F, about 1): vignetting
/// 1 - v (r / r_corner)^2 about the centre, and a linear ramp of peak-to-peak g that is
/// brightest at the top left, where the lights are.
cv::Mat IlluminationField(const CameraEffects& camera, int width_px, int height_px);

/// Turns radiance (CV_32F, 1 = full scale) into recorded counts: electrons = radiance *
/// full_well, Gaussian noise of variance electrons + read^2 (Poisson-like), black level,
/// rounding and clipping to 8, 12 or 16 bits (12 in CV_16U, 0..4095). The normal deviates come from
/// a 65536-entry quantile table indexed by a SplitMix64 stream seeded with `noise_seed` (tails cut
/// at 4.3 s.d.).
cv::Mat Sensor(const cv::Mat& radiance, const CameraEffects& camera, int bit_depth,
               std::uint64_t noise_seed);

}  // namespace hoof::synth
