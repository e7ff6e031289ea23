#include "dynamics/contact_fit.h"

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "dynamics/impact_simulator.h"

namespace hoof::dynamics {
namespace {

/// Normal impacts simulated with a known contact law (k_true, zeta_true), rebound speeds
/// multiplied by (1 + noise) with a seeded normal draw.
std::vector<NormalImpact> Synthesize(double k_true, double zeta_true, double noise, int n,
                                     unsigned seed) {
  const SpecimenParameters specimen;
  const ContactParameters contact{k_true, DampingForRatio(zeta_true, k_true, specimen.mass_kg),
                                  0.0};
  const ImpactSimulator sim(specimen, contact);
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<NormalImpact> out;
  for (int i = 0; i < n; ++i) {
    const double v = 1.5 + 2.5 * i / std::max(1, n - 1);  // the paper's 1.5-4 m/s
    const double after = sim.Simulate(ImpactConditions::Paper(v, 0.0)).at_separation.v_SC.y();
    out.push_back({v, after * (1.0 + noise * gauss(rng))});
  }
  return out;
}

TEST(ContactFitTest, RecoversZetaButNotStiffnessFromExactVelocities) {
  // Data made with the paper's concrete stiffness; the fit works at k = 1e8 and still finds
  // zeta, because velocities depend on zeta alone.
  const auto impacts = Synthesize(4.24e8, 0.2531, 0.0, 8, 1);
  ContactFitOptions options;
  options.map_points_k = options.map_points_b = 11;
  const ContactFitSummary s = FitNormalContact(impacts, SpecimenParameters{}, options);
  ASSERT_TRUE(s.success) << s.message;
  EXPECT_NEAR(s.zeta, 0.2531, 2e-4);
  EXPECT_LT(s.mpe_percent, 0.02);
  // Every k in the paper's box (where b stays in bounds) fits as well as the truth: the valley.
  ASSERT_EQ(s.valley.size(), 9u);
  EXPECT_DOUBLE_EQ(s.valley_k_min_N_m, 1e5);
  EXPECT_DOUBLE_EQ(s.valley_k_max_N_m, 1e9);
  EXPECT_LT(s.valley_mpe_spread_percent, 0.05);
  EXPECT_LT(s.valley_zeta_spread, 2e-3);
  for (const auto& p : s.valley) {
    EXPECT_NEAR(p.zeta, 0.2531, 2e-3) << "k " << p.k_N_m;
    EXPECT_NEAR(p.b_N_s_m, DampingForRatio(p.zeta, p.k_N_m, 0.008), 1e-9 * p.b_N_s_m);
  }
  // And the explanation says k is not identified.
  EXPECT_NE(s.Explanation().find("NOT identified"), std::string::npos);
}

TEST(ContactFitTest, ObjectiveMapIsSmallestAlongTheValley) {
  const auto impacts = Synthesize(7.24e8, 0.1105, 0.0, 6, 2);
  ContactFitOptions options;
  options.map_points_k = 9;
  options.map_points_b = 201;  // b step 10 N s/m
  options.valley_points = 2;
  const ContactFitSummary s = FitNormalContact(impacts, SpecimenParameters{}, options);
  ASSERT_TRUE(s.success);
  for (std::size_t i = 0; i < s.map_k_N_m.size(); ++i) {
    const double b_valley = DampingForRatio(s.zeta, s.map_k_N_m[i], 0.008);
    if (b_valley > 1990) continue;
    Eigen::Index j_best = 0;
    s.map_mpe_percent.row(static_cast<Eigen::Index>(i)).minCoeff(&j_best);
    EXPECT_NEAR(s.map_b_N_s_m[static_cast<std::size_t>(j_best)], b_valley, 10.0 + 0.01 * b_valley)
        << "k " << s.map_k_N_m[i];
  }
}

TEST(ContactFitTest, IntervalCoversTheTruthAtItsNominalRate) {
  // 2 % noise on the rebound speed, 12 impacts, 120 seeded replicates: a 95 % interval should
  // cover zeta_true in about 95 % of them (binomial s.d. 2 %).
  ContactFitOptions options;
  options.map_points_k = options.map_points_b = 0;
  options.valley_points = 2;
  int covered = 0;
  const int replicates = 120;
  for (int rep = 0; rep < replicates; ++rep) {
    const auto impacts = Synthesize(5.86e7, 0.6009, 0.02, 12, 100 + static_cast<unsigned>(rep));
    const ContactFitSummary s = FitNormalContact(impacts, SpecimenParameters{}, options);
    ASSERT_TRUE(s.success);
    if (s.zeta_ci_low <= 0.6009 && 0.6009 <= s.zeta_ci_high) ++covered;
    EXPECT_GT(s.zeta_se, 0.0);
  }
  EXPECT_GE(covered, 106);  // >= 88 %
  EXPECT_LE(covered, 119);
}

TEST(ContactFitTest, BadInputNamesTheImpactOrOption) {
  auto expect = [](auto fn, const std::string& what) {
    try {
      fn();
      FAIL() << "expected an error naming " << what;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  expect([] { FitNormalContact({{3.0, 2.5}, {-1.0, 2.0}}, {}); }, "normal impact 1");
  expect([] { FitNormalContact({{3.0, NAN}}, {}); }, "normal impact 0");
  ContactFitOptions options;
  options.k_max_N_m = 1e4;
  expect([&] { FitNormalContact({{3.0, 2.5}}, {}, options); }, "k_max_N_m");
  options = {};
  options.confidence = 1.5;
  expect([&] { FitNormalContact({{3.0, 2.5}}, {}, options); }, "confidence");
  // No impacts: a summary that says so, not a crash.
  const ContactFitSummary none = FitNormalContact({}, {});
  EXPECT_FALSE(none.success);
  EXPECT_FALSE(none.message.empty());
  // One impact: zeta, but no interval.
  ContactFitOptions quick;
  quick.map_points_k = quick.map_points_b = 0;
  quick.valley_points = 2;
  const ContactFitSummary one = FitNormalContact({{3.0, 2.55}}, {}, quick);
  ASSERT_TRUE(one.success);
  EXPECT_TRUE(std::isnan(one.zeta_se));
}

}  // namespace
}  // namespace hoof::dynamics
