// The profile likelihood of one contact effect over its size, on a study file written by
// `hoofimpact analyze` (docs/discovery.md, "Fits"): the baseline (zeta and mu per surface, the
// noise model) is fitted as discovery fits it (FitBaseline); then, at each size, the effect is
// held there and zeta, mu and the noise model are refitted, from the baseline's mu and from each
// --mu-starts value (applied to every surface whose baseline mu lies above it). It prints
// 2 (log-likelihood - the baseline's) at each size and start, with the mu reached. A diagnostic
// for a fit that ends in the wrong optimum; it asserts nothing.
//
//   build/bench/discovery_profile STUDY_H5 [--effect KEY] [--sizes 0.01,0.02] [--mu-starts 0.3]
//                                 [--ladder N] [--held-out] [--split] [--trials N]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "discovery/internal.h"
#include "studyfile/study_file.h"

namespace {

using namespace hoof::discovery;
using namespace hoof::discovery::internal;

std::string Mus(const Fit& f) {
  std::string s;
  for (double m : f.model.mu) {
    if (!s.empty()) s.push_back(' ');
    s.append(Fmt(m, 3));
  }
  return s;
}

std::vector<TrialCovariance> CovariancesAt(const Workspace& ws, const Fit& f) {
  return Covariances(ws, ws.Sensitivities(f.model, ws.All()), f.noise);
}

/// Held-out errors of `fit` (its `free` effects refitted per fold, as discovery does): the mean
/// squared residual over the variance `base`'s noise model predicts (discovery's held-out error),
/// and the held-out density discovery judges a contact effect by (AddDensity: under `fit`'s own
/// noise model, nats per held-out trial, constants dropped).
std::pair<double, double> HeldOut(const Workspace& ws, const Fit& fit,
                                  const std::vector<std::string>& free, const Fit& base,
                                  int folds) {
  CrossValidation cv = CrossValidate(ws, fit, free, CovariancesAt(ws, base), folds);
  AddDensity(cv, CovariancesAt(ws, fit));
  return {cv.mean_error, cv.mean_density};
}

/// The command line.
struct ProfileArgs {
  std::string path, key = "tangential_compliance";
  std::vector<double> sizes{0.01, 0.016, 0.02, 0.032, 0.064, 0.1, 1.0};
  std::vector<double> mu_starts;
  int threads = 2;
  std::size_t ladder_peaks = 0;
  bool held_out = false, split = false;
  std::size_t trials_shown = 0;
};

void AddOptions(CLI::App& app, ProfileArgs& a) {
  app.add_option("study", a.path, "Study file (hoofimpact analyze)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--effect", a.key, "Library key of a contact effect");
  app.add_option("--sizes", a.sizes, "Sizes to hold the effect at (its own units)")->delimiter(',');
  app.add_option("--mu-starts", a.mu_starts,
                 "Further starts of mu (each surface whose baseline mu lies above it)")
      ->delimiter(',');
  app.add_option("--jobs", a.threads, "Threads")->check(CLI::Range(1, 256));
  app.add_option("--ladder", a.ladder_peaks,
                 "Also print the ladder's N largest local optima (the fit's starts are the first "
                 "3) with their linear gain, and the profile at each");
  app.add_flag("--held-out", a.held_out,
               "At each size, the effect's free fit from there and its held-out errors: in the "
               "baseline's covariance (discovery's rule) and as the negative log predictive "
               "density under each model's own");
  app.add_flag("--split", a.split,
               "At each size, the gain split into the part of the predictions (the effect's "
               "residuals in the baseline's covariance) and the part of the covariance (its own "
               "sensitivities and noise model), with the oblique trials' median |d prediction / "
               "d mu| under each");
  app.add_option("--trials", a.trials_shown,
                 "At each size, the N trials whose log-likelihood gains most (each model under its "
                 "own noise model), with the surface's systematic s.d. of v_x and w d under each: "
                 "what discovery's check without the most influential trial looks at");
}

/// The ladder's `peaks` largest local optima of the linear gain, as a round builds it (plan.cc)
/// at the baseline with its noise model, and the profile at each.
void PrintLadder(const Workspace& ws, const Fit& base, const std::string& key,
                 std::size_t ladder_peaks) {
  const LibraryEntry& e = Entry(key);
  const auto all = ws.All();
  const auto sens = ws.Sensitivities(base.model, all);
  const SizeLadder ladder = Ladder(ws, base.model, key, ws.Residuals(base.model, all), sens,
                                   Covariances(ws, sens, base.noise));
  std::printf("\nthe ladder's %zu sizes: its largest local optima of the linear gain\n",
              ladder.size.size());
  for (double size : LadderStarts(ladder, ladder_peaks)) {
    std::size_t k = 0;
    while (ladder.size[k] != size) ++k;
    const Eigen::VectorXd& b = ladder.projected[k];
    Model m = base.model;
    m.effects[key] = {EffectForm::kShared, {size}};
    const Fit f = FitModel(ws, all, m, {}, base.noise, true, 12);
    std::printf("  %s = %-8s linear gain %9.2f  profile 2 dlogL %9.2f\n", e.parameter.c_str(),
                Fmt(size, 3).c_str(), 2 * ladder.current.dot(b) - b.squaredNorm(),
                2 * (f.loglik - base.loglik));
  }
  std::printf("\n");
}

/// The gain of the fit `f` split into the part of the predictions (the effect's residuals in
/// the baseline's covariance) and the part of the covariance, with the oblique trials' median
/// |d prediction / d mu| under each.
void PrintSplit(const Workspace& ws, const Fit& base, const Fit& f) {
  const auto all = ws.All();
  const auto base_sens = ws.Sensitivities(base.model, all);
  const auto sens = ws.Sensitivities(f.model, all);
  const double in_base_cov =
      LogLikelihood(ws, all, ws.Residuals(f.model, all), base_sens, base.noise);
  auto median_mu_slope = [&](const std::vector<Sensitivity>& v) {
    std::vector<double> x;
    for (std::size_t i = 0; i < all.size(); ++i)
      if (!ws.obs[i].normal) x.push_back(v[i].col(1).norm());
    if (x.empty()) return 0.0;
    std::nth_element(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(x.size() / 2), x.end());
    return x[x.size() / 2];
  };
  // Oblique trials whose slope by mu differs from the baseline's by more than a factor 2
  // (a trial that sticks in one model and slides in the other).
  int apart = 0, oblique = 0;
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (ws.obs[i].normal) continue;
    ++oblique;
    const double a = sens[i].col(1).norm(), b = base_sens[i].col(1).norm();
    apart += a > 2 * b || b > 2 * a;
  }
  std::printf(
      "    of which the predictions %.2f, the covariance %.2f; oblique trials' median "
      "|d/d mu| %.4g (baseline %.4g), %d of %d apart by more than 2x\n",
      2 * (in_base_cov - base.loglik), 2 * (f.loglik - in_base_cov), median_mu_slope(sens),
      median_mu_slope(base_sens), apart, oblique);
}

