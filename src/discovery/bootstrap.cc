// The parametric bootstrap of a detection plan (docs/discovery.md, "Detection limits and
// plans"): studies of the same trials simulated from the fitted baseline with an effect added,
// each trial with its own zeta and mu drawn from the noise model's scatter and its velocities
// with the measurement's error, and the candidate judged on each as a round of Discover would.
// The simulation is the full nonlinear one: where the noise model's linearisation in the
// scatter is poor, the bootstrap's power departs from the power the plan computes from it.
#include <algorithm>
#include <cmath>
#include <random>

#include "discovery/internal.h"
#include "dynamics/parameters.h"

namespace hoof::discovery::internal {
namespace {

/// A copy of `ws` whose measured velocities are `measured` (per obs, in S).
std::unique_ptr<Workspace> WithMeasured(const Workspace& ws,
                                        const std::vector<Eigen::Vector3d>& measured) {
  auto out = std::make_unique<Workspace>();
  out->obs = ws.obs;
  for (std::size_t i = 0; i < out->obs.size(); ++i) out->obs[i].measured = measured[i];
  out->surfaces = ws.surfaces;
  out->k = ws.k;
  out->has_oblique = ws.has_oblique;
  out->mu_eff_max = MuEffMax(*out);  // of the simulated velocities
  out->zeta_start = ws.zeta_start;
  out->mu_start = ws.mu_start;
  out->rtol = ws.rtol;
  out->measurement_floor = ws.measurement_floor;
  out->threads = ws.threads;
  out->counted_in = ws.counted_in ? ws.counted_in : &ws;
  return out;
}

}  // namespace

std::vector<double> MuEffMax(const Workspace& ws) {
  std::vector<double> out(ws.surfaces.size(), 0.0);
  for (const Obs& o : ws.obs) {
    if (o.normal) continue;
    const Eigen::Vector2d dv = o.measured.head<2>() - o.conditions.v_SC_m_s;
    const double mu_eff = std::abs(dv.x() / dv.y());
    auto& most = out.at(static_cast<std::size_t>(o.surface));
    if (std::isfinite(mu_eff)) most = std::max(most, mu_eff);
  }
  return out;
}

std::vector<Eigen::Vector3d> SimulateStudy(const Workspace& ws, const Fit& truth,
                                           std::uint64_t seed) {
  // The draws first, in obs order, from one generator: the same seed gives the same study
  // whatever the number of threads.
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> unit;
  const std::size_t n = ws.obs.size();
  std::vector<double> zeta(n), mu(n);
  std::vector<Eigen::Vector3d> error(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Obs& o = ws.obs[i];
    const auto s = static_cast<std::size_t>(o.surface);
    // The scatter is drawn in e, in which a trial's velocities are linear (v_y after a normal
    // impact is -e v_y before): the noise model's s.d. of zeta, turned into one of e through
    // the two-phase law's slope, describes the same scatter to first order, and is exact in e.
    const double z = truth.model.zeta[s], h = 1e-6 * std::max(z, 1e-3);
    const double slope = (dynamics::RestitutionOfTwoPhaseLaw(z + h) -
                          dynamics::RestitutionOfTwoPhaseLaw(std::max(0.0, z - h))) /
                         (z + h - std::max(0.0, z - h));
    const double e = dynamics::RestitutionOfTwoPhaseLaw(z) +
                     std::abs(slope) * truth.noise.zeta_sd[s] * unit(rng);
    zeta[i] = dynamics::DampingRatioFromRestitution(std::clamp(e, 0.01, 1.0));
    const double dm = truth.noise.mu_sd[s] * unit(rng);
    mu[i] = ws.has_oblique[s] ? std::max(0.0, truth.model.mu[s] + dm) : truth.model.mu[s];
    for (int c = 0; c < kComponents; ++c) {
      const double sys = truth.noise.systematic_sd[s][c];
      const double sd = std::sqrt(o.measurement_var[c] + sys * sys);
      error[i][c] = sd * unit(rng) * o.scale;
    }
  }
  std::vector<Eigen::Vector3d> measured(n);
  ws.ParallelFor(n, [&](std::size_t i) {
    const Obs& o = ws.obs[i];
    bool ok = false;
    const Eigen::Vector3d p =
        ws.Predict(o, zeta[i], mu[i], ws.Extensions(truth.model, o.surface), &ok);
    // A trial the simulator cannot run keeps its measured values (it counts as a misfit of
    // every model alike).
    measured[i] = ok ? Eigen::Vector3d(p + error[i]) : o.measured;
  });
  return measured;
}

double ExpectedNoncentrality(const Workspace& ws, const Fit& current,
                             const std::vector<std::string>& free_current, const std::string& key,
                             double size, int passes) {
  Model truth = current.model;
  truth.effects[key] = {EffectForm::kShared, {size}};
  const std::size_t n = ws.obs.size();
  std::vector<Eigen::Vector3d> expected(n);
  std::vector<char> ran(n, 0);
  ws.ParallelFor(n, [&](std::size_t i) {
    const Obs& o = ws.obs[i];
    const auto s = static_cast<std::size_t>(o.surface);
    bool ok = false;
    expected[i] = ws.Predict(o, truth.zeta[s], truth.mu[s], ws.Extensions(truth, o.surface), &ok);
    ran[i] = ok ? 1 : 0;
  });
  // A trial the simulator cannot run with the effect tells nothing about it: it keeps the
  // current model's own prediction.
  for (std::size_t i = 0; i < n; ++i)
    if (!ran[i]) {
      const Obs& o = ws.obs[i];
      const auto s = static_cast<std::size_t>(o.surface);
      bool ok = false;
      expected[i] = ws.Predict(o, current.model.zeta[s], current.model.mu[s],
                               ws.Extensions(current.model, o.surface), &ok);
      if (!ok) return kNaN;
    }
  const auto sim = WithMeasured(ws, expected);
  const std::vector<int> all = sim->All();
  const Fit back = FitModel(*sim, all, current.model, free_current, current.noise, false, passes);
  if (!back.ok) return kNaN;
  // Both in the truth's covariances: the misfit alone, as the tangent-plane noncentrality
  // measures it (a refitted model's own covariances would add the change of their determinant).
  const auto sens = sim->Sensitivities(truth, all);
  const double lambda =
      2 * (LogLikelihood(*sim, all, sim->Residuals(truth, all), sens, current.noise) -
           LogLikelihood(*sim, all, sim->Residuals(back.model, all), sens, current.noise));
  return std::isfinite(lambda) ? std::max(0.0, lambda) : kNaN;
}

BootstrapResult BootstrapDetection(const Workspace& ws, const Fit& baseline, const std::string& key,
                                   double size, double level, const DiscoveryOptions& options,
                                   int draws, const std::function<void(const std::string&)>& say) {
  BootstrapResult out;
  Fit truth = baseline;
  truth.model.effects[key] = {EffectForm::kShared, {size}};
  const Model start = baseline.model;
  for (int b = 0; b < draws; ++b) {
    const auto sim = WithMeasured(
        ws, SimulateStudy(ws, truth, 0x5EEDB007ULL + 0x9E3779B97F4A7C15ULL * (b + 1ULL)));
    const std::vector<int> all = sim->All();
    const Fit fitted = FitModel(*sim, all, start, {}, baseline.noise, true, 12);
    const CandidateResult c = JudgeCandidate(*sim, fitted, key, options, level);
    ++out.draws;
    out.detected += c.significant ? 1 : 0;
    out.lr_significant += c.p_value < level ? 1 : 0;
    out.estimates.push_back(c.estimate);
    if (say)
      say("  bootstrap study " + std::to_string(b + 1) + "/" + std::to_string(draws) + ": " +
          (c.significant ? "detected" : "not detected") + " (" + c.parameter + " = " +
          Fmt(c.estimate) + UnitSuffix(c.unit) + ", p = " + FmtP(c.p_value) + ")" +
          (c.significant || c.reason.empty() ? "" : ": " + c.reason));
  }
  return out;
}

}  // namespace hoof::discovery::internal
