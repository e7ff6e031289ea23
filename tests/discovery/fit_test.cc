// The discovery fit (src/discovery/fit.cc) at the bounds of an effect's range. The measurements
// here are the simulator's own predictions with a known effect, so the fit must return that
// effect: from a start at 0 (the lower bound, where every candidate's fit may pass), and when the
// truth lies on the upper bound itself. Numeric derivatives that step outside the bounds, where
// the simulator refuses the value, held such fits at the bound with a standard error of nothing.
// And the ladder of sizes (src/discovery/plan.cc) from which a candidate's fit starts and its
// detection limit is found; and a fit that is the same whatever the number of threads.
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "discovery/internal.h"
#include "dynamics/parameters.h"

namespace hoof::discovery::internal {
namespace {

constexpr double kZeta = 0.12, kMu = 0.35;

/// One steel surface: impacts at `angles_deg` (normal and 20 deg unless told) at six speeds
/// each (unless told), measured without error as the simulator predicts them with the contact
/// extensions `truth`.
void StudyWith(const dynamics::ContactExtensions& truth, Workspace& ws,
               const std::vector<double>& angles_deg = {0.0, 20.0},
               const std::vector<double>& speeds = {1.5, 2.0, 2.5, 3.0, 3.5, 4.0}) {
  ws.surfaces = {"steel"};
  ws.k = {dynamics::PaperContact(dynamics::Surface::kSteel).k_N_m};
  ws.has_oblique = {true};
  ws.zeta_start = {kZeta};
  ws.mu_start = {kMu};
  ws.threads = 2;
  for (double angle_deg : angles_deg)
    for (double speed : speeds) {
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
  n.systematic_sd = {Eigen::Vector3d::Constant(1e-4)};
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

/// The model without effects, its residuals and derivatives, and the whitening under SmallNoise.
struct Baseline {
  Model model;
  std::vector<Eigen::Vector3d> r;
  std::vector<Sensitivity> sens;
  std::vector<TrialCovariance> ref;
  explicit Baseline(const Workspace& ws) {
    model.zeta = {kZeta};
    model.mu = {kMu};
    r = ws.Residuals(model, ws.All());
    sens = ws.Sensitivities(model, ws.All());
    ref = Covariances(ws, sens, SmallNoise());
  }
};

/// The ladder of `key` against the model without effects, under SmallNoise.
SizeLadder LadderOf(const Workspace& ws, const std::string& key) {
  const Baseline b(ws);
  return Ladder(ws, b.model, key, b.r, b.sens, b.ref);
}

TEST(DiscoveryFitTest, AnEffectWhoseChangeSwingsInSignIsFitFromTheLaddersOptima) {
  // A tangential spring: the spin after small-angle impacts swings in sign as k/k_t goes from
  // 0.01 to 0.02, so the likelihood has an optimum per swing. A fit started at a tenth of the
  // probe size (as before the ladder) ends in another one; started from the ladder's optima, the
  // best of them is the truth.
  dynamics::ContactExtensions truth;
  truth.tangential_compliance_ratio = 0.016;
  Workspace ws;
  StudyWith(truth, ws, {0.0, 10.0, 20.0});
  const std::string key = "tangential_compliance";
  const SizeLadder ladder = LadderOf(ws, key);
  ASSERT_EQ(ladder.size.front(), Entry(key).smallest);
  const std::vector<double> starts = LadderStarts(ladder, 3);
  ASSERT_FALSE(starts.empty());
  Fit best;
  for (double size : starts) {
    const Fit f = FitModel(ws, ws.All(), Start(key, size), {key}, SmallNoise(), false);
    if (size == starts.front() || f.loglik > best.loglik) best = f;
  }
  ASSERT_TRUE(best.ok) << best.message;
  EXPECT_NEAR(best.model.effects.at(key).value.at(0), 0.016, 0.016 * 0.01);
  const Fit old_start =
      FitModel(ws, ws.All(), Start(key, 0.1 * Entry(key).probe), {key}, SmallNoise(), false);
  EXPECT_GT(std::abs(old_start.model.effects.at(key).value.at(0) - 0.016), 0.016 * 0.05);
  EXPECT_LT(old_start.loglik, best.loglik);
}

TEST(DiscoveryFitTest, TheLaddersDetectionLimitIsWaldsAtThatSize) {
  // Hunt-Crossley damping changes e with c. The ladder's limit L is the size whose simulated
  // change has the target noncentrality, so the Wald limit of the change per unit at L (the
  // secant from 0 to L) must be L again, up to the ladder's interpolation.
  Workspace ws;
  StudyWith({}, ws);
  const std::string key = "hunt_crossley";
  const SizeLadder ladder = LadderOf(ws, key);
  const double level = 1e-3;
  const double limit = LadderDetectionLimit(ladder, level);
  ASSERT_TRUE(std::isfinite(limit));
  ASSERT_GT(limit, ladder.size.front());
  const Baseline b(ws);
  const auto& sens = b.sens;
  const auto& ref = b.ref;
  auto secant = [&](double size) {
    const auto r1 = ws.Residuals(Start(key, size), ws.All());
    std::vector<Eigen::Vector3d> d_r(ws.obs.size());
    for (std::size_t i = 0; i < ws.obs.size(); ++i) d_r[i] = (b.r[i] - r1[i]) / size;
    return d_r;
  };
  EXPECT_NEAR(DetectionLimit(ProfiledInformation(ws, secant(limit), sens, ref), level), limit,
              0.01 * limit);
  // Its changes point one way at every size: no ray beyond the secant at the probe size.
  EXPECT_TRUE(LadderRays(ws, ladder, secant(Entry(key).probe), sens, ref).empty());
}

TEST(DiscoveryFitTest, NoDetectionLimitBelowTheSmallestSizeTheFitMayTake) {
  // Without error every size of the spring is detected, but the fit cannot name one below
  // LibraryEntry::smallest; nor is the limit a straight line from the probe size, where the
  // change is far larger.
  Workspace ws;
  StudyWith({}, ws, {0.0, 10.0, 20.0});
  const std::string key = "tangential_compliance";
  EXPECT_DOUBLE_EQ(LadderDetectionLimit(LadderOf(ws, key), 1e-3), Entry(key).smallest);
}

TEST(DiscoveryFitTest, TheFitIsTheSameToTheLastBitWhateverTheThreads) {
  // A decision at its threshold must not turn with `--jobs`. Measurements with a seeded error,
  // an effect and the noise model fitted: every number of the fit compared bit for bit between
  // one, two and three threads.
  dynamics::ContactExtensions truth;
  truth.hunt_crossley_N_s_m2 = 3e7;
  Workspace ws;
  std::vector<double> speeds;
  for (int i = 0; i < 36; ++i) speeds.push_back(1.5 + 2.5 * i / 35.0);
  StudyWith(truth, ws, {0.0, 10.0, 20.0, 30.0}, speeds);
  std::mt19937_64 rng(20261125);
  std::normal_distribution<double> error(0.0, 2e-3);
  for (Obs& o : ws.obs)
    for (int c = 0; c < kComponents; ++c) o.measured[c] += error(rng) * o.scale;
  auto fit_on = [&](int threads) {
    ws.threads = threads;
    return FitModel(ws, ws.All(), Start("hunt_crossley", 0.0), {"hunt_crossley"}, SmallNoise(),
                    true);
  };
  const Fit one = fit_on(1);
  ASSERT_TRUE(one.ok) << one.message;
  for (int threads : {2, 3}) {
    const Fit f = fit_on(threads);
    ASSERT_TRUE(f.ok) << f.message;
    EXPECT_EQ(f.loglik, one.loglik) << threads << " threads";
    EXPECT_EQ(f.model.zeta, one.model.zeta) << threads << " threads";
    EXPECT_EQ(f.model.mu, one.model.mu) << threads << " threads";
    EXPECT_EQ(f.model.effects.at("hunt_crossley").value,
              one.model.effects.at("hunt_crossley").value)
        << threads << " threads";
    EXPECT_EQ(f.effect_se.at("hunt_crossley"), one.effect_se.at("hunt_crossley"))
        << threads << " threads";
    EXPECT_EQ(f.zeta_se, one.zeta_se) << threads << " threads";
    EXPECT_EQ(f.noise.zeta_sd, one.noise.zeta_sd) << threads << " threads";
  }
  // And it is a fit: the damping comes back near the truth it was measured with.
  EXPECT_NEAR(one.model.effects.at("hunt_crossley").value.at(0), 3e7, 0.3 * 3e7);
}

}  // namespace
}  // namespace hoof::discovery::internal
