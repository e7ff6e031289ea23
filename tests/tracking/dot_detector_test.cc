#include "tracking/dot_detector.h"

#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "tracking/test_images.h"

namespace hoof::tracking {
namespace {

TEST(DotDetectorTest, FindsDotsWithSubPixelCentresOnCleanImages) {
  // Centres at arbitrary sub-pixel positions; 8-bit quantization is the only error.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst[2] = {0, 0};
  for (int trial = 0; trial < 20; ++trial) {
    const std::vector<Eigen::Vector2d> truth = {{100.0 + u(rng), 80.0 + u(rng)},
                                                {220.0 + u(rng), 150.0 + u(rng)}};
    const cv::Mat img = hoof::testing::DrawDots(320, 240, truth, 7.5, 15);
    for (int method = 0; method < 2; ++method) {
      DotDetectorOptions o;
      o.method = method == 0 ? CentreMethod::kWeightedCentroid : CentreMethod::kEllipseFit;
      const auto dots = FindDots(img, 2, o);
      ASSERT_EQ(dots.size(), 2u);
      for (const auto& t : truth) {
        double best = 1e9;
        for (const auto& d : dots) best = std::min(best, (d.p_I - t).norm());
        worst[method] = std::max(worst[method], best);
      }
    }
  }
  EXPECT_LT(worst[0], 0.01);  // weighted centroid
  EXPECT_LT(worst[1], 0.03);  // ellipse through mid-level crossings
}

TEST(DotDetectorTest, NoiseDoesNotBiasTheCentroid) {
  // 2 % noise (about 5 grey levels): the centroid scatter stays far below 0.05 px and the mean
  // error is zero.
  const Eigen::Vector2d truth{150.37, 120.81};
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  double ss = 0;
  const int n = 50;
  for (int i = 0; i < n; ++i) {
    const cv::Mat img = hoof::testing::DrawDots(300, 240, {truth}, 7.5, 15, 0.02, 100 + i);
    const auto dot = FindDotNear(img, truth + Eigen::Vector2d(1.5, -2.0), 8.0, 7.5);
    ASSERT_TRUE(dot.has_value());
    mean += dot->p_I - truth;
    ss += (dot->p_I - truth).squaredNorm();
  }
  mean /= n;
  EXPECT_LT(std::sqrt(ss / n), 0.03);
  EXPECT_LT(mean.norm(), 0.01);
}

TEST(DotDetectorTest, NothingIsFoundWhereThereIsNoDot) {
  cv::Mat flat(200, 200, CV_8U, cv::Scalar(100));
  cv::Mat noise(200, 200, CV_8U);
  cv::randn(noise, 0, 3);
  flat += noise;
  EXPECT_TRUE(FindDots(flat, 2).empty());
  // A dot exists, but outside the search window.
  const cv::Mat img = hoof::testing::DrawDots(200, 200, {{150.2, 150.7}}, 7.0, 14);
  EXPECT_FALSE(FindDotNear(img, {50, 50}, 10.0, 7.0).has_value());
  EXPECT_TRUE(FindDotNear(img, {146, 153}, 10.0, 7.0).has_value());
}

TEST(DotDetectorTest, LowContrastDotsFailTheSignificanceRule) {
  // The same dot at 4 % of full scale over 2 % noise is not significant at 8 sigma... until
  // the rule is relaxed, which shows it is the rule, not the drawing, that decides.
  cv::Mat img = hoof::testing::DrawDots(200, 200, {{100.4, 100.6}}, 7.0, 14);
  cv::Mat f;
  img.convertTo(f, CV_32F, 1.0 / 255);
  f = 0.4 + (f - 0.05) * (0.04 / 0.85);
  cv::Mat noise(200, 200, CV_32F);
  cv::randn(noise, 0, 0.01);
  f += noise;
  EXPECT_FALSE(FindDotNear(f, {100, 100}, 6.0, 7.0).has_value());
  DotDetectorOptions loose;
  loose.min_significance = 2.0;
  EXPECT_TRUE(FindDotNear(f, {100, 100}, 6.0, 7.0, loose).has_value());
}

}  // namespace
}  // namespace hoof::tracking
