// The discovery workflow's rounds (docs/discovery.md): the baseline under the noise model, then
// per round the residuals' structure, the candidates (candidates.cc) and what was added; at the
// end the findings and the verdict.
#include "discovery/discovery.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <numbers>

#include <boost/math/distributions/normal.hpp>

#include "discovery/internal.h"

namespace hoof::discovery {

using namespace internal;

namespace {

Finding FindingOf(const CandidateResult& c, FindingStatus status, double alpha) {
  Finding f;
  f.key = c.key;
  f.name = c.name;
  f.parameter = c.parameter;
  f.unit = c.unit;
  f.status = status;
  f.form = c.form;
  f.estimate = c.estimate;
  f.se = c.se;
  f.values = c.values;
  f.gap_shrink = kNaN;
  if (c.form == EffectForm::kPerSurface) {
    // The surfaces where the effect stands clear of zero (one-sided at alpha).
    const double z = boost::math::quantile(boost::math::complement(boost::math::normal(), alpha));
    for (const auto& v : c.values)
      if (std::isfinite(v.se) ? v.value > z * v.se : v.value > 0) f.surfaces.push_back(v.surface);
  }
  return f;
}

}  // namespace

namespace internal {

const CandidateResult* EarlierSignificance(const std::vector<Round>& rounds, int before,
                                           const std::string& key, int* round) {
  for (const auto& r : rounds) {
    if (r.index >= before) break;
    for (const auto& c : r.candidates)
      if (c.key == key && c.fitted && c.p_value < r.naming_level) {
        if (round) *round = r.index;
        return &c;
      }
  }
  return nullptr;
}

void KeepEarlierEvidence(const std::vector<Round>& earlier, const std::vector<std::string>& added,
                         Round& rd) {
  std::vector<std::string> names;
  for (const auto& key : added) names.push_back(Entry(key).name);
  for (auto& c : rd.candidates) {
    if (c.measurement_effect ||
        (c.outcome != CandidateOutcome::kNotTested && c.outcome != CandidateOutcome::kConfounded))
      continue;
    int when = 0;
    const CandidateResult* before = EarlierSignificance(earlier, rd.index, c.key, &when);
    if (!before) continue;
    c.identifiability = Identifiability::kIdentified;
    c.outcome = CandidateOutcome::kNotSignificant;
    c.reason =
        "with " + JoinedWords(names) + " in the model its fit gains " +
        (c.lr_statistic > 0 ? "only " + Fmt(c.lr_statistic) + " in 2 log-likelihood" : "nothing") +
        " (p = " + FmtP(c.p_value) + "); in round " + std::to_string(when) +
        " its likelihood-ratio p was " + FmtP(before->p_value) + " (" + ToString(before->outcome) +
        "): the effect added since takes up what it explained";
  }
}

}  // namespace internal

namespace {

/// The trials the rounds work on: as measured, until a rotation rate is added; from then on
/// re-measured with it (kept alive here).
struct CurrentTrials {
  const Workspace* ws = nullptr;
  std::shared_ptr<Workspace> remeasured_ws;
  std::shared_ptr<const std::vector<pipeline::TrialAnalysis>> remeasured;
};

/// The findings of the effect `o` added in round `rd`: named, or indistinguishable from the
/// candidates alike it, each of which is a finding too.
void AddFindings(const Round& rd, const RoundOutcome& o, double alpha,
                 std::vector<Finding>& findings) {
  const CandidateResult* best = nullptr;
  for (const auto& c : rd.candidates)
    if (c.key == o.key) best = &c;
  for (const auto& a : o.alike)
    for (const auto& c : rd.candidates)
      if (c.key == a) {
        Finding f = FindingOf(c, FindingStatus::kIndistinguishable, alpha);
        f.partner = best->name;
        f.separating_measurement =
            Entry(a).separating_measurement + "; " + Entry(best->key).separating_measurement;
        findings.push_back(f);
      }
  Finding f = FindingOf(
      *best, o.alike.empty() ? FindingStatus::kNamed : FindingStatus::kIndistinguishable, alpha);
  for (const auto& a : o.alike) f.partner += (f.partner.empty() ? "" : ", ") + Entry(a).name;
  if (!o.alike.empty()) f.separating_measurement = Entry(best->key).separating_measurement;
  f.gap_shrink = rd.gap_shrink;
  findings.push_back(f);
}

/// The state after the effect `o` is added: a rotation rate re-measures the trials, the
/// constant tilt is switched on, a contact effect becomes part of the current model.
void Adopt(const RoundOutcome& o, const DiscoveryOptions& options, const std::vector<int>& all,
           RoundState& st, CurrentTrials& trials) {
  st.accepted.push_back(o.key);
  if (IsRotationRate(o.key)) {
    // From now on the trials are the ones re-measured with the motion.
    st.motion = o.motion;
    trials.remeasured = o.remeasured;
    trials.remeasured_ws = o.ws;  // built from them when the rate was evaluated
    if (!trials.remeasured_ws) {
      trials.remeasured_ws = std::make_shared<Workspace>();
      int skipped_again = 0;
      Build(*trials.remeasured, options, &skipped_again, *trials.remeasured_ws);
    }
    trials.ws = trials.remeasured_ws.get();
    st.current = o.fit;
    st.tilt = FitTilt(*trials.ws, all, st.tilt_on);
  } else if (Entry(o.key).measurement_effect) {
    st.tilt_on = true;
    st.tilt = o.tilt;
  } else {
    st.current = o.fit;
  }
}

/// What the final model leaves: its significant structure (named effects become tentative
/// when some remains), and the candidates its own parameters absorb (the probes of the last
/// round, which added nothing, were made against it).
void FinalStructure(const Workspace& current, const RoundState& st, const std::vector<int>& all,
                    const std::vector<Eigen::Vector3d>& final_residuals,
                    const DiscoveryOptions& options, DiscoveryResult& out) {
  const auto final_sens = current.Sensitivities(st.current.model, all);
  for (const auto& t : StructureTests(current, final_residuals, final_sens, st.current.noise,
                                      st.tilt.tilt_rad, options))
    if (t.significant) out.remaining.push_back(t);
  out.unexplained = !out.remaining.empty();
  if (out.unexplained)
    for (auto& f : out.findings)
      if (f.status == FindingStatus::kNamed) f.status = FindingStatus::kTentative;
  if (!out.rounds.empty() && out.rounds.back().accepted.empty())
    for (const auto& c : out.rounds.back().candidates)
      if (c.outcome == CandidateOutcome::kConfounded) {
        Finding f = FindingOf(c, FindingStatus::kIndistinguishable, options.alpha);
        f.partner = c.confounded_with;
        f.separating_measurement = Entry(c.key).separating_measurement;
        out.findings.push_back(f);
      }
}

/// The final model's values: per surface, the largest systematic error per component, and the
/// value of every added effect.
void FinalValues(const Workspace& current, const RoundState& st, DiscoveryResult& out) {
  out.final_model = SurfaceFits(current, st.current);
  // The largest of the surfaces' systematic errors per component (each surface's is in
  // `final_model`).
  for (const auto& sd : st.current.noise.systematic_sd)
    out.measurement_sd = out.measurement_sd.cwiseMax(sd);
  for (const auto& key : st.accepted) {
    if (IsRotationRate(key)) {
      for (const auto& rd : out.rounds)
        for (const auto& c : rd.candidates)
          if (rd.accepted == key && c.key == key)
            out.effects.push_back({key, "", c.estimate, c.se});
    } else if (Entry(key).measurement_effect) {
      out.effects.push_back({key, "", st.tilt.tilt_rad * 180 / std::numbers::pi,
                             st.tilt.tilt_se_rad * 180 / std::numbers::pi});
    } else {
      for (const auto& v : EffectValues(current, st.current, key)) out.effects.push_back(v);
    }
  }
}

/// Each trial's residuals under the baseline and the final model (NaN for an unused component).
void TrialResidualsOf(const Workspace& ws, const std::vector<Eigen::Vector3d>& base_residuals,
                      const std::vector<Eigen::Vector3d>& final_residuals, DiscoveryResult& out) {
  for (std::size_t i = 0; i < ws.obs.size(); ++i) {
    const Obs& o = ws.obs[i];
    TrialResiduals r;
    r.id = o.trial->spec.id;
    r.surface = ws.surfaces[static_cast<std::size_t>(o.surface)];
    r.angle_deg = o.angle_deg;
    r.speed_m_s = o.speed_m_s;
    r.baseline = base_residuals[i];
    r.final_model = final_residuals[i];
    for (int c = 0; c < kComponents; ++c)
      if (!o.used[static_cast<std::size_t>(c)]) r.baseline[c] = r.final_model[c] = kNaN;
    r.marker_ratio = o.marker_ratio;  // as measured
    out.residuals.push_back(r);
  }
}

/// Round `round`: the structure tests of the current model's residuals, every candidate, and
/// the one added, if any (adopted into `st` and `current`). Returns whether one was added.
bool RunRound(int round, const std::vector<int>& all, const std::vector<std::string>& keys,
              const DiscoveryOptions& options, const std::function<void(const std::string&)>& say,
              RoundState& st, CurrentTrials& current, DiscoveryResult& out) {
  Round rd;
  rd.index = round;
  const Workspace& cw = *current.ws;
  const auto residuals = cw.Residuals(st.current.model, all);
  const auto sens = cw.Sensitivities(st.current.model, all);
  rd.tests = StructureTests(cw, residuals, sens, st.current.noise, st.tilt.tilt_rad, options);
  say("round " + std::to_string(round) + ": " +
      std::to_string(
          std::count_if(rd.tests.begin(), rd.tests.end(), [](auto& t) { return t.significant; })) +
      " significant trend(s) of " + std::to_string(rd.tests.size()) + " in the residuals");
  const RoundOutcome o = RunCandidates(cw, st, residuals, sens, keys, options, say, rd);
  st.profile_starts.insert(o.profile_starts.begin(), o.profile_starts.end());
  KeepEarlierEvidence(out.rounds, st.accepted, rd);
  if (!o.added) {
    out.rounds.push_back(rd);
    return false;
  }
  say("  added " + o.key);
  AddFindings(rd, o, options.alpha, out.findings);
  Adopt(o, options, all, st, current);
  out.rounds.push_back(rd);
  return true;
}

}  // namespace

DiscoveryResult Discover(const std::vector<pipeline::TrialAnalysis>& trials,
                         const DiscoveryOptions& options,
                         const std::function<void(const std::string&)>& progress) {
  options.Validate();
  const auto t0 = std::chrono::steady_clock::now();
  auto say = [&](const std::string& s) {
    if (progress) progress(s);
  };
  DiscoveryResult out;
  int skipped = 0;
  Workspace ws;  // the trials as measured
  Build(trials, options, &skipped, ws);
  CurrentTrials current{&ws, nullptr, nullptr};
  out.trials_skipped = skipped;
  out.trials_used = static_cast<int>(ws.obs.size());
  if (ws.obs.size() < 6) {
    out.message = "too few measured trials with a fitted surface model (" +
                  std::to_string(ws.obs.size()) + "; at least 6 are needed)";
    return out;
  }
  std::vector<std::string> keys = options.candidates;
  if (keys.empty())
    for (const auto& e : Library()) keys.push_back(e.key);
  const std::vector<int> all = ws.All();

  say("baseline: fitting zeta and mu per surface and the noise model to " +
      std::to_string(ws.obs.size()) + " trials");
  RoundState st;
  st.measured = &trials;
  st.current = FitBaseline(ws);
  st.tilt = FitTilt(ws, all, false);
  out.baseline = SurfaceFits(ws, st.current);
  const Model baseline_model = st.current.model;

  for (int round = 1; round <= options.max_rounds; ++round)
    if (!RunRound(round, all, keys, options, say, st, current, out)) break;

  const auto final_residuals = current.ws->Residuals(st.current.model, all);
  FinalStructure(*current.ws, st, all, final_residuals, options, out);
  FinalValues(*current.ws, st, out);
  TrialResidualsOf(ws, ws.Residuals(baseline_model, all), final_residuals, out);
  out.verdict = VerdictText(out, options, skipped) + MassNote(ws);
  out.simulations = ws.simulations.load() +
                    (current.remeasured_ws ? current.remeasured_ws->simulations.load() : 0);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.success = true;
  return out;
}

}  // namespace hoof::discovery
