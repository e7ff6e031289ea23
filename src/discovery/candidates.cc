// One candidate of a round of the discovery workflow (docs/discovery.md, "Candidates and the
// decision"): fitted against the current model, shared or per surface, tested by its likelihood
// ratio under the noise model, cross-validated, probed for identifiability, and judged. The
// round's choice among them is in round.cc.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <numeric>
#include <sstream>

#include <boost/math/distributions/normal.hpp>

#include "discovery/evaluation.h"
#include "discovery/internal.h"
#include "stats/distributions.h"

namespace hoof::discovery::internal {
namespace {

std::string Moved(const Workspace& ws, const Fit& probe, const Fit& current) {
  bool zeta = false, mu = false;
  for (std::size_t s = 0; s < ws.surfaces.size(); ++s) {
    zeta |= std::abs(probe.model.zeta[s] - current.model.zeta[s]) > 1e-3 * current.model.zeta[s];
    mu |= ws.has_oblique[s] && std::abs(probe.model.mu[s] - current.model.mu[s]) > 1e-3;
  }
  if (zeta && mu) return "a changed zeta and a changed mu";
  if (zeta) return "a changed zeta";
  if (mu) return "a changed mu";
  return "the baseline";
}

/// p of a Wald test that the values (each with its s.e.) are equal: the chi-square of their
/// departures from the weighted mean, with one dof fewer than values with an s.e.
double EqualityP(const std::vector<EffectValue>& values) {
  double sw = 0.0, swv = 0.0;
  int n = 0;
  for (const auto& v : values)
    if (v.se > 0) sw += 1 / (v.se * v.se), swv += v.value / (v.se * v.se), ++n;
  if (n < 2) return 1.0;
  double chi2 = 0.0;
  for (const auto& v : values)
    if (v.se > 0) chi2 += std::pow(v.value - swv / sw, 2) / (v.se * v.se);
  return stats::ChiSquaredUpperTail(chi2, n - 1);
}

}  // namespace

std::vector<EffectValue> EffectValues(const Workspace& ws, const Fit& f, const std::string& key) {
  std::vector<EffectValue> out;
  const auto it = f.model.effects.find(key);
  if (it == f.model.effects.end()) return out;
  const auto se = f.effect_se.find(key);
  for (std::size_t k = 0; k < it->second.value.size(); ++k) {
    EffectValue v;
    v.key = key;
    if (it->second.form == EffectForm::kPerSurface) v.surface = ws.surfaces[k];
    v.value = it->second.value[k];
    v.se = se != f.effect_se.end() && k < se->second.size() ? se->second[k] : kNaN;
    out.push_back(v);
  }
  return out;
}

namespace {

/// An effect (of any kind) was added in an earlier round.
bool LaterRound(const RoundContext& x) { return !x.state.accepted.empty(); }

}  // namespace

/// A rotation rate (out_of_plane.cc), with the held-out gap of the velocities it would bring.
Evaluation EvaluateRate(const RoundContext& x, const std::string& key) {
  Evaluation ev;
  RateEvaluation re = EvaluateRotationRate(x.ws, x.state, key, x.free_current, x.level, x.options);
  ev.c = re.c;
  ev.fit = re.fit;
  ev.motion = re.motion;
  ev.remeasured = re.remeasured;
  ev.remeasured_ws = re.ws;
  // The held-out gap of the velocities, should it be added: the current model's predictions
  // of the re-measured trials, each fitted without its fold.
  if (ev.c.significant && re.ws) {
    const auto s_new = re.ws->Sensitivities(re.fit.model, x.all);
    ev.velocity_cv = CrossValidate(*re.ws, re.fit, x.free_current,
                                   Covariances(*re.ws, s_new, re.fit.noise), x.options.folds);
  }
  return ev;
}

constexpr const char* kBallGap = "does not apply to a ball";
constexpr const char* kUnmarkedGap = "not measured on bodies without markers";

std::string OutOfPlaneGap(const Workspace& ws) {
  int balls = 0, outlines = 0;
  for (const Obs& o : ws.obs) {
    const pipeline::TrialSpec& spec = o.trial->spec;
    if (!spec.body.is_silhouette() && spec.specimen.markers_B_m.size() >= 2) return "";
    (spec.body.is_ball() || spec.specimen.is_ball() ? balls : outlines) += 1;
  }
  if (balls + outlines == 0) return "";
  if (outlines == 0)
    return std::string(kBallGap) +
           ": its rotation is not seen, and it carries no markers whose projected distance "
           "would show a tilt";
  const std::string bodies = (balls > 0 ? std::to_string(balls) + " ball(s) and " : std::string()) +
                             std::to_string(outlines) + " unmarked outline(s)";
  return std::string(kUnmarkedGap) + " (" + bodies +
         "): the out-of-plane check reads the projected distance of the markers";
}

bool IsOutOfPlaneGap(const std::string& message) {
  return message.starts_with(kBallGap) || message.starts_with(kUnmarkedGap);
}

Evaluation NotApplicable(const std::string& key, const std::string& why) {
  Evaluation ev;
  ev.c = CandidateOf(key);
  ev.c.message = why;
  ev.c.identifiability = Identifiability::kNotTested;
  ev.c.outcome = CandidateOutcome::kNotTested;
  ev.c.reason = "not tested: " + why;
  return ev;
}

/// The constant out-of-plane tilt, judged on the marker distance alone.
Evaluation EvaluateTilt(const RoundContext& x, const std::string& key) {
  Evaluation ev;
  ev.c = CandidateOf(key);
  CandidateResult& c = ev.c;
  if (x.n_ratio < 3) {
    c.message = "fewer than 3 trials with a marker distance";
    c.identifiability = Identifiability::kNotTested;
    c.outcome = CandidateOutcome::kNotTested;
    c.reason = "not tested: " + c.message;
    return ev;
  }
  const TiltFit tf = FitTilt(x.ws, x.all, true);
  ev.tilt = tf;
  c.fitted = true;
  c.estimate = tf.tilt_rad * 180 / std::numbers::pi;
  c.se = tf.tilt_se_rad * 180 / std::numbers::pi;
  c.values = {EffectValue{key, "", c.estimate, c.se}};
  c.lr_statistic = std::max(0.0, 2 * (tf.loglik - x.state.tilt.loglik));
  c.p_value = ChiBarSquareUpperTail(c.lr_statistic, 1);
  c.delta_aic = -c.lr_statistic + 2;
  c.delta_bic = -c.lr_statistic + std::log(static_cast<double>(x.n_ratio));
  ev.cv = CrossValidateTilt(x.ws, true, x.options.folds);
  c.cv_error = ev.cv.mean_error;
  c.cv_error_current = x.cv_tilt_current.mean_error;
  c.cv_p = PairedImprovementP(x.cv_tilt_current.error, ev.cv.error);
  c.identifiability = Identifiability::kIdentified;
  // A tilt too small to tell from the calibration's own limits is not named.
  const bool beyond = 1 - std::cos(tf.tilt_rad) > x.options.marker_ratio_tolerance;
  c.significant = c.p_value < x.level && HeldOutFell(c) && beyond;
  if (!beyond && c.p_value < x.level) {
    c.outcome = CandidateOutcome::kBelowResolution;
    c.reason = "p = " + FmtP(c.p_value) + ", but the tilt of " + Fmt(c.estimate, 2) +
               " deg changes the marker distance by less than the calibration's tolerance (" +
               Fmt(x.options.marker_ratio_tolerance) + ")";
  }
  return ev;
}

namespace {

/// mu at the second start of a friction-limited effect, over the surface's largest measured
/// mu_eff: above every trial's need to stick, and low enough that the effect's slip reaches it.
constexpr double kFrictionLimitedStart = 1.5;

/// The starts of a contact effect's fit where no size of its ladder gains
/// (LibraryEntry::starts_without_gain).
std::vector<double> StartsWithoutGain(const LibraryEntry& e) {
  const double hi = 0.1 * e.probe;
  if (e.starts_without_gain <= 1) return {hi};
  const double lo = e.smallest > 0 ? e.smallest : 1e-3 * e.probe;
  std::vector<double> starts;
  for (int k = 0; k < e.starts_without_gain; ++k)
    starts.push_back(lo * std::pow(hi / lo, static_cast<double>(k) / (e.starts_without_gain - 1)));
  return starts;
}

/// The sizes of LibraryEntry::profile_sizes at the two best local maxima of the effect's profile
/// likelihood (none for an effect without a profile).
std::vector<double> ProfileStarts(const RoundContext& x, const LibraryEntry& e) {
  const int n = e.profile_sizes;
  if (n < 2 || !(e.smallest > 0)) return {};
  const Fit& current = x.state.current;
  // Evenly in u = size^-1/2, from the smallest size (largest u) to a tenth of the probe.
  const double u_first = 1 / std::sqrt(e.smallest), u_last = 1 / std::sqrt(0.1 * e.probe);
  std::vector<double> size(static_cast<std::size_t>(n)), loglik(size.size());
  for (std::size_t k = 0; k < size.size(); ++k) {
    const double u = u_first + (u_last - u_first) * static_cast<double>(k) / (n - 1);
    size[k] = 1 / (u * u);
    Model held = current.model;
    held.effects[e.key] = {EffectForm::kShared, {size[k]}};
    const Fit f = FitModel(x.ws, x.all, held, x.free_current, current.noise, true, 1);
    loglik[k] = f.ok ? f.loglik : -std::numeric_limits<double>::infinity();
  }
  std::vector<std::size_t> peaks;
  for (std::size_t k = 0; k < size.size(); ++k)
    if (std::isfinite(loglik[k]) && (k == 0 || loglik[k] >= loglik[k - 1]) &&
        (k + 1 == size.size() || loglik[k] > loglik[k + 1]))
      peaks.push_back(k);
  std::stable_sort(peaks.begin(), peaks.end(),
                   [&](std::size_t a, std::size_t b) { return loglik[a] > loglik[b]; });
  if (peaks.size() > 2) peaks.resize(2);
  std::vector<double> starts;
  for (std::size_t k : peaks) starts.push_back(size[k]);
  return starts;
}

/// A contact effect's free fit, shared by all surfaces, from the best of the starts: the
/// ladder's three largest optima (or StartsWithoutGain when no size gains), each also from a
/// lowered mu for a friction-limited effect, the best sizes of its profile (ProfileStarts, or an
/// earlier round's, RoundState::profile_starts; those profiled here are returned in `profiled`),
/// and the probe's fit. An optimum elsewhere that fits nearly as well is described in
/// `other_optimum`.
Fit FitFromStarts(const RoundContext& x, const std::string& key, const Fit& probe,
                  const std::vector<std::string>& free, std::string& other_optimum,
                  std::vector<double>& profiled) {
  const LibraryEntry& e = Entry(key);
  const Fit& current = x.state.current;
  std::vector<double> starts = LadderStarts(x.probes.ladder.at(key), 3);
  if (starts.empty()) starts = StartsWithoutGain(e);
  // Where every trial of a surface sticks, its mu is not identified and no fit moves it; an
  // effect that slips where the rigid contact sticks also starts from a mu the trials allow
  // but a slip can reach (LibraryEntry::friction_limited).
  std::vector<Model> bases{current.model};
  std::vector<std::vector<double>> base_starts{starts};
  if (e.friction_limited) {
    Model lowered = current.model;
    bool any = false;
    for (std::size_t s = 0; s < lowered.mu.size(); ++s) {
      const double mu = kFrictionLimitedStart * x.ws.mu_eff_max[s];
      if (x.ws.has_oblique[s] && mu > 0 && mu < lowered.mu[s]) lowered.mu[s] = mu, any = true;
    }
    if (any) {
      // Its own ladder: at the baseline's mu the change may gain at no size at all.
      const auto r = x.ws.Residuals(lowered, x.all);
      const auto sens = x.ws.Sensitivities(lowered, x.all);
      std::vector<double> own = LadderStarts(
          Ladder(x.ws, lowered, key, r, sens, Covariances(x.ws, sens, current.noise)), 3);
      if (own.empty()) own = StartsWithoutGain(e);
      bases.push_back(lowered);
      base_starts.push_back(own);
    }
  }
  // The profile's starts: from an earlier round where one profiled it, else profiled now.
  const auto earlier = x.state.profile_starts.find(key);
  if (earlier != x.state.profile_starts.end()) {
    for (double size : earlier->second) base_starts[0].push_back(size);
  } else {
    profiled = ProfileStarts(x, e);
    for (double size : profiled) base_starts[0].push_back(size);
  }
  Fit chosen;
  bool first = true;
  std::vector<Fit> optima;
  for (std::size_t b = 0; b < bases.size(); ++b)
    for (double size : base_starts[b]) {
      const Model& base = bases[b];
      Model start = base;
      start.effects[key] = {EffectForm::kShared, {size}};
      Fit f = FitModel(x.ws, x.all, start, free, current.noise, true);
      if (f.ok) optima.push_back(f);
      if (first || f.loglik > chosen.loglik) chosen = std::move(f);
      first = false;
    }
  if (probe.loglik > chosen.loglik)
    chosen = FitModel(x.ws, x.all, probe.model, free, probe.noise, true);
  // An optimum elsewhere that the likelihood cannot tell from the best (2 log-likelihood
  // within the 95 % point of chi-square 1): the s.e. describes one optimum, not the choice.
  if (chosen.ok) {
    const double best = chosen.model.effects.at(key).value.at(0);
    const double se = chosen.effect_se.count(key) ? chosen.effect_se.at(key).at(0) : kNaN;
    for (const Fit& f : optima) {
      const double v = f.model.effects.at(key).value.at(0);
      const double gap = 2 * (chosen.loglik - f.loglik);
      const double apart = std::max(0.01 * best, std::isfinite(se) ? 5 * se : 0.0);
      if (std::abs(v - best) > apart && gap >= 0 && gap < x.chi95 && other_optimum.empty())
        other_optimum = "another optimum, " + e.parameter + " = " + Fmt(v, 3) + UnitSuffix(e.unit) +
                        ", fits nearly as well (2 log-likelihood " + Fmt(gap, 2) +
                        " lower): the size is uncertain between them";
    }
  }
  return chosen;
}

/// The log-likelihood a candidate's fit is compared with. Its fit may have found zeta, mu and
/// the noise model a better optimum than the current fit did; the reference is then the current
/// model refitted from there, so that a gain of the baseline's own parameters is not credited to
/// the effect.
double ReferenceLogLikelihood(const RoundContext& x, const std::string& key, const Fit& chosen,
                              const Fit& current, const std::vector<int>& which) {
  double reference = current.loglik;
  Model back = chosen.model;
  back.effects.erase(key);
  const Fit again = FitModel(x.ws, which, back, x.free_current, chosen.noise, true);
  if (again.ok && again.loglik > reference) reference = again.loglik;
  // And the candidate's own solution with the effect removed, as it stands: the alternation
  // of model and noise is not monotone, so a refit from a point can end below it.
  const auto r_back = x.ws.Residuals(back, which);
  const auto s_back = x.ws.Sensitivities(back, which);
  const Noise n_back = EstimateNoise(x.ws, which, r_back, s_back, chosen.noise);
  return std::max(reference, LogLikelihood(x.ws, which, r_back, s_back, n_back));
}
double ReferenceLogLikelihood(const RoundContext& x, const std::string& key, const Fit& chosen) {
  return ReferenceLogLikelihood(x, key, chosen, x.state.current, x.all);
}

/// The obs whose log-likelihood gains most from `chosen` against the current model (each under
/// its own noise model), and its evidence without that obs: the likelihood-ratio p with the
/// current model and the candidate both refitted from their full-data fits on the other obs.
/// A systematic error per surface is shared by its trials, so a single trial that the current
/// model cannot follow (a 10 deg trial that slid where the rest stuck, say) raises it for every
/// trial of its surface, and an effect that explains that one trial gains on all of them.
void CheckInfluence(const RoundContext& x, const std::string& key,
                    const std::vector<std::string>& free, const Fit& chosen, CandidateResult& c) {
  const Fit& current = x.state.current;
  const auto r = x.ws.Residuals(chosen.model, x.all);
  const auto sens = x.ws.Sensitivities(chosen.model, x.all);
  std::size_t most = 0;
  double gain_most = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < x.all.size(); ++i) {
    const std::vector<int> one{x.all[i]};
    const double gain =
        LogLikelihood(x.ws, one, {r[i]}, {sens[i]}, chosen.noise) -
        LogLikelihood(x.ws, one, {x.residual_current[i]}, {x.sens[i]}, current.noise);
    if (gain > gain_most) gain_most = gain, most = i;
  }
  std::vector<int> without;
  for (std::size_t i = 0; i < x.all.size(); ++i)
    if (i != most) without.push_back(x.all[i]);
  const Fit base = FitModel(x.ws, without, current.model, x.free_current, current.noise, true);
  const Fit with = FitModel(x.ws, without, chosen.model, free, chosen.noise, true);
  const double reference = ReferenceLogLikelihood(x, key, with, base, without);
  const Obs& o = x.ws.obs[static_cast<std::size_t>(x.all[most])];
  c.influential_trial = o.trial ? o.trial->spec.id : "trial " + std::to_string(x.all[most] + 1);
  c.p_without_influential =
      ChiBarSquareUpperTail(std::max(0.0, 2 * (with.loglik - reference)), c.df);
}

/// Per surface against shared: a likelihood ratio with S - 1 degrees of freedom, and a Wald
/// test that the values differ. Sets `c.p_per_surface`, and `c.form`, `c.df` and `chosen` when
/// the per-surface form wins.
void ChooseForm(const RoundContext& x, const std::string& key, const std::vector<std::string>& free,
                Fit& chosen, CandidateResult& c) {
  const std::size_t S = x.ws.surfaces.size();
  Model ps = chosen.model;
  ps.effects[key] = {EffectForm::kPerSurface,
                     std::vector<double>(S, chosen.model.effects[key].value.at(0))};
  const Fit per = FitModel(x.ws, x.all, ps, free, chosen.noise, true);
  // As against the current model: the shared form refitted from the per-surface solution,
  // so that the comparison is of the two forms, not of the optima of zeta, mu and the noise
  // that each fit happened to reach.
  if (per.ok) {
    Model back = per.model;
    const auto& v = per.model.effects.at(key).value;
    back.effects[key] = {
        EffectForm::kShared,
        {std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size())}};
    const Fit again = FitModel(x.ws, x.all, back, free, per.noise, true);
    if (again.ok && again.loglik > chosen.loglik) chosen = again;
  }
  const double lr_ps = std::max(0.0, 2 * (per.loglik - chosen.loglik));
  c.p_per_surface = stats::ChiSquaredUpperTail(lr_ps, static_cast<double>(S - 1));
  // And the values themselves must differ: a Wald test of their equality (chi-square with
  // S - 1 dof). The likelihood ratio alone also rewards the other optimum of zeta, mu and
  // the noise that a per-surface fit can reach with equal values.
  c.p_per_surface = std::max(c.p_per_surface, EqualityP(EffectValues(x.ws, per, key)));
  if (per.ok && per.loglik > chosen.loglik && c.p_per_surface < x.options.alpha) {
    chosen = per;
    c.form = EffectForm::kPerSurface;
    c.df = static_cast<int>(S);
  }
}

