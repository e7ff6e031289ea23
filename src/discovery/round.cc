// One round of the discovery workflow (docs/discovery.md, "Candidates and the decision"): every
// candidate evaluated (candidates.cc), the strongest significant one added, and the round's
// decision and held-out gap written.
#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "discovery/evaluation.h"
#include "discovery/internal.h"
#include "stats/distributions.h"

namespace hoof::discovery::internal {
namespace {

/// The winner: a significant rotation rate first (it changes the velocities that every
/// contact effect is judged on), of lowest AIC; else the significant contact effect of lowest
/// AIC; the constant tilt only when neither is significant (it is judged on other data, and
/// tried again next round). Null when nothing is significant.
Evaluation* ChooseWinner(std::vector<Evaluation>& evals) {
  Evaluation* best = nullptr;
  for (auto& ev : evals)
    if (ev.c.significant && IsRotationRate(ev.c.key) && (!best || Aic(ev.c) < Aic(best->c)))
      best = &ev;
  if (!best)
    for (auto& ev : evals)
      if (ev.c.significant && !ev.c.measurement_effect && (!best || Aic(ev.c) < Aic(best->c)))
        best = &ev;
  if (!best)
    for (auto& ev : evals)
      if (ev.c.significant) best = &ev;
  return best;
}

/// The added candidate's reason, and why every other significant one was not added; the keys of
/// those indistinguishable from it.
std::vector<std::string> ExplainAgainstWinner(const RoundContext& x, Evaluation& best,
                                              std::vector<Evaluation>& evals) {
  std::vector<std::string> alike;
  best.c.outcome = CandidateOutcome::kAdded;
  std::ostringstream why;
  why << "likelihood-ratio p = " << FmtP(best.c.p_value) << " below the naming level "
      << FmtP(x.level) << ", " << HeldOutText(best.c);
  best.c.reason = why.str();
  for (auto& ev : evals) {
    if (&ev == &best || !ev.c.significant) continue;
    const double d_aic = Aic(ev.c) - Aic(best.c);
    std::ostringstream w;
    if (ev.c.measurement_effect == best.c.measurement_effect &&
        IsRotationRate(ev.c.key) == IsRotationRate(best.c.key) && d_aic < x.chi95) {
      ev.c.outcome = CandidateOutcome::kIndistinguishable;
      w << "significant (p = " << FmtP(ev.c.p_value) << "), and fits as well as " << best.c.name
        << " (AIC within " << Fmt(d_aic) << "): the two cannot be told apart with these data";
      alike.push_back(ev.c.key);
    } else {
      ev.c.outcome = CandidateOutcome::kWeakerThanAdded;
      w << "significant (p = " << FmtP(ev.c.p_value) << "), but " << best.c.name;
      if (IsRotationRate(best.c.key) && !IsRotationRate(ev.c.key))
        w << " was added first (a rotation rate goes first: it changes the velocities the "
             "contact effects are "
             "judged on)";
      else if (ev.c.measurement_effect != best.c.measurement_effect)
        w << " was added first (a contact effect goes before the measurement effect)";
      else
        w << " explains the data better (AIC lower by " << Fmt(d_aic) << ")";
      w << "; it is tried again against the model with it";
    }
    ev.c.reason = w.str();
  }
  return alike;
}

/// Rank: the added first, then by the strength of the evidence.
void Rank(std::vector<Evaluation>& evals) {
  auto klass = [](const CandidateResult& c) {
    switch (c.outcome) {
      case CandidateOutcome::kAdded:
        return 0;
      case CandidateOutcome::kIndistinguishable:
        return 1;
      case CandidateOutcome::kWeakerThanAdded:
        return 2;
      default:
        return 3;
    }
  };
  std::stable_sort(evals.begin(), evals.end(), [&](const Evaluation& a, const Evaluation& b) {
    if (klass(a.c) != klass(b.c)) return klass(a.c) < klass(b.c);
    if (a.c.fitted != b.c.fitted) return a.c.fitted;
    // A candidate not evaluated has no p (NaN): last, and a strict weak order all the same.
    auto p = [](const CandidateResult& c) { return std::isnan(c.p_value) ? 2.0 : c.p_value; };
    return p(a.c) < p(b.c);
  });
  for (std::size_t i = 0; i < evals.size(); ++i) evals[i].c.rank = static_cast<int>(i) + 1;
}

/// The round's decision when nothing was added.
std::string NothingAdded(const std::vector<Evaluation>& evals, double level) {
  bool worse = false, small = false;
  for (const auto& ev : evals) {
    worse |= ev.c.outcome == CandidateOutcome::kWorseHeldOut;
    small |= ev.c.outcome == CandidateOutcome::kBelowResolution;
  }
  std::string d =
      "Nothing added: no candidate improves the fit significantly under the noise model (naming "
      "level " +
      FmtP(level) + ")";
  if (worse) d += ", or one that does fails to predict held-out trials better";
  if (small) d += "; a significant out-of-plane tilt is below the measurement's resolution";
  return d + ".";
}

/// The gap on held-out trials before and after the added effect (of the velocities, as
/// measured and as re-measured, for a rotation rate): per trial, and its root mean square.
void HeldOutGap(const RoundContext& x, const Evaluation& winner, Round& rd) {
  const CandidateResult& w = winner.c;
  const bool rate = IsRotationRate(w.key);
  const CrossValidation& before = w.measurement_effect && !rate ? x.cv_tilt_current : x.cv_current;
  const CrossValidation& after = rate ? winner.velocity_cv : winner.cv;
  double sb = 0, sa = 0;
  int n = 0;
  for (std::size_t i = 0;
       i < x.ws.obs.size() && i < before.residual.size() && i < after.residual.size(); ++i) {
    const Obs& o = x.ws.obs[i];
    if (!std::isfinite(Rms(before.residual[i])) || !std::isfinite(Rms(after.residual[i]))) continue;
    GapTrial g;
    g.id = o.trial->spec.id;
    g.surface = x.ws.surfaces[static_cast<std::size_t>(o.surface)];
    g.angle_deg = o.angle_deg;
    g.speed_m_s = o.speed_m_s;
    g.fold = o.fold;
    g.residual_before = before.residual[i];
    g.residual_after = after.residual[i];
    g.gap_before = Rms(g.residual_before);
    g.gap_after = Rms(g.residual_after);
    for (int c = 0; c < kComponents; ++c)
      if (std::isfinite(g.residual_before[c]) && std::isfinite(g.residual_after[c]))
        sb += g.residual_before[c] * g.residual_before[c],
            sa += g.residual_after[c] * g.residual_after[c], ++n;
    rd.gap.push_back(g);
  }
  rd.gap_before = n ? std::sqrt(sb / n) : kNaN;
  rd.gap_after = n ? std::sqrt(sa / n) : kNaN;
  rd.gap_shrink = rd.gap_before > 0 ? 1 - rd.gap_after / rd.gap_before : kNaN;
}

/// The round's decision when `w` was added.
std::string AddedText(const CandidateResult& w, const Round& rd,
                      const std::vector<std::string>& alike) {
  std::ostringstream d;
  d << "Added " << w.name;
  if (w.form == EffectForm::kPerSurface) {
    d << " per surface (";
    for (std::size_t i = 0; i < w.values.size(); ++i)
      d << (i ? ", " : "") << w.values[i].surface << " " << w.parameter << " = "
        << Fmt(w.values[i].value) << " +- " << Fmt(w.values[i].se)
        << UpperBoundNote(w.key, w.values[i].value);
    d << UnitSuffix(w.unit) << ")";
  } else {
    d << " (" << w.parameter << " = " << Fmt(w.estimate) << " +- " << Fmt(w.se)
      << UnitSuffix(w.unit) << UpperBoundNote(w.key, w.estimate) << ")";
  }
  d << ": likelihood ratio " << Fmt(w.lr_statistic) << ", p = " << FmtP(w.p_value) << "; "
    << HeldOutText(w) << "; held-out gap " << Fmt(100 * rd.gap_before) << " % -> "
    << Fmt(100 * rd.gap_after) << " % of the impact speed (" << GapChangeText(rd.gap_shrink)
    << ").";
  if (!alike.empty()) {
    d << " It cannot be told apart from";
    for (std::size_t i = 0; i < alike.size(); ++i) d << (i ? ", " : " ") << Entry(alike[i]).name;
    d << " with these data.";
  }
  return d.str();
}

}  // namespace

CandidateResult JudgeCandidate(const Workspace& ws, const Fit& current, const std::string& key,
                               const DiscoveryOptions& options, double level) {
  RoundState state;
  state.current = current;
  const std::vector<int> all = ws.All();
  const auto residuals = ws.Residuals(current.model, all);
  const auto sens = ws.Sensitivities(current.model, all);
  const std::vector<TrialCovariance> ref = Covariances(ws, sens, current.noise);
  RoundContext x{ws, state, residuals, sens, ref, options, all, {}, {}, level, {}, {}};
  for (const auto& [k, p] : current.model.effects) x.free_current.push_back(k);
  x.chi95 = stats::ChiSquaredQuantile(0.95, 1);
  x.probes = ProbeCandidates(ws, current.model, {key}, residuals, sens, ref, options);
  x.cv_current = CrossValidate(ws, current, x.free_current, ref, options.folds);
  AddDensity(x.cv_current, ref);
  x.n_res = UsedResiduals(ws);
  Evaluation ev = EvaluateContact(x, key);
  if (!ev.c.significant) ExplainNotSignificant(x, ev.c);
  return ev.c;
}

RoundOutcome RunCandidates(const Workspace& ws, const RoundState& state,
                           const std::vector<Eigen::Vector3d>& residual_current,
                           const std::vector<Sensitivity>& sens,
                           const std::vector<std::string>& keys, const DiscoveryOptions& options,
                           const std::function<void(const std::string&)>& say, Round& rd) {
  const std::vector<TrialCovariance> ref = Covariances(ws, sens, state.current.noise);
  RoundContext x{ws, state, residual_current, sens, ref, options, ws.All(), {}, {}, 0.0, {}, {}};
  std::vector<std::string> to_try;
  for (const auto& key : keys)
    if (std::find(state.accepted.begin(), state.accepted.end(), key) == state.accepted.end())
      to_try.push_back(key);
  x.chi95 = stats::ChiSquaredQuantile(0.95, 1);
  for (const auto& a : state.accepted)
    if (!Entry(a).measurement_effect) x.free_current.push_back(a);
  for (const Obs& o : ws.obs) x.n_ratio += std::isfinite(o.marker_ratio) ? 1 : 0;
  x.probes = ProbeCandidates(ws, state.current.model, to_try, residual_current, sens, ref, options);
  x.level = x.probes.naming.level;
  rd.naming_level = x.probes.naming.level;
  rd.bonferroni_level = x.probes.naming.bonferroni;
  rd.hypotheses = x.probes.naming.hypotheses;
  x.cv_current = CrossValidate(ws, state.current, x.free_current, ref, options.folds);
  AddDensity(x.cv_current, ref);
  x.cv_tilt_current = CrossValidateTilt(ws, state.tilt_on, options.folds);
  x.n_res = UsedResiduals(ws);

  std::vector<Evaluation> evals;
  const std::string out_of_plane_gap = OutOfPlaneGap(ws);
  for (const auto& key : to_try) {
    say("  " + key);
    if (Entry(key).measurement_effect && !out_of_plane_gap.empty())
      evals.push_back(NotApplicable(key, out_of_plane_gap));
    else if (IsRotationRate(key))
      evals.push_back(EvaluateRate(x, key));
    else if (Entry(key).measurement_effect)
      evals.push_back(EvaluateTilt(x, key));
    else
      evals.push_back(EvaluateContact(x, key));
  }
  for (auto& ev : evals)
    if (!ev.c.significant && ev.c.reason.empty()) ExplainNotSignificant(x, ev.c);
  Evaluation* best = ChooseWinner(evals);
  RoundOutcome out;
  for (const auto& ev : evals)
    if (!ev.profile_starts.empty()) out.profile_starts[ev.c.key] = ev.profile_starts;
  if (best) out.alike = ExplainAgainstWinner(x, *best, evals);
  for (auto& ev : evals)
    if (!ev.other_optimum.empty() && ev.c.significant) ev.c.reason += "; " + ev.other_optimum;
  Rank(evals);
  // `best` moved with the sort; find it again by its outcome.
  const Evaluation* winner = nullptr;
  for (const auto& ev : evals) {
    rd.candidates.push_back(ev.c);
    if (ev.c.outcome == CandidateOutcome::kAdded) winner = &ev;
  }
  if (!winner) {
    rd.decision = NothingAdded(evals, x.level);
    return out;
  }
  const CandidateResult& w = winner->c;
  out.added = true;
  out.key = w.key;
  out.fit = winner->fit;
  out.tilt = winner->tilt;
  out.motion = winner->motion;
  out.remeasured = winner->remeasured;
  out.ws = winner->remeasured_ws;
  rd.accepted = w.key;
  HeldOutGap(x, *winner, rd);
  rd.decision = AddedText(w, rd, out.alike);
  return out;
}

}  // namespace hoof::discovery::internal
