#pragma once
/// @file
/// Procedural textures of the everyday-footage room (docs/synthetic-trials.md, "Everyday
/// footage"): seeded value noise, painted walls, wooden planks and a ruler's ticks. Colours are
/// linear RGB in [0, 1]. Everything is a pure function of position and seed, so a clip's
/// background is the same on every machine.

#include <cstdint>

#include <Eigen/Core>

namespace hoof::synth {

/// Smooth value noise in [0, 1] on a unit lattice, seeded.
double ValueNoise(double x, double y, std::uint64_t seed);
/// Sum of `octaves` of ValueNoise, each twice the frequency and half the amplitude, in [0, 1].
double Fractal(double x, double y, int octaves, std::uint64_t seed);
/// A uniform number in [0, 1) from integers (a hash).
double Hash01(std::int64_t a, std::int64_t b, std::uint64_t seed);

/// The room's paints and woods, drawn from realistic palettes by the seed.
struct RoomPalette {
  Eigen::Vector3d wall_low{0.70, 0.68, 0.63}, wall_high{0.78, 0.77, 0.74};
  Eigen::Vector3d side_wall{0.66, 0.66, 0.64};
  Eigen::Vector3d wood{0.45, 0.30, 0.17};
  Eigen::Vector3d plain_floor{0.60, 0.59, 0.56};
  double plank_width_m = 0.14, plank_length_m = 1.2;
};
/// The palette for a seed.
RoomPalette DrawPalette(std::uint64_t seed);

/// Painted wall at (u, v) in its plane (m), between the low and high paint by height v.
Eigen::Vector3d WallPaint(const Eigen::Vector3d& low, const Eigen::Vector3d& high, double u,
                          double v, std::uint64_t seed);
/// Wooden planks running along z, at (x, z) on the floor (m): a tint per plank, grain, dark
/// seams between planks and at their staggered ends.
Eigen::Vector3d WoodPlanks(const RoomPalette& palette, double x, double z, std::uint64_t seed);
/// A yellow ruler along its length u (m from its zero end) and across it w in [0, 1]: black
/// ticks every 1 mm from the top edge, longer at 5 mm and 10 mm.
Eigen::Vector3d RulerFace(double u, double w);

}  // namespace hoof::synth