/// The fitted effect's values (the largest as the estimate), and its likelihood ratio against
/// the `reference` log-likelihood with its p, AIC and BIC.
void FitStatistics(const RoundContext& x, const std::string& key, const Fit& chosen,
                   double reference, CandidateResult& c) {
  c.fitted = chosen.ok;
  c.message = chosen.message;
  c.values = EffectValues(x.ws, chosen, key);
  c.estimate = kNaN;
  c.se = kNaN;
  for (const auto& v : c.values)
    if (!std::isfinite(c.estimate) || v.value > c.estimate) c.estimate = v.value, c.se = v.se;
  c.lr_statistic = std::max(0.0, 2 * (chosen.loglik - reference));
  c.p_value = ChiBarSquareUpperTail(c.lr_statistic, c.df);
  c.delta_aic = -c.lr_statistic + 2 * c.df;
  c.delta_bic = -c.lr_statistic + c.df * std::log(x.n_res);
}

/// The candidate's held-out predictions (cross-validated, or the current model's at 0) and
/// their comparison with the current model's. At 0 the candidate is the current model, and so
/// are its held-out predictions. Its held-out density is under its own noise model: an effect
/// that explains part of the trial-to-trial scatter predicts held-out trials with less of it.
void HeldOut(const RoundContext& x, const Fit& chosen, const std::vector<std::string>& free,
             bool at_zero, Evaluation& ev) {
  CandidateResult& c = ev.c;
  if (at_zero) {
    ev.cv = x.cv_current;
  } else {
    ev.cv = CrossValidate(x.ws, chosen, free, x.ref, x.options.folds);
    AddDensity(ev.cv, Covariances(x.ws, x.ws.Sensitivities(chosen.model, x.all), chosen.noise));
  }
  c.cv_error = ev.cv.mean_error;
  c.cv_error_current = x.cv_current.mean_error;
  c.cv_density = ev.cv.mean_density;
  c.cv_density_current = x.cv_current.mean_density;
  c.cv_p = PairedImprovementP(x.cv_current.density, ev.cv.density);
}

