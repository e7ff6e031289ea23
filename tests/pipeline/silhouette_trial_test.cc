// A trial tracked by its silhouette, end to end (AnalyzeTrial), on frames drawn here with exact
// area coverage at known positions: a ball bouncing with a known e, and the same ball's clip
// cut before the impact; the body field of trial.json.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "pipeline/trial_analysis.h"
#include "tracking/silhouette_test_images.h"

namespace hoof::pipeline {
namespace {

namespace fs = std::filesystem;

constexpr double kFps = 8000, kMPerPx = 1e-4, kRadiusPx = 18.3, kG = 9.80665;
constexpr double kImpactFrame = 21.4;                  // first touch between frames 21 and 22
constexpr double kVBefore = 2.0, kE = 0.8, kVx = 0.3;  // m/s (down before), e, along the surface
constexpr double kSurfaceYPx = 150.0;                  // the surface's row in the image

/// The ball's centre in the image at frame i: a parabola down to the surface, then up again
/// with e times the normal speed, drifting along the level surface at kVx.
Eigen::Vector2d Centre(int i) {
  const double t = (i - kImpactFrame) / kFps;
  const double h_m =
      t < 0 ? -kVBefore * t - 0.5 * kG * t * t : kE * kVBefore * t - 0.5 * kG * t * t;
  return {60.27 + kVx * t / kMPerPx, kSurfaceYPx - kRadiusPx - h_m / kMPerPx};
}

/// Writes a trial folder of `count` frames (16-bit PNGs with 12-bit values: a dark ball on a
/// bright back-light, seeded noise) and the given body and camera fields.
fs::path WriteTrial(const std::string& name, int count, const std::string& body_and_camera,
                    bool moving = true) {
  const fs::path dir = fs::path(HOOF_BINARY_DIR) / "test-output" / "silhouette_trial" / name;
  fs::remove_all(dir);
  fs::create_directories(dir / "frames");
  for (int i = 0; i < count; ++i) {
    cv::Mat img(200, 140, CV_64F, cv::Scalar(3800.0));
    hoof::testing::PaintDisc(img, moving ? Centre(i) : Centre(0), kRadiusPx, 400.0, 3800.0);
    char file[32];
    std::snprintf(file, sizeof file, "frames/%06d.png", i);
    cv::imwrite((dir / file).string(),
                hoof::testing::Quantize(img, CV_16U, 12.0, static_cast<unsigned>(100 + i)));
  }
  std::ofstream(dir / "trial.json")
      << R"({"format": "hoofimpact-trial/1", "id": ")" << name
      << R"(", "surface": "steel", "surface_angle_deg": 0, "fps": 8000,
  "frames": {"pattern": "frames/%06d.png", "first": 0, "count": )"
      << count << "}, " << body_and_camera << "}";
  return dir;
}

const char* kBall =
    R"("body": {"model": "silhouette", "shape": "ball", "diameter_m": 0.00366}, "camera": {})";

TEST(SilhouetteTrialTest, ABouncingBallGivesItsRestitutionFromTheCentreTrack) {
  const TrialAnalysis r = AnalyzeTrial(ReadTrial(WriteTrial("bounce", 44, kBall)));
  ASSERT_TRUE(r.success) << r.error;
  EXPECT_FALSE(r.no_impact);
  EXPECT_EQ(r.scale_source, "body.diameter_m");
  // 3.66 mm over 36.6 px: the fitted diameter is within 0.04 px (the mid-level crossing of a
  // curved, anti-aliased edge lies a hundredth of a pixel inside it).
  EXPECT_NEAR(r.m_per_px_used, kMPerPx, 1e-3 * kMPerPx);
  EXPECT_NEAR(r.body_diameter_px, 2 * kRadiusPx, 0.05);
  EXPECT_EQ(r.silhouette.polarity, tracking::Polarity::kDarkOnBright);
  const auto& k = r.impact;
  EXPECT_NEAR(k.e, kE, 0.01) << "e " << k.e << " +- " << k.e_se;
  EXPECT_NEAR(k.v_SC_before.y(), -kVBefore, 0.01 * kVBefore);
  EXPECT_NEAR(k.v_SC_after.y(), kE * kVBefore, 0.01 * kVBefore);
  EXPECT_NEAR(k.v_SC_before.x(), kVx, 0.01);
  EXPECT_NEAR(k.impact_time_s, kImpactFrame / kFps, 0.1 / kFps);
  // A ball's rotation is not seen.
  EXPECT_TRUE(std::isnan(k.w_before_rad_s));
  EXPECT_TRUE(std::isnan(k.w_after_rad_s));
  EXPECT_TRUE(std::isnan(k.kinetic_energy_before_J));  // its mass is unknown
}

TEST(SilhouetteTrialTest, AClipEndingBeforeTheImpactSaysSoAndReportsTheApproach) {
  const TrialAnalysis r = AnalyzeTrial(
      ReadTrial(WriteTrial("approach", 18, R"("body": {"model": "silhouette", "shape": "ball"},
        "camera": {"m_per_px": 1e-4})")));
  EXPECT_FALSE(r.success);
  EXPECT_TRUE(r.no_impact) << r.error;
  EXPECT_NE(r.error.find("no impact"), std::string::npos) << r.error;
  EXPECT_EQ(r.scale_source, "camera.m_per_px");
  EXPECT_EQ(r.motion.frames_tracked, 18);
  EXPECT_TRUE(r.motion.gravity_fit);
  // The mean velocity over frames 0..17 (at frame 8.5): v = vb - g (ti - t) downwards.
  const double v_down = kVBefore - kG * (kImpactFrame - 8.5) / kFps;
  const double speed = std::hypot(v_down, kVx);
  EXPECT_NEAR(r.motion.speed_m_s, speed, 0.002 * speed);
  EXPECT_NEAR(r.motion.speed_px_per_frame, speed / kMPerPx / kFps, 0.002 * speed / kMPerPx / kFps);
  EXPECT_LT(r.motion.rms_residual_px, 0.05);
  EXPECT_GT(r.motion.speed_se_m_s, 0.0);
  EXPECT_LT(std::abs(r.motion.speed_m_s - speed), 4 * r.motion.speed_se_m_s + 1e-4 * speed);
}

TEST(SilhouetteTrialTest, ABodyThatDoesNotMoveIsAnErrorNamingTheFrames) {
  const TrialAnalysis r = AnalyzeTrial(ReadTrial(WriteTrial("still", 16, kBall, false)));
  EXPECT_FALSE(r.success);
  EXPECT_FALSE(r.no_impact);
  EXPECT_NE(r.error.find("no moving body"), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("000000.png"), std::string::npos) << r.error;
}

// An unmarked specimen (the bar with one rounded end) drawn at known poses: its centroid is C,
// its axis gives the angle, and the impact's velocities, spins and e follow from the outline.
TEST(SilhouetteTrialTest, AnUnmarkedSpecimensOutlineGivesItsVelocitiesSpinAndRestitution) {
  constexpr double fps = 4000, m = 5e-4, width_px = 16, rect_px = 40, t_i = 19.4 / fps;
  const double d = hoof::testing::RoundedBarCentroid(width_px, rect_px) * m;  // |EC|
  const double R = width_px / 2 * m;
  const double theta_i = 100.0 * 3.14159265358979323846 / 180;  // x_B up and a little left
  const Eigen::Vector2d v_b{0.3, -2.0}, v_a{0.1, 1.4};
  const double w_b = 5.0, w_a = 25.0;
  // At first touch the round end's lowest point is on the surface (height 0).
  const Eigen::Vector2d x_Bi{std::cos(theta_i), std::sin(theta_i)};
  const Eigen::Vector2d p_Ci = Eigen::Vector2d(0.03, R) + d * x_Bi;
  const auto pose = [&](int i) {
    const double t = i / fps - t_i;
    const Eigen::Vector2d v = t < 0 ? v_b : v_a;
    const double w = t < 0 ? w_b : w_a;
    return std::pair<Eigen::Vector2d, double>{p_Ci + v * t + Eigen::Vector2d(0, -0.5 * kG * t * t),
                                              theta_i + w * t};
  };
  const fs::path dir = fs::path(HOOF_BINARY_DIR) / "test-output" / "silhouette_trial" / "outline";
  fs::remove_all(dir);
  fs::create_directories(dir / "frames");
  for (int i = 0; i < 40; ++i) {
    const auto [p_C, theta] = pose(i);
    const Eigen::Vector2d x_B{std::cos(theta), std::sin(theta)};
    const Eigen::Vector2d E_W = p_C - d * x_B;
    const Eigen::Vector2d E_I{E_W.x() / m, 150.0 - E_W.y() / m};
    cv::Mat img(170, 120, CV_64F, cv::Scalar(20.0));
    hoof::testing::Paint(img, hoof::testing::RoundedBar(E_I, -theta, width_px, rect_px), 190.0, 0,
                         0, 119, 169);
    char file[32];
    std::snprintf(file, sizeof file, "frames/%06d.png", i);
    cv::imwrite((dir / file).string(),
                hoof::testing::Quantize(img, CV_8U, 1.0, static_cast<unsigned>(300 + i)));
  }
  std::ofstream(dir / "trial.json") << R"({"format": "hoofimpact-trial/1", "id": "outline",
    "specimen": "bar", "specimen_parameters": {"mass_kg": 0.008, "inertia_kg_m2": 1.5e-6,
    "end_radius_m": )" << R << R"(, "d_EC_m": )"
                                    << d << R"(}, "surface": "steel", "surface_angle_deg": 0,
    "fps": 4000, "frames": {"pattern": "frames/%06d.png", "first": 0, "count": 40},
    "camera": {"m_per_px": 5e-4}, "body": {"model": "silhouette", "shape": "outline"}})";
  const TrialAnalysis r = AnalyzeTrial(ReadTrial(dir));
  ASSERT_TRUE(r.success) << r.error;
  EXPECT_EQ(r.silhouette.polarity, tracking::Polarity::kBrightOnDark);
  const auto& k = r.impact;
  // The velocities of C at first touch (the fits are parabolas, so gravity is accounted for).
  EXPECT_NEAR(k.v_SC_before.x(), v_b.x(), 0.01);
  EXPECT_NEAR(k.v_SC_before.y(), v_b.y(), 0.01);
  EXPECT_NEAR(k.v_SC_after.x(), v_a.x(), 0.01);
  EXPECT_NEAR(k.v_SC_after.y(), v_a.y(), 0.01);
  EXPECT_NEAR(k.w_before_rad_s, w_b, 0.5);
  EXPECT_NEAR(k.w_after_rad_s, w_a, 0.5);
  // e from the contact point T's normal velocity: v_T = v_C + w x (p_T - p_C).
  const auto v_T = [&](const Eigen::Vector2d& v, double w) -> Eigen::Vector2d {
    const Eigen::Vector2d r_CT = -d * x_Bi - Eigen::Vector2d(0, R);
    return v + w * Eigen::Vector2d(-r_CT.y(), r_CT.x());
  };
  const double e = std::abs(v_T(v_a, w_a).y() / v_T(v_b, w_b).y());
  EXPECT_NEAR(k.e, e, 0.01) << "e " << k.e << " +- " << k.e_se << ", truth " << e;
  EXPECT_NEAR(k.impact_time_s, t_i, 0.2 / fps);
}

TEST(SilhouetteTrialTest, TheBodyFieldIsCheckedNamingTheField) {
  const auto error_of = [](const std::string& body_and_camera) {
    const fs::path dir = WriteTrial("bad_body", 1, body_and_camera);
    try {
      ReadTrial(dir);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error_of(R"("body": {"model": "dots"}, "camera": {"m_per_px": 1e-4})")
                .find("field \"body.model\" is \"dots\""),
            std::string::npos);
  EXPECT_NE(
      error_of(R"("body": {"model": "silhouette", "shape": "cube"}, "camera": {"m_per_px": 1})")
          .find("field \"body.shape\""),
      std::string::npos);
  EXPECT_NE(error_of(R"("body": {"model": "silhouette", "shape": "ball", "polarity": "grey"},
                        "camera": {"m_per_px": 1})")
                .find("field \"body.polarity\""),
            std::string::npos);
  EXPECT_NE(error_of(R"("body": {"model": "silhouette", "shape": "ball", "diameter_m": -1},
                        "camera": {})")
                .find("field \"body.diameter_m\" must be > 0"),
            std::string::npos);
  // No scale at all: camera.m_per_px is missing.
  EXPECT_NE(error_of(R"("body": {"model": "silhouette", "shape": "ball"}, "camera": {})")
                .find("field \"camera.m_per_px\" is missing"),
            std::string::npos);
  EXPECT_NE(
      error_of(R"("body": {"model": "markers", "diameter_m": 0.01}, "camera": {"m_per_px": 1})")
          .find("field \"body.diameter_m\" applies to the \"silhouette\" model only"),
      std::string::npos);
  // A ball needs no specimen; it is its own.
  const TrialSpec t = ReadTrial(WriteTrial("ball_spec", 1, kBall));
  EXPECT_TRUE(t.body.is_ball());
  EXPECT_EQ(t.specimen_id, "ball");
  EXPECT_DOUBLE_EQ(t.specimen.end_radius_m, 0.00183);
  EXPECT_DOUBLE_EQ(t.specimen.d_EC_m, 0.0);
}

}  // namespace
}  // namespace hoof::pipeline