/// The `trials_shown` trials whose log-likelihood gains most from `f` (each model under its own
/// sensitivities and noise model), largest first.
void PrintTrials(const Workspace& ws, const Fit& base, const Fit& f, std::size_t trials_shown) {
  const auto all = ws.All();
  const auto rb = ws.Residuals(base.model, all), rf = ws.Residuals(f.model, all);
  const auto sb = ws.Sensitivities(base.model, all), sf = ws.Sensitivities(f.model, all);
  std::vector<std::pair<double, std::size_t>> gain;
  for (std::size_t i = 0; i < all.size(); ++i) {
    const std::vector<int> one{all[i]};
    gain.emplace_back(2 * (LogLikelihood(ws, one, {rf[i]}, {sf[i]}, f.noise) -
                           LogLikelihood(ws, one, {rb[i]}, {sb[i]}, base.noise)),
                      i);
  }
  std::sort(gain.rbegin(), gain.rend());
  for (std::size_t k = 0; k < std::min(trials_shown, gain.size()); ++k) {
    const Obs& o = ws.obs[gain[k].second];
    const auto s = static_cast<std::size_t>(o.surface);
    std::printf(
        "    %-28s 2 dlogL %8.2f  e %.3f mu_eff %.3f  systematic v_x, w d %.4f, "
        "%.4f (baseline %.4f, %.4f)\n",
        o.trial->spec.id.c_str(), gain[k].first, o.trial->impact.e, o.trial->impact.mu_eff,
        f.noise.systematic_sd[s][0], f.noise.systematic_sd[s][2], base.noise.systematic_sd[s][0],
        base.noise.systematic_sd[s][2]);
  }
}

