// The scale from a calibration image (tracking/calibration_target.h) on checkerboards and rulers
// that the renderer draws at a known scale (synth/calibration_image.h), through the default
// camera's lens distortion, defocus, lighting and noise. The checkerboard over 6 seeds: within 4
// of its own standard errors and 0.01 % of the truth (the s.e. is honest). The ruler over 12
// seeds: within 0.05 %, its s.e. too small (see below). Bad input: no board, another corner
// count, a ruler segment off the image: errors that name the image.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "synth/calibration_image.h"
#include "synth/camera_model.h"
#include "tracking/calibration_target.h"

namespace {

using hoof::synth::CalibrationPlan;
using hoof::synth::CalibrationTarget;
using hoof::synth::RenderOptions;
using hoof::tracking::CalibrationScale;

/// The lens as trial.json gives it to `track` (synth/trial_files.cc writes the same).
hoof::tracking::ImageToWorld Lens(const RenderOptions& o) {
  hoof::tracking::ImageToWorld cam;
  const hoof::synth::LensModel lens(o.camera, o.width_px, o.height_px);
  if (lens.distorts()) {
    const Eigen::Vector2d c = lens.principal_point_px();
    cam.camera_matrix =
        std::array<double, 9>{lens.focal_px(), 0, c.x(), 0, lens.focal_px(), c.y(), 0, 0, 1};
    cam.distortion = lens.coefficients();
  }
  return cam;
}

struct Measured {
  CalibrationPlan plan;
  CalibrationScale scale;
};

Measured MeasureRendered(CalibrationTarget target, std::uint64_t seed,
                         const RenderOptions& base = {}) {
  RenderOptions o = base;
  o.calibration = target;
  Measured m;
  m.plan = hoof::synth::PlanCalibration(o, seed);
  const cv::Mat image = hoof::synth::RenderCalibrationImage(m.plan, o, seed);
  if (target == CalibrationTarget::kCheckerboard)
    m.scale = hoof::tracking::MeasureCheckerboard(image, m.plan.cols, m.plan.rows, m.plan.square_m,
                                                  Lens(o), "calibration.png");
  else
    m.scale = hoof::tracking::MeasureRuler(image, m.plan.from_px, m.plan.to_px, m.plan.tick_m,
                                           Lens(o), "calibration.png");
  return m;
}

/// Over seeds 1..n: every measurement within `max_rel` of the truth and, when `max_z` > 0, within
/// max_z of its s.e., and the rate of |error| / s.e. < 3 at least `min_rate`; all printed.
void ExpectScale(CalibrationTarget target, int n, double max_rel, double max_z, double min_rate) {
  int within = 0;
  double sum_z2 = 0, worst = 0;
  for (int seed = 1; seed <= n; ++seed) {
    const Measured m = MeasureRendered(target, static_cast<std::uint64_t>(seed));
    const double err = m.scale.m_per_px - m.plan.m_per_px;
    const double z = err / m.scale.m_per_px_se;
    sum_z2 += z * z;
    within += std::abs(z) < 3 ? 1 : 0;
    std::printf(
        "%s seed %d: m/px %.6e (truth %.6e), s.e. %.2e (%.4f %%), z %+.2f, %d points, "
        "rms %.3f px\n",
        hoof::synth::ToString(target), seed, m.scale.m_per_px, m.plan.m_per_px, m.scale.m_per_px_se,
        100 * m.scale.m_per_px_se / m.plan.m_per_px, z, m.scale.points, m.scale.rms_residual_px);
    EXPECT_GT(m.scale.m_per_px_se, 0.0);
    if (max_z > 0) {
      EXPECT_LT(std::abs(z), max_z) << "seed " << seed;
    }
    EXPECT_LT(std::abs(err), max_rel * m.plan.m_per_px) << "seed " << seed;
    worst = std::max(worst, std::abs(err) / m.plan.m_per_px);
  }
  const double rate = static_cast<double>(within) / n;
  std::printf(
      "%s: |error| / s.e. < 3 in %d of %d seeds (%.0f %%), rms of the z %.2f, worst relative "
      "error %.4f %%\n",
      hoof::synth::ToString(target), within, n, 100 * rate, std::sqrt(sum_z2 / n), 100 * worst);
  EXPECT_GE(rate, min_rate);
}

// The board's s.e. is about 0.002 % (0.016 px rms residuals over 54 corners spanning ~130 x 80
// px): every seed within 4 s.e. and 0.01 % (5 s.e.), and |z| < 3 in at least 5 of 6 seeds.
TEST(CalibrationScaleTest, ARenderedCheckerboardGivesTheScaleWithAnHonestError) {
  ExpectScale(CalibrationTarget::kCheckerboard, 6, 1e-4, 4.0, 5.0 / 6);
}

// The ruler (80 ticks of 5 px over 400 px) is within 0.05 % of the truth on every seed, but its
// stated s.e. (0.0013-0.0045 %) is NOT honest: the measured scale is low by 0.005-0.02 % on
// every seed (a bias not yet explained, docs/tracking.md "4b. The scale"), so |z| < 3 on only
// a few seeds. No assertion on z here; the rate is printed.
TEST(CalibrationScaleTest, ARenderedRulerGivesTheScaleWithin005Percent) {
  ExpectScale(CalibrationTarget::kRuler, 12, 5e-4, 0.0, 0.0);
}

TEST(CalibrationScaleTest, NoBoardOrAnotherCornerCountIsAnErrorNamingTheImage) {
  RenderOptions o;
  o.calibration = CalibrationTarget::kCheckerboard;
  const CalibrationPlan plan = hoof::synth::PlanCalibration(o, 1);
  const cv::Mat image = hoof::synth::RenderCalibrationImage(plan, o, 1);
  try {
    hoof::tracking::MeasureCheckerboard(image, 7, 5, plan.square_m, Lens(o), "board.png");
    FAIL() << "a 9 x 6 board taken as 7 x 5";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("board.png"), std::string::npos) << what;
    EXPECT_NE(what.find("9 x 6"), std::string::npos) << what;
    EXPECT_NE(what.find("7 x 5"), std::string::npos) << what;
  }
  const cv::Mat blank(o.height_px, o.width_px, CV_8U, cv::Scalar(90));
  try {
    hoof::tracking::MeasureCheckerboard(blank, 9, 6, plan.square_m, Lens(o), "blank.png");
    FAIL() << "a board found in a blank image";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("blank.png"), std::string::npos) << what;
    EXPECT_NE(what.find("no checkerboard"), std::string::npos) << what;
  }
}

TEST(CalibrationScaleTest, ARulerSegmentOffTheImageOrWithoutTicksIsAnError) {
  RenderOptions o;
  o.calibration = CalibrationTarget::kRuler;
  const CalibrationPlan plan = hoof::synth::PlanCalibration(o, 1);
  const cv::Mat image = hoof::synth::RenderCalibrationImage(plan, o, 1);
  try {
    hoof::tracking::MeasureRuler(image, plan.from_px, {600, 100}, plan.tick_m, Lens(o),
                                 "ruler.png");
    FAIL() << "a segment beyond the 512 px wide image";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("ruler.png"), std::string::npos) << what;
    EXPECT_NE(what.find("\"to\""), std::string::npos) << what;
    EXPECT_NE(what.find("outside"), std::string::npos) << what;
  }
  // A segment across the plain background: no regular ticks.
  const cv::Mat blank(o.height_px, o.width_px, CV_8U, cv::Scalar(90));
  EXPECT_THROW(
      hoof::tracking::MeasureRuler(blank, {20, 20}, {400, 20}, plan.tick_m, Lens(o), "blank.png"),
      std::runtime_error);
}

}  // namespace
