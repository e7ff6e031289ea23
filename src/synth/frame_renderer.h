#pragma once
/// @file
/// Draws the frames of a planned trial: the specimen texture warped to each exposure
/// sub-sample pose and averaged (motion blur), composited over the static scene, lit, seen
/// through the lens (distortion, defocus) and recorded by the sensor (noise, quantization).

#include <cstdint>

#include <opencv2/core.hpp>

#include "synth/camera_model.h"
#include "synth/renderer.h"

namespace hoof::synth {

/// Per-trial drawing state; Render() is const and may be called for frames in any order.
class FrameRenderer {
 public:
  FrameRenderer(const TrialTruth& truth, const SpecimenGeometry& geometry,
                const RenderOptions& options, const SceneAssets& assets);

  /// Ideal radiance of written frame j (CV_32F): scene and specimen, lit, before the lens.
  cv::Mat Ideal(int j) const;
  /// The recorded frame j (CV_8U or CV_16U).
  cv::Mat Render(int j) const;

  const LensModel& lens() const { return lens_; }

 private:
  /// Adds the specimen's premultiplied radiance and coverage for `pose` into `acc` (roi).
  void AccumulatePose(const BodyPose& pose, const cv::Rect& roi, cv::Mat& acc) const;
  /// Bounding box (ideal image px, clipped to the frame) of the texture under `pose`.
  cv::Rect PoseBounds(const BodyPose& pose) const;
  /// Composites the specimen of frame j into `ideal` (a copy of the lit background); returns
  /// the rectangle that changed (empty when the specimen is out of view).
  cv::Rect Composite(int j, cv::Mat& ideal) const;
  /// The pose the texture is drawn at: the ball's without rotation.
  BodyPose Drawn(const BodyPose& pose) const;
  /// Texture -> ideal image affine map for the face at z_B.
  cv::Matx23d TextureToImage(const BodyPose& pose, double z_B_m) const;

  const TrialTruth& truth_;
  const SpecimenGeometry& geometry_;
  const RenderOptions& options_;
  const SpecimenTexture& texture_;
  ViewGeometry view_;
  LensModel lens_;
  cv::Mat background_lit_;  ///< Static scene times illumination (CV_32F).
  cv::Mat illumination_;
  cv::Mat map_x_, map_y_;        ///< Recorded pixel -> ideal image point (when distorting).
  cv::Mat background_recorded_;  ///< background_lit_ through the lens (when distorting).
  bool out_of_plane_ = false;
  bool ball_ = false;
};

/// Bilinear resampling of a CV_32F image at the points of two CV_32F maps, in double
/// precision weights (cv::remap quantizes positions to 1/32 px), replicating the border.
/// Only the pixels of `dst_rect` in `dst` (already allocated, CV_32F, the maps' size) are set.
void RemapBilinear(const cv::Mat& src, const cv::Mat& map_x, const cv::Mat& map_y, cv::Mat& dst);
void RemapBilinear(const cv::Mat& src, const cv::Mat& map_x, const cv::Mat& map_y,
                   const cv::Rect& dst_rect, cv::Mat& dst);

}  // namespace hoof::synth
