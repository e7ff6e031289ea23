// A contact candidate's evidence without its most influential trial (CheckInfluence,
// src/discovery/candidates.cc; docs/discovery.md, "One trial is no effect"). The systematic error
// of the noise model is one per surface, so a single trial that the current model cannot
// follow raises it for every trial of the surface, and an effect that explains that trial alone
// then gains on all of them: its likelihood ratio is significant although only one trial
// speaks for it. Judged without that trial, both models refitted, such an effect is not named;
// an effect that every oblique trial shows still is. And the fit those judgements rest on never
// ends below its start (FitModel, src/discovery/fit.cc): without that, the fit that found the
// one-trial spring on a null study stopped early instead, and the two were seen only together.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "discovery/internal.h"
#include "steel_study.h"

namespace hoof::discovery::internal {
namespace {

// Steel with its mu just above what a 10 deg impact needs to stick (tan 10 deg = 0.176): its
// 10 deg trials stick, and a trial whose own mu falls lower would slide.
constexpr double kZeta = 0.16, kMu = 0.185;
constexpr double kLevel = 1e-3;

/// 40 trials at 0, 10, 20 and 30 deg with the paper's scatter of e and mu, the measurement's
/// systematic error 1e-3 of the impact speed, and `spring` (k/k_t, 0 for none) hidden.
void Study(Workspace& ws, double spring, std::uint64_t seed) {
  SteelStudy(ws, {0.0, 10.0, 20.0, 30.0}, 10, kZeta, kMu);
  Fit truth;
  truth.model.zeta = {kZeta};
  truth.model.mu = {kMu};
  if (spring > 0) truth.model.effects["tangential_compliance"] = {EffectForm::kShared, {spring}};
  truth.noise.zeta_sd = {0.05};
  truth.noise.mu_sd = {0.02};
  truth.noise.systematic_sd = {Eigen::Vector3d::Constant(1e-3)};
  const auto measured = SimulateStudy(ws, truth, seed);
  for (std::size_t i = 0; i < ws.obs.size(); ++i) ws.obs[i].measured = measured[i];
  // As Build sets it: the largest |mu_eff| of the oblique trials, from the velocities of C
  // before (the conditions) and after (measured), in S.
  ws.mu_eff_max = {0.0};
  for (const Obs& o : ws.obs) {
    if (o.normal) continue;
    const Eigen::Vector2d dv = o.measured.head<2>() - o.conditions.v_SC_m_s;
    ws.mu_eff_max[0] = std::max(ws.mu_eff_max[0], std::abs(dv.x() / dv.y()));
  }
}

/// The study of Study() on two surfaces alike: the second is a copy of steel's trials under
/// another name, drawn with their own scatter and error.
void TwoSurfaceStudy(Workspace& ws, double spring, std::uint64_t seed) {
  SteelStudy(ws, {0.0, 10.0, 20.0, 30.0}, 10, kZeta, kMu);
  ws.surfaces.push_back("steel_b");
  ws.k.push_back(ws.k[0]);
  ws.has_oblique.push_back(ws.has_oblique[0]);
  ws.zeta_start.push_back(kZeta);
  ws.mu_start.push_back(kMu);
  const std::size_t n = ws.obs.size();
  for (std::size_t i = 0; i < n; ++i) {
    Obs o = ws.obs[i];
    o.surface = 1;
    ws.obs.push_back(o);
  }
  Fit truth;
  truth.model.zeta = {kZeta, kZeta};
  truth.model.mu = {kMu, kMu};
  if (spring > 0) truth.model.effects["tangential_compliance"] = {EffectForm::kShared, {spring}};
  truth.noise.zeta_sd = {0.05, 0.05};
  truth.noise.mu_sd = {0.02, 0.02};
  truth.noise.systematic_sd.assign(2, Eigen::Vector3d::Constant(1e-3));
  const auto measured = SimulateStudy(ws, truth, seed);
  for (std::size_t i = 0; i < ws.obs.size(); ++i) ws.obs[i].measured = measured[i];
  ws.mu_eff_max = MuEffMax(ws);
}

CandidateResult Judge(const Workspace& ws, const std::string& key) {
  const Fit base = FitBaseline(ws);
  EXPECT_TRUE(base.ok) << base.message;
  DiscoveryOptions options;
  options.per_surface = false;
  return JudgeCandidate(ws, base, key, options, kLevel);
}

TEST(InfluenceTest, AnEffectThatOnlyOneTrialSpeaksForIsNotNamed) {
  Workspace ws;
  Study(ws, 0.0, 31);
  // One 10 deg trial at 4 m/s leaves with v_x and w d off by 2 % and 5 % of its impact speed,
  // as a trial that slid where the rest stuck (a scorecard study, one surface, showed this).
  std::size_t odd = 0;
  for (std::size_t i = 0; i < ws.obs.size(); ++i)
    if (ws.obs[i].angle_deg == 10.0) odd = i;
  ASSERT_EQ(ws.obs[odd].speed_m_s, 4.0);
  ws.obs[odd].measured[0] += 0.02 * ws.obs[odd].scale;
  ws.obs[odd].measured[2] += 0.05 * ws.obs[odd].scale;
  const CandidateResult c = Judge(ws, "tangential_compliance");
  std::cout << "p = " << c.p_value << ", without " << c.influential_trial
            << " p = " << c.p_without_influential << ": " << c.reason << "\n";
  // The case the check is for: significant, clear of 0, and lower held-out density, with that
  // one trial; not without it.
  EXPECT_LT(c.p_value, kLevel);
  EXPECT_EQ(c.influential_trial, "trial " + std::to_string(odd + 1));
  EXPECT_GE(c.p_without_influential, kLevel);
  EXPECT_FALSE(c.significant);
  EXPECT_EQ(c.outcome, CandidateOutcome::kRestsOnOneTrial);
}

/// The spring hidden in `ws` is named, and holds without the trial that gains most from it.
void ExpectSpringNamedWithoutItsMostInfluentialTrial(const Workspace& ws) {
  const CandidateResult c = Judge(ws, "tangential_compliance");
  std::cout << "k/k_t = " << c.estimate << " +- " << c.se << ", p = " << c.p_value << ", without "
            << c.influential_trial << " p = " << c.p_without_influential << "\n";
  EXPECT_TRUE(c.significant) << c.reason;
  EXPECT_FALSE(c.influential_trial.empty());
  EXPECT_LT(c.p_without_influential, kLevel);
  // Its size is not what this test asks: the spring's likelihood has several optima
  // (docs/discovery.md, "Local optima" under Limits), and a fit may land on another.
  EXPECT_GT(c.estimate, 0.0);
}

TEST(InfluenceTest, AnEffectThatEveryObliqueTrialShowsIsNamedWithoutAnyOneOfThem) {
  Workspace ws;
  Study(ws, 0.05, 31);
  ExpectSpringNamedWithoutItsMostInfluentialTrial(ws);
}

// An effect that every oblique trial of two surfaces shows holds without the trial that gains
// most from it, as on one surface.
TEST(InfluenceTest, AnEffectThatEveryObliqueTrialOfTwoSurfacesShowsIsStillNamed) {
  Workspace ws;
  TwoSurfaceStudy(ws, 0.05, 31);
  ExpectSpringNamedWithoutItsMostInfluentialTrial(ws);
}

// The alternation of Ceres solve and noise model is not monotone by itself: each solve lowers
// the residuals whitened by the covariance at its start, and where the trials' sensitivities to
// zeta and mu turn quickly (these 10 deg trials, between sticking and sliding) a step can lower
// the likelihood with the noise model re-estimated. FitModel steps back then, so a fit from any
// start ends at or above the likelihood of that start.
TEST(InfluenceTest, AFitNeverEndsBelowItsStart) {
  // Two studies on which, without the step back, the spring's fit from k/k_t = 0.02 ended 9.2
  // (spring 0.03 hidden, seed 2) and 3.1 (nothing hidden, seed 3) in 2 log-likelihood below
  // its start.
  int fits = 0;
  for (const auto& [spring, seed] : {std::pair{0.03, 2}, std::pair{0.0, 3}}) {
    Workspace ws;
    Study(ws, spring, static_cast<std::uint64_t>(seed));
    const auto all = ws.All();
    const Fit base = FitBaseline(ws);
    ASSERT_TRUE(base.ok) << base.message;
    for (const std::string key : {"tangential_compliance", "rolling_resistance"})
      for (double size : {0.02, 0.05, 0.2}) {
        Model start = base.model;
        start.effects[key] = {EffectForm::kShared, {size * Entry(key).probe}};
        const auto r = ws.Residuals(start, all);
        const auto sens = ws.Sensitivities(start, all);
        const Noise noise = EstimateNoise(ws, all, r, sens, base.noise);
        const double at_start = LogLikelihood(ws, all, r, sens, noise);
        const Fit f = FitModel(ws, all, start, {key}, noise, true);
        EXPECT_GE(f.loglik, at_start - 1e-9)
            << "seed " << seed << ": " << key << " from " << size * Entry(key).probe;
        ++fits;
      }
  }
  EXPECT_EQ(fits, 12);
}

}  // namespace
}  // namespace hoof::discovery::internal
