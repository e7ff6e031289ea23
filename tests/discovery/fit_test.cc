// The discovery fit (src/discovery/fit.cc) at the bounds of an effect's range. The measurements
// here are the simulator's own predictions with a known effect, so the fit must return that
// effect: from a start at 0 (the lower bound, where every candidate's fit may pass), and when the
// truth lies on the upper bound itself. Numeric derivatives that step outside the bounds, where
// the simulator refuses the value, held such fits at the bound with a standard error of nothing.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "discovery/internal.h"
#include "dynamics/parameters.h"

namespace hoof::discovery::internal {
namespace {

constexpr double kZeta = 0.12, kMu = 0.35;

/// One steel surface: normal and 20 deg impacts at six speeds each, measured without error as
/// the simulator predicts them with the contact extensions `truth`.
void StudyWith(const dynamics::ContactExtensions& truth, Workspace& ws) {
  ws.surfaces = {"steel"};
  ws.k = {dynamics::PaperContact(dynamics::Surface::kSteel).k_N_m};
  ws.has_oblique = {true};
  ws.zeta_start = {kZeta};
  ws.mu_start = {kMu};
  ws.threads = 2;
  for (double angle_deg : {0.0, 20.0})
    for (double speed : {1.5, 2.0, 2.5, 3.0, 3.5, 4.0}) {
      Obs o;
      o.surface = 0;
      o.angle_deg = angle_deg;
      o.speed_m_s = speed;
      o.normal = angle_deg == 0.0;
      o.phi = angle_deg * std::numbers::pi / 180.0;
      o.conditions = dynamics::ImpactConditions::Paper(speed, angle_deg);
      o.scale = speed;
      o.used = {!o.normal, true, !o.normal};
      o.measurement_var = Eigen::Vector3d::Constant(1e-8);
      bool ok = false;
      o.measured = ws.Predict(o, kZeta, kMu, truth, &ok);
      EXPECT_TRUE(ok);
      ws.obs.push_back(o);
    }
}

Noise SmallNoise() {
  Noise n;
  n.zeta_sd = {1e-4};
  n.mu_sd = {1e-4};
  n.systematic_sd = Eigen::Vector3d::Constant(1e-4);
  return n;
}

Model Start(const std::string& key, double value) {
  Model m;
  m.zeta = {kZeta};
  m.mu = {kMu};
  m.effects[key] = {EffectForm::kShared, {value}};
  return m;
}

TEST(DiscoveryFitTest, AnEffectFitFromZeroReachesTheTruth) {
  dynamics::ContactExtensions truth;
  truth.hunt_crossley_N_s_m2 = 3e7;
  Workspace ws;
  StudyWith(truth, ws);
  const Fit f =
      FitModel(ws, ws.All(), Start("hunt_crossley", 0.0), {"hunt_crossley"}, SmallNoise(), false);
  ASSERT_TRUE(f.ok) << f.message;
  EXPECT_NEAR(f.model.effects.at("hunt_crossley").value.at(0), 3e7, 3e5);
  EXPECT_NEAR(f.model.zeta[0], kZeta, 1e-3);
}

TEST(DiscoveryFitTest, AnEstimateOnTheUpperBoundHasTheStandardErrorOfItsCurvature) {
  // The library's Hertzian exponent ends at 1. Its s.e. there comes from the same curvature as
  // inside the range: compare it with the s.e. of a fit whose truth (0.9) is inside.
  auto fit_at = [](double p) {
    dynamics::ContactExtensions truth;
    truth.stiffness_exponent_extra = p;
    Workspace ws;
    StudyWith(truth, ws);
    return FitModel(ws, ws.All(), Start("hertz_stiffness", 0.5), {"hertz_stiffness"}, SmallNoise(),
                    false);
  };
  const Fit inside = fit_at(0.9), bound = fit_at(1.0);
  ASSERT_TRUE(inside.ok) << inside.message;
  ASSERT_TRUE(bound.ok) << bound.message;
  EXPECT_NEAR(inside.model.effects.at("hertz_stiffness").value.at(0), 0.9, 1e-3);
  EXPECT_NEAR(bound.model.effects.at("hertz_stiffness").value.at(0), 1.0, 1e-3);
  // And the verdict says which of the two lies on the bound.
  EXPECT_FALSE(
      AtUpperBound("hertz_stiffness", inside.model.effects.at("hertz_stiffness").value[0]));
  EXPECT_TRUE(AtUpperBound("hertz_stiffness", bound.model.effects.at("hertz_stiffness").value[0]));
  const double se_inside = inside.effect_se.at("hertz_stiffness").at(0);
  const double se_bound = bound.effect_se.at("hertz_stiffness").at(0);
  ASSERT_GT(se_inside, 0);
  EXPECT_GT(se_bound, 0.5 * se_inside);
  EXPECT_LT(se_bound, 2.0 * se_inside);
}

}  // namespace
}  // namespace hoof::discovery::internal
