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
/// The body is geometry.body's: the specimen with markers, without (kUnmarked), or the ball
/// (BuildBallTexture). Back-lit, the specimen is a dark silhouette (kSilhouetteRadiance).
SpecimenTexture BuildSpecimenTexture(const SpecimenGeometry& geometry, double m_per_px,
                                     int oversampling, std::uint64_t seed,
                                     Lighting lighting = Lighting::kFront);

/// The ball in W-aligned body axes (x right, y up; it is drawn without rotation), centre at the
/// origin, radius diameter / 2. Front-lit: a Lambertian sphere lit from the upper left and
/// front, kBallAmbient + kBallDiffuse max(0, n.l). Back-lit: a dark disc (kSilhouetteRadiance)
/// with the bright spot at its centre that a back-lit sphere shows: kBallSpotRadiance
/// exp(-r^2 / (2 (kBallSpotSigma R)^2)) added.
SpecimenTexture BuildBallTexture(const SpecimenGeometry& geometry, double m_per_px,
                                 int oversampling, Lighting lighting);

/// Radiance of the white dots and of the black patches (before lighting), for tests and docs.
inline constexpr float kDotRadiance = 0.88f;
inline constexpr float kPatchRadiance = 0.035f;
/// A body seen against the back light.
inline constexpr float kSilhouetteRadiance = 0.03f;
inline constexpr double kBallAmbient = 0.06, kBallDiffuse = 0.74;
inline constexpr double kBallSpotRadiance = 0.8, kBallSpotSigma = 0.1;

}  // namespace hoof::synth