/// Whether some value stands clear of `smallest` by its own s.e. (one-sided Wald at
/// `level`).
bool ClearOfSmallest(const std::vector<EffectValue>& values, double smallest, double level) {
  const boost::math::normal z;
  const double z_level = boost::math::quantile(boost::math::complement(z, level));
  bool clear = false;
  for (const auto& v : values) clear |= v.se > 0 && (v.value - smallest) / v.se > z_level;
  return clear;
}

}  // namespace

/// A contact effect: probed for identifiability, fitted (shared, then per surface), tested by
/// its likelihood ratio, cross-validated, and checked to stand clear of 0.
Evaluation EvaluateContact(const RoundContext& x, const std::string& key) {
  const LibraryEntry& e = Entry(key);
  const Fit& current = x.state.current;
  Evaluation ev;
  ev.c = CandidateOf(key);
  CandidateResult& c = ev.c;
  // Identifiability probe: the effect fixed at a realistic size, first without refitting (is
  // any trial sensitive to it?), then with zeta and mu refitted (do they absorb it?).
  Model probe_start = current.model;
  probe_start.effects[key] = {EffectForm::kShared, {e.probe}};
  const double fixed_lr =
      2 * (LogLikelihood(x.ws, x.all, x.probes.residual_probe.at(key), x.sens, current.noise) -
           current.loglik);
  const Fit probe = FitModel(x.ws, x.all, probe_start, x.free_current, current.noise, true, 4);
  const double probe_lr = 2 * (probe.loglik - current.loglik);
  std::vector<std::string> free = x.free_current;
  free.push_back(key);
  Fit chosen = FitFromStarts(x, key, probe, free, ev.other_optimum, ev.profile_starts);
  const double reference = ReferenceLogLikelihood(x, key, chosen);
  // The current model is this one with the effect at 0: a fit that ends below the reference
  // stopped in a worse local optimum, and the nested point is the better answer.
  bool at_zero = false;
  if (!(chosen.loglik >= reference)) {
    at_zero = true;
    chosen = current;
    chosen.model.effects[key] = {EffectForm::kShared, {0.0}};
    chosen.effect_se[key] = {kNaN};
  }
  c.form = EffectForm::kShared;
  c.df = 1;
  if (x.options.per_surface && x.ws.surfaces.size() > 1 && chosen.ok && !at_zero)
    ChooseForm(x, key, free, chosen, c);
  FitStatistics(x, key, chosen, reference, c);
  HeldOut(x, chosen, free, at_zero, ev);
  // A significant likelihood ratio is itself the evidence that the data tell the effect from
  // zeta and mu (they were refitted); only a candidate without it is probed further.
  // So is a gain of the fit at its own estimate that the probe's size falls short of: data
  // that answer with a likelihood ratio beyond chi^2_1(0.95) are sensitive to the effect (at a
  // size other than the probe's), and "not tested" beside that p would contradict it.
  c.identifiability = c.p_value < x.level || c.lr_statistic >= x.chi95
                          ? Identifiability::kIdentified
                      : std::abs(fixed_lr) < x.chi95 ? Identifiability::kNotTested
                      : std::abs(probe_lr) < x.chi95 ? Identifiability::kConfounded
                                                     : Identifiability::kIdentified;
  if (c.identifiability == Identifiability::kConfounded)
    c.confounded_with = Moved(x.ws, probe, current);
  // Detection limit: from the study's expected data with the effect at the ladder's sizes.
  c.detection_limit =
      ExpectedDetectionLimit(x.ws, current, x.free_current, key, x.probes.ladder.at(key), x.level);
  // The estimate must also stand clear of 0 by its own standard error (one-sided Wald at the
  // naming level, per value for a per-surface effect): a likelihood ratio whose effect is
  // 0.4 s.e. from 0 is a gain of the other parameters, and naming it would contradict the
  // estimate printed beside it. Clear of the smallest value the fit may take, where that is
  // above 0: an estimate on it says the data want less of the effect than the library can
  // represent, and the step from 0 to it is no evidence of the effect.
  c.wald_clear = ClearOfSmallest(c.values, e.smallest, x.level / c.df);
  if (ContactEvidenceHolds(c, x.level, LaterRound(x))) CheckInfluence(x, key, free, chosen, c);
  c.significant = ContactEvidenceHolds(c, x.level, LaterRound(x));
  ev.fit = chosen;
  ev.free = free;
  return ev;
}

