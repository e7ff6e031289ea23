#pragma once
/// @file
/// The specimen's face as a texture in the body frame B: hoof-wall grey with keratin tubules
/// (fine streaks along x_B), darker edges, and the markers (white dots on black patches).
/// Stored premultiplied with its coverage and prefiltered with a one-pixel box, so that
/// bilinear warping to the image gives area coverage: the dots land with sub-pixel accuracy.

#include <cstdint>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "synth/options.h"

namespace hoof::synth {

/// Texture of the face z_B = +thickness/2. Texel (col i, row j) has its centre at
/// x_B = origin_B_m.x + i texel_m, y_B = origin_B_m.y + j texel_m.
struct SpecimenTexture {
  /// CV_32FC2: channel 0 radiance times coverage, channel 1 coverage (alpha), both in [0, 1].
  cv::Mat premultiplied;
  Eigen::Vector2d origin_B_m{0.0, 0.0};  ///< Body position of texel (0, 0)'s centre (m).
  double texel_m = 0.0;                  ///< Texel size (m).
};

/// Draws the texture with `oversampling` texels per image pixel of size m_per_px. The
/// tubule pattern comes from `seed`; markers and outline are exact (4 x 4 samples per texel).
SpecimenTexture BuildSpecimenTexture(const SpecimenGeometry& geometry, double m_per_px,
                                     int oversampling, std::uint64_t seed);

/// Radiance of the white dots and of the black patches (before lighting), for tests and docs.
inline constexpr float kDotRadiance = 0.88f;
inline constexpr float kPatchRadiance = 0.035f;

}  // namespace hoof::synth
