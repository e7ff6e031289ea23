// The everyday camera (synth/pinhole_camera.h): the image of a sphere against the closed form on
// the axis and, off it, against the centroid of the pixels whose rays hit the sphere (a ray test
// that does not use the conic); the directions of tilt, roll and pan.
#include "synth/pinhole_camera.h"

#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/LU>

#include "core/frames.h"

namespace hoof::synth {
namespace {

FootageCameraOptions Level() {
  FootageCameraOptions o;
  o.width_px = 640;
  o.height_px = 480;
  o.focal_px = 500;
  o.p_W_m = {0, 0.5, 2.0};
  o.tilt_deg = o.roll_deg = o.pan_deg = 0;
  return o;
}

/// Centroid of the sub-pixel points (step 1/8 px) whose rays hit the sphere, found by
/// intersecting each ray with the sphere.
Eigen::Vector2d RayCentroid(const PinholeCamera& cam, const Eigen::Vector3d& c_W, double r,
                            double& area) {
  const Eigen::Vector3d c = cam.ToCamera(c_W);
  const Eigen::Vector2d guess = cam.Project(c_W);
  const double reach = 3 * cam.focal_px() * r / c.z();
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  double n = 0;
  const double step = 1.0 / 8;
  for (double y = guess.y() - reach; y < guess.y() + reach; y += step)
    for (double x = guess.x() - reach; x < guess.x() + reach; x += step) {
      const Eigen::Vector3d d = cam.RayC(x, y).normalized();
      const double b = d.dot(c);
      if (b * b - (c.squaredNorm() - r * r) >= 0) {  // the ray meets the sphere
        sum += Eigen::Vector2d(x, y);
        n += 1;
      }
    }
  area = n * step * step;
  return sum / n;
}

TEST(PinholeCameraTest, ASphereOnTheAxisIsACircleOfTheClosedFormRadius) {
  const PinholeCamera cam(Level());
  const double r = 0.05, Z = 1.5;
  const SphereImage s = cam.ImageOfSphere({0, 0.5, 2.0 - Z}, r);
  ASSERT_TRUE(s.valid);
  EXPECT_NEAR(s.center_px.x(), 319.5, 1e-9);
  EXPECT_NEAR(s.center_px.y(), 239.5, 1e-9);
  // The tangent cone's half-angle is asin(r / Z): radius f tan(asin(r / Z)).
  const double expected = 500 * r / std::sqrt(Z * Z - r * r);
  EXPECT_NEAR(s.semi_major_px, expected, 1e-9);
  EXPECT_NEAR(s.semi_minor_px, expected, 1e-9);
  EXPECT_NEAR(s.radius_px, expected, 1e-9);
  EXPECT_NEAR(cam.MetresPerPixel({0, 0.5, 2.0 - Z}), Z / 500, 1e-15);
}

TEST(PinholeCameraTest, OffTheAxisTheEllipseCentreIsTheImagesCentroidNotTheProjection) {
  FootageCameraOptions o = Level();
  o.tilt_deg = 12;
  o.roll_deg = 7;
  const PinholeCamera cam(o);
  const double r = 0.12;
  for (const Eigen::Vector3d& c :
       {Eigen::Vector3d(0.9, 0.1, 0.4), Eigen::Vector3d(-0.7, 1.1, 0.9)}) {
    const SphereImage s = cam.ImageOfSphere(c, r);
    ASSERT_TRUE(s.valid);
    double area = 0;
    const Eigen::Vector2d centroid = RayCentroid(cam, c, r, area);
    EXPECT_LT((centroid - s.center_px).norm(), 0.01) << c.transpose();
    EXPECT_GT((s.projection_px - s.center_px).norm(), 0.5) << c.transpose();  // they differ
    EXPECT_NEAR(area, std::acos(-1.0) * s.semi_major_px * s.semi_minor_px, 0.002 * area);
    EXPECT_GT(s.semi_major_px, s.semi_minor_px * 1.01);  // an ellipse, not a circle
    // The major axis points at the principal point (the ellipse is stretched radially).
    const Eigen::Vector2d radial = (s.center_px - cam.principal_point_px()).normalized();
    const Eigen::Vector2d major{std::cos(s.major_angle_rad), std::sin(s.major_angle_rad)};
    EXPECT_GT(std::abs(radial.dot(major)), 0.999);
  }
}

TEST(PinholeCameraTest, TiltPanAndRollTurnTheImageAsDocumented) {
  FootageCameraOptions o = Level();
  const Eigen::Vector3d ahead{0, 0.5, 0};  // on the axis of the level camera
  o.tilt_deg = 10;  // looking down: a point at the camera's height appears above the centre
  EXPECT_LT(PinholeCamera(o).Project(ahead).y(), 239.5 - 50);
  o.tilt_deg = 0;
  o.pan_deg = 10;  // turned toward +x: the point appears left of the centre
  EXPECT_LT(PinholeCamera(o).Project(ahead).x(), 319.5 - 50);
  o.pan_deg = 0;
  o.roll_deg = 20;  // the scene turns clockwise: "down" tilts toward -x_I
  const Eigen::Vector2d g = PinholeCamera(o).ImageDirection(ahead, -Eigen::Vector3d::UnitY());
  const double rho = core::DegToRad(20);
  EXPECT_NEAR(g.x(), -std::sin(rho), 1e-6);
  EXPECT_NEAR(g.y(), std::cos(rho), 1e-6);
  // R_CW is a rotation.
  const Eigen::Matrix3d R = PinholeCamera(o).R_CW();
  EXPECT_LT((R * R.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
}

TEST(PinholeCameraTest, ImageVelocityOnTheAxisIsFocalTimesVelocityOverDepth) {
  const PinholeCamera cam(Level());
  const Eigen::Vector3d c{0, 0.5, 0.5};  // on the axis, 1.5 m ahead
  const Eigen::Vector2d v = cam.ImageVelocity(c, 0.001, {0.7, -0.4, 0.9});
  EXPECT_NEAR(v.x(), 500 * 0.7 / 1.5, 1e-3);
  EXPECT_NEAR(v.y(), 500 * 0.4 / 1.5, 1e-3);  // y_I points down
}

}  // namespace
}  // namespace hoof::synth
