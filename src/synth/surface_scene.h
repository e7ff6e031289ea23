#pragma once
/// @file
/// The static part of a frame: a dark studio backdrop and the impact surface seen edge-on,
/// its face textured as the material looks (steel: smooth, brushed, a specular edge highlight;
/// concrete: grainy aggregate; asphalt: dark, coarse stones in binder).

#include <cstdint>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "dynamics/parameters.h"

namespace hoof::synth {

/// The visible face of one surface block in its own coordinates at image scale: column u
/// along the surface, row v down from the top edge (row `top_row` is the top edge).
struct SurfaceTexture {
  dynamics::Surface surface = dynamics::Surface::kSteel;
  cv::Mat radiance;  ///< CV_32F, radiance in [0, 1] before lighting.
  int top_row = 16;  ///< Canvas row of the top edge of the block.
};

/// Draws the face of `surface` large enough for frames of `frame` size at `m_per_px`
/// (texture features have physical sizes), from `seed`.
SurfaceTexture BuildSurfaceTexture(dynamics::Surface surface, double m_per_px, cv::Size frame,
                                   std::uint64_t seed);

/// Where the surface is in the ideal image and which part of the block is seen.
struct SurfacePlacement {
  double angle_rad = 0.0;                ///< phi; the line descends toward +x for phi > 0.
  Eigen::Vector2d contact_px{0.0, 0.0};  ///< Image point of the first-touch contact point.
  double u_offset_px = 0.0;              ///< Shift along the block (another spot each trial).
};

/// Ideal radiance (CV_32F) of the static scene: the block below the surface line, with an
/// anti-aliased top edge, and the studio backdrop above it (backdrop pattern from `seed`).
cv::Mat RenderBackground(const SurfaceTexture& texture, const SurfacePlacement& placement,
                         cv::Size frame, std::uint64_t seed);

/// Radiance of the back light seen around the body, and of the block's silhouette.
inline constexpr float kBacklitBackgroundRadiance = 0.92f;
inline constexpr float kBacklitBlockRadiance = 0.04f;

/// Ideal radiance of a back-lit scene: the bright back light above the surface line and the
/// block as a dark silhouette below it (the line anti-aliased as in RenderBackground).
cv::Mat RenderBacklitBackground(const SurfacePlacement& placement, cv::Size frame);

}  // namespace hoof::synth
