#include "synth/frame_renderer.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "core/frames.h"

namespace hoof::synth {
namespace {

/// Radiance of the specimen's side walls relative to its face, seen when it turns out of plane.
constexpr float kSideWallShade = 0.3f;

}  // namespace

FrameRenderer::FrameRenderer(const TrialTruth& truth, const SpecimenGeometry& geometry,
                             const RenderOptions& options, const SceneAssets& assets)
    : truth_(truth),
      geometry_(geometry),
      options_(options),
      texture_(assets.specimen),
      lens_(options.camera, options.width_px, options.height_px) {
  view_.m_per_px = options.m_per_px;
  view_.contact_px = truth.contact_px;
  view_.d_EC_m = geometry.Simulated().d_EC_m;
  const cv::Size frame(options.width_px, options.height_px);
  SurfacePlacement placement;
  placement.angle_rad = core::DegToRad(truth.spec.angle_deg);
  placement.contact_px = truth.contact_px;
  placement.u_offset_px = truth.surface_u_offset_px;
  const cv::Mat background = options.lighting == Lighting::kBacklit
                                 ? RenderBacklitBackground(placement, frame)
                                 : RenderBackground(assets.Surface(truth.spec.surface), placement,
                                                    frame, MixSeed(truth.spec.seed, 77));
  illumination_ = IlluminationField(options.camera, frame.width, frame.height);
  background_lit_ = background.mul(illumination_);
  if (lens_.distorts()) {
    lens_.BuildRemapMaps(frame.width, frame.height, map_x_, map_y_);
    RemapBilinear(background_lit_, map_x_, map_y_, background_recorded_);
  }
  ball_ = geometry.body == Body::kBall;
  out_of_plane_ = truth.spec.hidden.out_of_plane.Any() && !ball_;
}

BodyPose FrameRenderer::Drawn(const BodyPose& pose) const {
  if (!ball_) return pose;
  // A sphere looks the same in every orientation: its shading stays with the lights.
  BodyPose p = pose;
  p.theta_W_rad = p.tilt_rad = p.roll_rad = 0.0;
  return p;
}

cv::Matx23d FrameRenderer::TextureToImage(const BodyPose& pose, double z_B_m) const {
  const Eigen::Matrix<double, 2, 3> body = BodyToImage(pose, z_B_m, view_);
  const double h = texture_.texel_m;
  const Eigen::Vector2d o = texture_.origin_B_m;
  return cv::Matx23d(body(0, 0) * h, body(0, 1) * h,
                     body(0, 0) * o.x() + body(0, 1) * o.y() + body(0, 2), body(1, 0) * h,
                     body(1, 1) * h, body(1, 0) * o.x() + body(1, 1) * o.y() + body(1, 2));
}

cv::Rect FrameRenderer::PoseBounds(const BodyPose& pose) const {
  const cv::Matx23d m = TextureToImage(pose, geometry_.thickness_m / 2);
  const double w = texture_.premultiplied.cols - 1, h = texture_.premultiplied.rows - 1;
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (const cv::Vec3d& corner :
       {cv::Vec3d(0, 0, 1), cv::Vec3d(w, 0, 1), cv::Vec3d(0, h, 1), cv::Vec3d(w, h, 1)}) {
    const cv::Vec2d p = m * corner;
    x0 = std::min(x0, p[0]);
    x1 = std::max(x1, p[0]);
    y0 = std::min(y0, p[1]);
    y1 = std::max(y1, p[1]);
  }
  // Out of plane, the back face is offset by up to the thickness.
  const double pad = 2 + (out_of_plane_ ? geometry_.thickness_m / options_.m_per_px : 0.0);
  const cv::Rect box(
      cv::Point(static_cast<int>(std::floor(x0 - pad)), static_cast<int>(std::floor(y0 - pad))),
      cv::Point(static_cast<int>(std::ceil(x1 + pad)) + 1,
                static_cast<int>(std::ceil(y1 + pad)) + 1));
  return box & cv::Rect(0, 0, options_.width_px, options_.height_px);
}

void FrameRenderer::AccumulatePose(const BodyPose& pose, const cv::Rect& roi, cv::Mat& acc) const {
  const auto warp = [&](double z_B_m, cv::Mat& out) {
    cv::Matx23d m = TextureToImage(pose, z_B_m);
    m(0, 2) -= roi.x;
    m(1, 2) -= roi.y;
    cv::Matx23d inv;
    cv::invertAffineTransform(m, inv);
    cv::warpAffine(texture_.premultiplied, out, inv, roi.size(),
                   cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_CONSTANT, cv::Scalar());
  };
  cv::Mat front;
  warp(geometry_.thickness_m / 2, front);
  if (out_of_plane_) {
    // Side walls: the back face outline, dark, under the front face.
    cv::Mat back;
    warp(-geometry_.thickness_m / 2, back);
    for (int r = 0; r < roi.height; ++r) {
      auto* f = front.ptr<cv::Vec2f>(r);
      const auto* b = back.ptr<cv::Vec2f>(r);
      for (int c = 0; c < roi.width; ++c) {
        const float keep = 1 - f[c][1];
        f[c][0] += keep * b[c][0] * kSideWallShade;
        f[c][1] += keep * b[c][1];
      }
    }
  }
  acc += front;
}

cv::Rect FrameRenderer::Composite(int j, cv::Mat& ideal) const {
  const auto& poses = truth_.exposure_poses.at(j);
  cv::Rect roi;
  for (const BodyPose& p : poses) roi |= PoseBounds(Drawn(p));
  if (roi.area() == 0) return roi;
  cv::Mat acc(roi.size(), CV_32FC2, cv::Scalar::all(0));
  for (const BodyPose& p : poses) AccumulatePose(Drawn(p), roi, acc);
  const float inv_n = 1.0f / static_cast<float>(poses.size());
  for (int r = 0; r < roi.height; ++r) {
    const auto* a = acc.ptr<cv::Vec2f>(r);
    float* out = ideal.ptr<float>(r + roi.y) + roi.x;
    const float* light = illumination_.ptr<float>(r + roi.y) + roi.x;
    for (int c = 0; c < roi.width; ++c) {
      const float alpha = a[c][1] * inv_n, radiance = a[c][0] * inv_n;
      out[c] = out[c] * (1 - alpha) + radiance * light[c];
    }
  }
  return roi;
}

cv::Mat FrameRenderer::Ideal(int j) const {
  cv::Mat ideal = background_lit_.clone();
  Composite(j, ideal);
  return ideal;
}

cv::Mat FrameRenderer::Render(int j) const {
  cv::Mat image = background_lit_.clone();
  const cv::Rect roi = Composite(j, image);
  if (lens_.distorts()) {
    // Only the recorded pixels that see the changed rectangle need resampling; the rest is
    // the background through the lens, computed once.
    cv::Mat recorded = background_recorded_.clone();
    if (roi.area() > 0) {
      double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
      for (const cv::Point2d corner : {cv::Point2d(roi.x, roi.y), cv::Point2d(roi.br().x, roi.y),
                                       cv::Point2d(roi.x, roi.br().y), cv::Point2d(roi.br())}) {
        const Eigen::Vector2d d = lens_.Distort({corner.x, corner.y});
        x0 = std::min(x0, d.x());
        x1 = std::max(x1, d.x());
        y0 = std::min(y0, d.y());
        y1 = std::max(y1, d.y());
      }
      const cv::Rect dst(
          cv::Point(static_cast<int>(std::floor(x0)) - 3, static_cast<int>(std::floor(y0)) - 3),
          cv::Point(static_cast<int>(std::ceil(x1)) + 4, static_cast<int>(std::ceil(y1)) + 4));
      RemapBilinear(image, map_x_, map_y_, dst & cv::Rect(0, 0, image.cols, image.rows), recorded);
    }
    image = recorded;
  }
  const CameraEffects& cam = options_.camera;
  if (cam.defocus)
    cv::GaussianBlur(image, image, cv::Size(0, 0), cam.defocus_sigma_px, cam.defocus_sigma_px,
                     cv::BORDER_REPLICATE);
  if (cam.flicker_hz > 0) image *= truth_.frames.at(j).light_factor;  // every light flickers
  return Sensor(image, cam, options_.bit_depth,
                MixSeed(truth_.spec.seed, 1000 + static_cast<std::uint64_t>(j)));
}

void RemapBilinear(const cv::Mat& src, const cv::Mat& map_x, const cv::Mat& map_y, cv::Mat& dst) {
  dst.create(map_x.size(), CV_32F);
  RemapBilinear(src, map_x, map_y, cv::Rect(0, 0, map_x.cols, map_x.rows), dst);
}

void RemapBilinear(const cv::Mat& src, const cv::Mat& map_x, const cv::Mat& map_y,
                   const cv::Rect& dst_rect, cv::Mat& dst) {
  CV_Assert(src.type() == CV_32F && map_x.type() == CV_32F && map_y.type() == CV_32F);
  CV_Assert(dst.type() == CV_32F && dst.size() == map_x.size());
  const int w = src.cols, h = src.rows;
  for (int r = dst_rect.y; r < dst_rect.br().y; ++r) {
    const float* mx = map_x.ptr<float>(r);
    const float* my = map_y.ptr<float>(r);
    float* out = dst.ptr<float>(r);
    for (int c = dst_rect.x; c < dst_rect.br().x; ++c) {
      const double x = std::clamp(static_cast<double>(mx[c]), 0.0, w - 1.0);
      const double y = std::clamp(static_cast<double>(my[c]), 0.0, h - 1.0);
      const int x0 = std::min(static_cast<int>(x), w - 2),
                y0 = std::min(static_cast<int>(y), h - 2);
      const double fx = x - x0, fy = y - y0;
      const float* r0 = src.ptr<float>(y0) + x0;
      const float* r1 = src.ptr<float>(y0 + 1) + x0;
      out[c] = static_cast<float>((1 - fy) * ((1 - fx) * r0[0] + fx * r0[1]) +
                                  fy * ((1 - fx) * r1[0] + fx * r1[1]));
    }
  }
}

}  // namespace hoof::synth
