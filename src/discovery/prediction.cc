// Each trial's prediction z under the baseline model (docs/discovery.md, "Prediction
// intervals"): the residual after the impact over the s.d. that the discovery noise model,
// refitted without the trial, gives a new trial of its surface and conditions.
#include <cmath>

#include "discovery/internal.h"

namespace hoof::discovery {

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
  for (std::size_t i = 0; i < ws.obs.size(); ++i) {
    const Obs& o = ws.obs[i];
    const TrialCovariance cov = Covariance(ws, o, sens[i], without[i]);
    TrialPrediction p;
    p.id = o.trial->spec.id;
    p.surface = ws.surfaces[static_cast<std::size_t>(o.surface)];
    p.angle_deg = o.angle_deg;
    p.speed_m_s = o.speed_m_s;
    for (std::size_t a = 0; a < cov.components.size(); ++a) {
      const int c = cov.components[a];
      const auto k = static_cast<Eigen::Index>(a);
      p.residual[c] = residuals[i][c];
      p.prediction_sd[c] = std::sqrt(cov.cov(k, k));
      p.z[c] = p.residual[c] / p.prediction_sd[c];
    }
    out.trials.push_back(p);
  }
  out.surfaces = SurfaceFits(ws, fit);
  out.success = fit.ok;
  if (!fit.ok) out.message = fit.message;
  return out;
}

}  // namespace hoof::discovery