/// The outcome and reason of a candidate that is not significant.
void ExplainNotSignificant(const RoundContext& x, CandidateResult& c) {
  std::ostringstream why;
  if (!c.fitted && c.outcome != CandidateOutcome::kNotTested) {
    c.outcome = CandidateOutcome::kNotFitted;
    why << "the fit failed: " << c.message;
  } else if (c.identifiability == Identifiability::kNotTested) {
    c.outcome = CandidateOutcome::kNotTested;
    why << "no trial is sensitive to it at " << c.parameter << " = " << Fmt(Entry(c.key).probe)
        << UnitSuffix(c.unit);
  } else if (c.identifiability == Identifiability::kConfounded) {
    c.outcome = CandidateOutcome::kConfounded;
    why << "at " << c.parameter << " = " << Fmt(Entry(c.key).probe) << UnitSuffix(c.unit) << ", "
        << c.confounded_with << " takes its change back";
  } else if (c.p_value >= x.level) {
    c.outcome = CandidateOutcome::kNotSignificant;
    why << "likelihood-ratio p = " << FmtP(c.p_value) << " is not below the naming level "
        << FmtP(x.level) << " (alpha = " << Fmt(x.options.alpha) << " over "
        << x.probes.naming.hypotheses << " hypotheses: candidates x forms)";
  } else if (!c.wald_clear && Entry(c.key).smallest > 0) {
    c.outcome = CandidateOutcome::kAtSmallestValue;
    why << "likelihood-ratio p = " << FmtP(c.p_value) << ", but its estimate " << Fmt(c.estimate)
        << " +- " << Fmt(c.se) << UnitSuffix(c.unit)
        << " does not stand clear of the smallest value the fit may take ("
        << Fmt(Entry(c.key).smallest) << UnitSuffix(c.unit)
        << "): the data want no more of it than the library's least, and the step from 0 to "
           "that value is no evidence of it";
  } else if (!c.wald_clear) {
    c.outcome = CandidateOutcome::kNotSignificant;
    why << "likelihood-ratio p = " << FmtP(c.p_value) << ", but its estimate " << Fmt(c.estimate)
        << " +- " << Fmt(c.se) << UnitSuffix(c.unit)
        << " does not stand clear of 0 at the naming level: the gain is in zeta, mu or the noise "
           "model";
  } else if (c.p_without_influential >= kWithoutInfluentialLevel) {
    c.outcome = CandidateOutcome::kRestsOnOneTrial;
    why << "likelihood-ratio p = " << FmtP(c.p_value) << ", but without the trial that gains most "
        << "from it (" << c.influential_trial << ") p = " << FmtP(c.p_without_influential)
        << ", not below " << Fmt(kWithoutInfluentialLevel)
        << ": one trial the current model cannot follow is no evidence of an effect";
  } else if (!HeldOutFell(c)) {
    c.outcome = CandidateOutcome::kWorseHeldOut;
    why << "p = " << FmtP(c.p_value) << " is significant, but its " << HeldOutText(c)
        << " did not fall: it fits these trials without predicting others better";
  } else {
    c.outcome = CandidateOutcome::kWorseHeldOut;
    why << "p = " << FmtP(c.p_value) << " is significant and its " << HeldOutText(c)
        << " fell, but not significantly (paired p = " << FmtP(c.cv_p) << ", not below "
        << Fmt(kLaterRoundHeldOutLevel)
        << "), which a round after an added effect asks: the likelihood ratio against a "
           "model with an effect fitted through the scatter is not at its nominal level";
  }
  c.reason = why.str();
}

int UsedResiduals(const Workspace& ws) {
  int n = 0;
  for (const Obs& o : ws.obs) n += o.Dim();
  return n;
}

}  // namespace hoof::discovery::internal
