// Each trial's prediction z under the baseline model (docs/discovery.md, "Prediction
// intervals"): the residual after the impact over the s.d. that the discovery noise model,
// refitted without the trial, gives a new trial of its surface and conditions (with the fitted
// means' own error), as a t on the surface's degrees of freedom, given as the normal z of the
// same tail probability.
#include <cmath>
#include <limits>

#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>

#include "discovery/internal.h"

namespace hoof::discovery {

double NormalEquivalent(double t, int dof) {
  if (!std::isfinite(t) || dof < 1) return core::kNaN;
  const boost::math::students_t student(dof);
  // The upper tail of |t|, complemented for precision far out; then the z with the same tail.
  const double tail = boost::math::cdf(boost::math::complement(student, std::abs(t)));
  if (tail <= 0.0) return std::copysign(std::numeric_limits<double>::infinity(), t);
  const double z = boost::math::quantile(boost::math::complement(boost::math::normal(), tail));
  return std::copysign(z, t);
}

BaselinePredictions PredictBaseline(const std::vector<pipeline::TrialAnalysis>& trials,
                                    const DiscoveryOptions& options) {
  using namespace internal;
  options.Validate();
  BaselinePredictions out;
  Workspace ws;
  Build(trials, options, &out.trials_skipped, ws);
  if (ws.obs.size() < 6) {
    out.message = "too few measured trials with a fitted surface model (" +
                  std::to_string(ws.obs.size()) + "; at least 6 are needed)";
    return out;
  }
  const std::vector<int> all = ws.All();
  const Fit fit = FitBaseline(ws);
  const std::vector<Eigen::Vector3d> residuals = ws.Residuals(fit.model, all);
  const std::vector<Sensitivity> sens = ws.Sensitivities(fit.model, all);
  // Each trial's interval from the noise model refitted without it (the model's zeta and mu
  // kept): a trial far off would otherwise widen its own interval (one trial's v_y raised by 0.3
  // of the impact speed raised the shared v_y error and its surface's zeta scatter until its z
  // was 2.95). The refits need no simulation: residuals and sensitivities are the full fit's.
  std::vector<Noise> without(ws.obs.size());
  ws.ParallelFor(ws.obs.size(), [&](std::size_t i) {
    std::vector<int> others;
    std::vector<Eigen::Vector3d> r;
    std::vector<Sensitivity> s;
    for (std::size_t j = 0; j < ws.obs.size(); ++j)
      if (j != i) {
        others.push_back(all[j]);
        r.push_back(residuals[j]);
        s.push_back(sens[j]);
      }
    without[i] = EstimateNoise(ws, others, r, s, fit.noise);
  });
  // Trials per surface: the degrees of freedom of a trial's t are its surface's other trials
  // less the surface's mean parameters (zeta, and mu where it has oblique trials).
  std::vector<int> per_surface(ws.surfaces.size(), 0);
  for (const Obs& o : ws.obs) ++per_surface[static_cast<std::size_t>(o.surface)];
  for (std::size_t i = 0; i < ws.obs.size(); ++i) {
    const Obs& o = ws.obs[i];
    const auto surface = static_cast<std::size_t>(o.surface);
    const TrialCovariance cov = Covariance(ws, o, sens[i], without[i]);
    // The fitted means' own error: a new trial is predicted from estimates, not from the truth.
    const double zeta_se = std::isfinite(fit.zeta_se[surface]) ? fit.zeta_se[surface] : 0.0;
    const double mu_se = std::isfinite(fit.mu_se[surface]) ? fit.mu_se[surface] : 0.0;
    TrialPrediction p;
    p.id = o.trial->spec.id;
    p.surface = ws.surfaces[static_cast<std::size_t>(o.surface)];
    p.angle_deg = o.angle_deg;
    p.speed_m_s = o.speed_m_s;
    p.dof = per_surface[surface] - 1 - (ws.has_oblique[surface] ? 2 : 1);
    for (std::size_t a = 0; a < cov.components.size(); ++a) {
      const int c = cov.components[a];
      const auto k = static_cast<Eigen::Index>(a);
      p.residual[c] = residuals[i][c];
      const double mean_var =
          std::pow(sens[i](c, 0) * zeta_se, 2) + std::pow(sens[i](c, 1) * mu_se, 2);
      p.prediction_sd[c] = std::sqrt(cov.cov(k, k) + mean_var);
      p.t[c] = p.residual[c] / p.prediction_sd[c];
      p.z[c] = NormalEquivalent(p.t[c], p.dof);
    }
    out.trials.push_back(p);
  }
  out.surfaces = SurfaceFits(ws, fit);
  out.success = fit.ok;
  if (!fit.ok) out.message = fit.message;
  return out;
}

}  // namespace hoof::discovery