/// The effect's free fit from `f` and its held-out errors against the baseline's.
void PrintHeldOut(const Workspace& ws, const Fit& base, const Fit& f, const std::string& key,
                  int folds, double base_cv, double base_nlpd) {
  const auto all = ws.All();
  const Fit fr = FitModel(ws, all, f.model, {key}, f.noise, true, 12);
  const auto [cv_in_base, nlpd_own] = HeldOut(ws, fr, {key}, base, folds);
  std::printf(
      "    free fit -> %s, 2 dlogL %.2f; held-out error in the baseline's "
      "covariance %.3f (baseline %.3f); held-out -log density %.3f (baseline "
      "%.3f)\n",
      Fmt(fr.model.effects.at(key).value.at(0), 3).c_str(), 2 * (fr.loglik - base.loglik),
      cv_in_base, base_cv, nlpd_own, base_nlpd);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"The profile likelihood of one contact effect over its size on a study file"};
  ProfileArgs args;
  AddOptions(app, args);
  CLI11_PARSE(app, argc, argv);
  const auto& [path, key, sizes, mu_starts, threads, ladder_peaks, held_out, split, trials_shown] =
      args;
  try {
    const LibraryEntry& e = Entry(key);
    if (e.measurement_effect)
      throw std::invalid_argument("'" + key + "' is a measurement effect, not a contact effect");
    for (double size : sizes)
      if (!(size >= 0 && size <= e.upper))
        throw std::invalid_argument("--sizes: " + Fmt(size) + " is outside [0, " + Fmt(e.upper) +
                                    "]");
    const auto trials = hoof::studyfile::ReadTrialAnalyses(path);
    DiscoveryOptions options;
    options.jobs = threads;
    Workspace ws;
    int skipped = 0;
    Build(trials, options, &skipped, ws);
    // Discovery's own minimum.
    if (ws.obs.size() < 6)
      throw std::runtime_error(path + ": too few measured trials with a fitted surface model (" +
                               std::to_string(ws.obs.size()) + "; at least 6 are needed)");
    const auto all = ws.All();
    const Fit base = FitBaseline(ws);
    if (!base.ok) throw std::runtime_error(path + ": the baseline fit failed: " + base.message);
    std::printf("%s: %zu trials used, %d skipped; baseline log-likelihood %.3f\n", path.c_str(),
                ws.obs.size(), skipped, base.loglik);
    for (std::size_t s = 0; s < ws.surfaces.size(); ++s)
      std::printf("  %-9s zeta %.4f (s.d. %.4f)  mu %.4f (s.d. %.4f)  largest mu_eff %.3f\n",
                  ws.surfaces[s].c_str(), base.model.zeta[s], base.noise.zeta_sd[s],
                  base.model.mu[s], base.noise.mu_sd[s], ws.mu_eff_max[s]);
    std::printf("\n%s (%s) held at each size; 2 dlogL against the baseline, mu reached\n",
                e.parameter.c_str(), e.unit.c_str());
    if (ladder_peaks > 0) PrintLadder(ws, base, key, ladder_peaks);
    const int folds = options.folds;
    double base_cv = 0.0, base_nlpd = 0.0;
    if (held_out) std::tie(base_cv, base_nlpd) = HeldOut(ws, base, {}, base, folds);
    std::vector<double> starts{-1.0};  // -1: the baseline's mu
    starts.insert(starts.end(), mu_starts.begin(), mu_starts.end());
    for (double size : sizes) {
      for (double mu0 : starts) {
        Model m = base.model;
        if (mu0 > 0)
          for (double& mu : m.mu) mu = std::min(mu, mu0);
        m.effects[key] = {EffectForm::kShared, {size}};
        const Fit f = FitModel(ws, all, m, {}, base.noise, true, 12);
        std::printf("  %s = %-8s from mu %-9s  2 dlogL %9.2f  mu %s%s\n", e.parameter.c_str(),
                    Fmt(size, 3).c_str(), mu0 > 0 ? Fmt(mu0, 3).c_str() : "baseline",
                    2 * (f.loglik - base.loglik), Mus(f).c_str(), f.ok ? "" : "  (fit failed)");
        if (split && f.ok) PrintSplit(ws, base, f);
        if (trials_shown > 0 && f.ok) PrintTrials(ws, base, f, trials_shown);
        if (held_out && f.ok) PrintHeldOut(ws, base, f, key, folds, base_cv, base_nlpd);
      }
    }
  } catch (const std::exception& ex) {
    std::cerr << "discovery_profile: " << ex.what() << "\n";
    return 1;
  }
  return 0;
}
