// Held-out errors of the discovery workflow (docs/discovery.md, "Candidates and the decision",
// step 5): each fold of trials predicted by a model fitted without it, in units of the variance
// the current model's noise model predicts for each trial (one scale for every model), and as
// a negative log density under the model's own noise model (what decides for a contact effect).
#include <cmath>
#include <numeric>

#include "discovery/internal.h"
#include "stats/distributions.h"

namespace hoof::discovery::internal {
namespace {

double MeanFinite(const std::vector<double>& v) {
  double s = 0;
  int n = 0;
  for (double e : v)
    if (std::isfinite(e)) s += e, ++n;
  return n ? s / n : kNaN;
}

}  // namespace

CrossValidation CrossValidate(const Workspace& ws, const Fit& start,
                              const std::vector<std::string>& free_effects,
                              const std::vector<TrialCovariance>& reference, int folds) {
  CrossValidation cv;
  cv.error.assign(ws.obs.size(), kNaN);
  cv.residual.assign(ws.obs.size(), Eigen::Vector3d::Constant(kNaN));
  for (int f = 0; f < folds; ++f) {
    std::vector<int> train, test;
    for (std::size_t i = 0; i < ws.obs.size(); ++i)
      (ws.obs[i].fold == f ? test : train).push_back(static_cast<int>(i));
    if (test.empty() || train.empty()) continue;
    // The noise model stays the full-data fit's: the fold changes what is predicted, not how
    // well a trial can be predicted.
    const Fit fit = FitModel(ws, train, start.model, free_effects, start.noise, false, 1);
    const auto r = ws.Residuals(fit.model, test);
    for (std::size_t j = 0; j < test.size(); ++j) {
      const auto i = static_cast<std::size_t>(test[j]);
      cv.residual[i] = r[j];
      const TrialCovariance& ref = reference[i];
      Eigen::VectorXd v(static_cast<Eigen::Index>(ref.components.size()));
      for (std::size_t a = 0; a < ref.components.size(); ++a)
        v[static_cast<Eigen::Index>(a)] = r[j][ref.components[a]];
      cv.error[i] = (ref.whiten * v).squaredNorm() / static_cast<double>(v.size());
    }
  }
  cv.mean_error = MeanFinite(cv.error);
  return cv;
}

void AddDensity(CrossValidation& cv, const std::vector<TrialCovariance>& own) {
  cv.density.assign(cv.residual.size(), kNaN);
  for (std::size_t i = 0; i < cv.residual.size() && i < own.size(); ++i) {
    const TrialCovariance& c = own[i];
    Eigen::VectorXd v(static_cast<Eigen::Index>(c.components.size()));
    for (std::size_t a = 0; a < c.components.size(); ++a)
      v[static_cast<Eigen::Index>(a)] = cv.residual[i][c.components[a]];
    if (v.size() > 0 && v.allFinite())
      cv.density[i] = 0.5 * (c.log_det + (c.whiten * v).squaredNorm());
  }
  cv.mean_density = MeanFinite(cv.density);
}

CrossValidation CrossValidateTilt(const Workspace& ws, bool free, int folds) {
  CrossValidation cv;
  cv.error.assign(ws.obs.size(), kNaN);
  cv.residual.assign(ws.obs.size(), Eigen::Vector3d::Constant(kNaN));
  // The scale of the marker distance ratio: its scatter about its own mean.
  std::vector<double> ratios;
  for (const Obs& o : ws.obs)
    if (std::isfinite(o.marker_ratio)) ratios.push_back(o.marker_ratio);
  double var = 1e-8;
  if (ratios.size() >= 2) {
    const double m =
        std::accumulate(ratios.begin(), ratios.end(), 0.0) / static_cast<double>(ratios.size());
    double ss = 0;
    for (double x : ratios) ss += (x - m) * (x - m);
    var = std::max(ss / static_cast<double>(ratios.size() - 1), 1e-14);
  }
  for (int f = 0; f < folds; ++f) {
    std::vector<int> train;
    for (std::size_t i = 0; i < ws.obs.size(); ++i)
      if (ws.obs[i].fold != f) train.push_back(static_cast<int>(i));
    const TiltFit t = FitTilt(ws, train, free);
    for (std::size_t i = 0; i < ws.obs.size(); ++i) {
      const Obs& o = ws.obs[i];
      if (o.fold != f || !std::isfinite(o.marker_ratio)) continue;
      const double r = o.marker_ratio - std::cos(t.tilt_rad);
      cv.residual[i] = {r, kNaN, kNaN};
      cv.error[i] = r * r / var;
    }
  }
  cv.mean_error = MeanFinite(cv.error);
  return cv;
}

double PairedImprovementP(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> d;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::isfinite(a[i]) && std::isfinite(b[i])) d.push_back(a[i] - b[i]);
  if (d.size() < 3) return 1.0;
  const double n = static_cast<double>(d.size());
  const double m = std::accumulate(d.begin(), d.end(), 0.0) / n;
  double ss = 0;
  for (double x : d) ss += (x - m) * (x - m);
  const double se = std::sqrt(ss / (n - 1) / n);
  if (!(se > 0)) return m > 0 ? 0.0 : 1.0;
  const double p2 = stats::TTwoSided(m / se, n - 1);
  return m > 0 ? p2 / 2 : 1 - p2 / 2;
}

double Rms(const Eigen::Vector3d& r) {
  double s = 0;
  int n = 0;
  for (int c = 0; c < kComponents; ++c)
    if (std::isfinite(r[c])) s += r[c] * r[c], ++n;
  return n ? std::sqrt(s / n) : kNaN;
}

}  // namespace hoof::discovery::internal
