// The everyday room (synth/room_scene.h): the ball's soft shadow against a Monte Carlo count of
// the rays from a floor point to the light that the ball blocks, and the light's fall-off.
#include "synth/room_scene.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

namespace hoof::synth {
namespace {

/// The share of the light sphere's solid angle, seen from p, whose rays meet the ball: rays
/// drawn uniformly over the cone that the light's sphere subtends.
double HiddenByRays(const Eigen::Vector3d& p, const Eigen::Vector3d& light, double R,
                    const Eigen::Vector3d& c, double r, int n, cv::RNG& rng) {
  const Eigen::Vector3d axis = (light - p).normalized();
  const double cos_max = std::sqrt(1 - R * R / (light - p).squaredNorm());
  const Eigen::Vector3d u = axis.unitOrthogonal(), v = axis.cross(u);
  int hidden = 0;
  for (int i = 0; i < n; ++i) {
    const double cos_t = 1 - rng.uniform(0.0, 1.0) * (1 - cos_max);  // uniform in solid angle
    const double sin_t = std::sqrt(1 - cos_t * cos_t), phi = rng.uniform(0.0, 2 * std::numbers::pi);
    const Eigen::Vector3d d = cos_t * axis + sin_t * (std::cos(phi) * u + std::sin(phi) * v);
    const double b = d.dot(c - p);
    if (b > 0 && b * b - ((c - p).squaredNorm() - r * r) >= 0) ++hidden;
  }
  return static_cast<double>(hidden) / n;
}

TEST(RoomSceneTest, TheShadowIsTheShareOfTheLightTheBallHides) {
  const Eigen::Vector3d light{0.3, 2.2, 0.5};
  const double R = 0.15, r = 0.025;
  cv::RNG rng(77);
  const Eigen::Vector3d c{0.0, 0.3, 0.0};
  // The point under the ball on the line from the light, and points across the penumbra.
  const Eigen::Vector3d below = light + (c - light) * (light.y() / (light.y() - c.y()));
  for (double dx : {0.0, 0.01, 0.02, 0.03, 0.045, 0.2}) {
    const Eigen::Vector3d p = below + Eigen::Vector3d(dx, 0, 0);
    const double f = ShadowFraction(p, light, R, c, r);
    EXPECT_NEAR(f, HiddenByRays(p, light, R, c, r, 40000, rng), 0.01) << dx;
    EXPECT_GE(f, 0.0);
    EXPECT_LE(f, 1.0);
  }
  // The ball's disc seen from below (0.025 / 0.3) is larger than the light's (0.15 / 1.9):
  // full shadow there; and none far off, or from above the ball.
  EXPECT_NEAR(ShadowFraction(below, light, R, {below.x(), 0.05, below.z()}, r), 1.0, 1e-12);
  EXPECT_EQ(ShadowFraction(below + Eigen::Vector3d(0.5, 0, 0), light, R, c, r), 0.0);
  EXPECT_EQ(ShadowFraction({0, 1.0, 0}, light, R, c, r), 0.0);
  // A point light: a hard shadow.
  EXPECT_EQ(ShadowFraction(below, light, 0.0, c, r), 1.0);
}

TEST(RoomSceneTest, DirectLightFallsWithDistanceAndAngle) {
  RoomOptions room;
  const Eigen::Vector3d ref{0, 0, 0};
  const RoomLight light(room, ref);
  const Eigen::Vector3d up = Eigen::Vector3d::UnitY();
  // 1 - ambient under the reference point (times brightness 1).
  EXPECT_NEAR(light.Direct(ref, up), 1 - room.ambient, 1e-12);
  // Inverse square along the ray from the light, and Lambert's cosine.
  const Eigen::Vector3d L = room.light_p_W_m;
  const Eigen::Vector3d half = L + (ref - L) * 0.5;
  const Eigen::Vector3d n = (L - ref).normalized();
  EXPECT_NEAR(light.Direct(half, n) / light.Direct(ref, n), 4.0, 1e-9);
  EXPECT_EQ(light.Direct(ref, -up), 0.0);
  EXPECT_NEAR(light.Ambient(0.5), 0.5 * room.ambient, 1e-15);
}

}  // namespace
}  // namespace hoof::synth
