#include "synth/room_texture.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace hoof::synth {
namespace {

std::uint64_t Mix(std::uint64_t z) {  // SplitMix64's finaliser
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

double Smooth(double t) { return t * t * (3 - 2 * t); }

Eigen::Vector3d Lerp(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double t) {
  return a + (b - a) * t;
}

/// How dark a seam of half-width `half` is at distance d from it: 1 on the seam, 0 beyond.
double Seam(double d, double half) { return std::clamp(1.0 - std::abs(d) / half, 0.0, 1.0); }

}  // namespace

double Hash01(std::int64_t a, std::int64_t b, std::uint64_t seed) {
  const std::uint64_t h =
      Mix(Mix(seed ^ static_cast<std::uint64_t>(a)) + static_cast<std::uint64_t>(b));
  return static_cast<double>(h >> 11) * (1.0 / 9007199254740992.0);
}

double ValueNoise(double x, double y, std::uint64_t seed) {
  const double fx = std::floor(x), fy = std::floor(y);
  const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy);
  const double tx = Smooth(x - fx), ty = Smooth(y - fy);
  const double a = Hash01(ix, iy, seed), b = Hash01(ix + 1, iy, seed);
  const double c = Hash01(ix, iy + 1, seed), d = Hash01(ix + 1, iy + 1, seed);
  return (a + (b - a) * tx) * (1 - ty) + (c + (d - c) * tx) * ty;
}

double Fractal(double x, double y, int octaves, std::uint64_t seed) {
  double sum = 0, weight = 0, amplitude = 1;
  for (int o = 0; o < octaves; ++o) {
    sum += amplitude * ValueNoise(x, y, seed + static_cast<std::uint64_t>(o) * 7919);
    weight += amplitude;
    amplitude /= 2;
    x *= 2.03;
    y *= 2.03;
  }
  return sum / weight;
}

RoomPalette DrawPalette(std::uint64_t seed) {
  // Paints (off-white, beige, light grey, pale blue, pale green) and woods (oak, birch, walnut,
  // grey laminate), linear RGB.
  static const std::array<Eigen::Vector3d, 5> paints = {
      Eigen::Vector3d{0.74, 0.72, 0.66}, Eigen::Vector3d{0.70, 0.62, 0.50},
      Eigen::Vector3d{0.62, 0.62, 0.61}, Eigen::Vector3d{0.55, 0.62, 0.68},
      Eigen::Vector3d{0.58, 0.65, 0.55}};
  static const std::array<Eigen::Vector3d, 4> woods = {
      Eigen::Vector3d{0.45, 0.30, 0.17}, Eigen::Vector3d{0.62, 0.50, 0.36},
      Eigen::Vector3d{0.24, 0.14, 0.08}, Eigen::Vector3d{0.42, 0.40, 0.37}};
  RoomPalette p;
  const Eigen::Vector3d paint = paints[static_cast<std::size_t>(Hash01(1, 2, seed) * 5)];
  p.wall_low = paint * (0.92 + 0.05 * Hash01(3, 4, seed));
  p.wall_high = paint * (1.02 + 0.06 * Hash01(5, 6, seed));
  p.side_wall = paint * (0.97 + 0.05 * Hash01(7, 8, seed));
  p.wood = woods[static_cast<std::size_t>(Hash01(9, 10, seed) * 4)];
  p.plain_floor = Eigen::Vector3d::Constant(0.50 + 0.15 * Hash01(11, 12, seed));
  p.plank_width_m = 0.10 + 0.08 * Hash01(13, 14, seed);
  return p;
}

Eigen::Vector3d WallPaint(const Eigen::Vector3d& low, const Eigen::Vector3d& high, double u,
                          double v, std::uint64_t seed) {
  const Eigen::Vector3d base = Lerp(low, high, std::clamp(v / 2.0, 0.0, 1.0));
  // Uneven paint and rolling marks: a few per cent, at scales of 10 cm and 1 cm.
  const double blotch = Fractal(u * 6, v * 6, 3, seed) - 0.5;
  const double fine = ValueNoise(u * 120, v * 120, seed + 3) - 0.5;
  return base * (1 + 0.05 * blotch + 0.012 * fine);
}

Eigen::Vector3d WoodPlanks(const RoomPalette& p, double x, double z, std::uint64_t seed) {
  const double across = x / p.plank_width_m;
  const double plank = std::floor(across);
  const auto i = static_cast<std::int64_t>(plank);
  const double offset = Hash01(i, 77, seed) * p.plank_length_m;
  const double along = (z + offset) / p.plank_length_m;
  const auto j = static_cast<std::int64_t>(std::floor(along));
  const double tint = 0.85 + 0.3 * Hash01(i, j, seed);
  // Grain: long streaks along the plank, finer rings, and a little per-board hue.
  const double grain = Fractal(x * 90, z * 4, 4, seed + static_cast<std::uint64_t>(i) * 131);
  const double rings = std::sin((x * 260 + 8 * Fractal(x * 10, z * 2, 2, seed + 5)) * 1.0);
  Eigen::Vector3d c = p.wood * tint * (0.82 + 0.3 * grain + 0.04 * rings);
  c.x() *= 1 + 0.06 * (Hash01(i, j + 1000, seed) - 0.5);
  const double seam_across = Seam((across - plank) * p.plank_width_m, 0.0012) +
                             Seam((plank + 1 - across) * p.plank_width_m, 0.0012);
  const double seam_end = Seam((along - std::floor(along)) * p.plank_length_m, 0.0012);
  return c * (1 - 0.6 * std::min(1.0, seam_across + seam_end));
}

Eigen::Vector3d RulerFace(double u, double w) {
  const Eigen::Vector3d yellow{0.80, 0.60, 0.06}, black{0.02, 0.02, 0.02};
  const double mm = u * 1000;
  const double k = std::round(mm);
  const auto tick = static_cast<long>(k);
  const double len = tick % 10 == 0 ? 0.55 : (tick % 5 == 0 ? 0.38 : 0.22);
  const bool on_tick = std::abs(mm - k) < 0.12 && w < len && mm >= -0.2;
  const bool digit_band = tick % 10 == 0 && w > 0.62 && w < 0.85 && std::abs(mm - k - 1.2) < 0.9;
  return on_tick || digit_band ? black : yellow;
}

}  // namespace hoof::synth
