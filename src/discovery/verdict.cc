// The discovery workflow's per-surface fits and its verdict in words (docs/discovery.md,
// "Reading the verdict").
#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "compare/trial_comparison.h"
#include "discovery/internal.h"

namespace hoof::discovery::internal {
namespace {

std::string Scope(const Finding& f) {
  if (f.form == EffectForm::kShared) return "";
  return " on " + JoinedWords(f.surfaces);
}

std::string Estimate(const Finding& f) {
  std::ostringstream v;
  if (f.form == EffectForm::kShared) {
    v << f.parameter << " = " << Fmt(f.estimate) << " +- " << Fmt(f.se) << UnitSuffix(f.unit)
      << UpperBoundNote(f.key, f.estimate);
  } else {
    for (std::size_t i = 0; i < f.values.size(); ++i)
      v << (i ? ", " : "") << f.values[i].surface << " " << f.parameter << " = "
        << Fmt(f.values[i].value) << " +- " << Fmt(f.values[i].se)
        << UpperBoundNote(f.key, f.values[i].value);
    v << UnitSuffix(f.unit);
  }
  return v.str();
}

}  // namespace

std::vector<SurfaceFit> SurfaceFits(const Workspace& ws, const Fit& f) {
  std::vector<SurfaceFit> out;
  for (std::size_t s = 0; s < ws.surfaces.size(); ++s) {
    SurfaceFit sf;
    sf.surface = ws.surfaces[s];
    sf.zeta = f.model.zeta[s];
    sf.zeta_se = s < f.zeta_se.size() ? f.zeta_se[s] : kNaN;
    sf.mu = ws.has_oblique[s] ? f.model.mu[s] : kNaN;
    sf.mu_se = ws.has_oblique[s] && s < f.mu_se.size() ? f.mu_se[s] : kNaN;
    sf.k_N_m = ws.k[s];
    sf.zeta_sd = s < f.noise.zeta_sd.size() ? f.noise.zeta_sd[s] : kNaN;
    sf.mu_sd = ws.has_oblique[s] && s < f.noise.mu_sd.size() ? f.noise.mu_sd[s] : kNaN;
    if (s < f.noise.systematic_sd.size()) {
      sf.measurement_sd = f.noise.systematic_sd[s];
      if (!ws.has_oblique[s]) sf.measurement_sd.x() = sf.measurement_sd.z() = kNaN;
    }
    for (const Obs& o : ws.obs) sf.trials += o.surface == static_cast<int>(s) ? 1 : 0;
    out.push_back(sf);
  }
  return out;
}

namespace {

/// The evidence of the added effect `f`, from the round that added it.
std::string Evidence(const DiscoveryResult& out, const Finding& f) {
  std::ostringstream e;
  for (const auto& rd : out.rounds)
    if (rd.accepted == f.key)
      for (const auto& c : rd.candidates)
        if (c.key == f.key)
          e << "likelihood-ratio p = " << FmtP(c.p_value) << "; " << HeldOutText(c)
            << ", held-out gap " << Fmt(100 * rd.gap_before) << " % -> " << Fmt(100 * rd.gap_after)
            << " % of the impact speed (" << GapChangeText(f.gap_shrink) << ")";
  return e.str();
}

/// A line per finding; returns whether one is named.
bool WriteFindings(std::ostream& v, const DiscoveryResult& out) {
  bool any_named = false;
  for (const auto& f : out.findings) {
    if (f.status == FindingStatus::kNamed) {
      any_named = true;
      v << "Named: " << f.name << Scope(f) << ", " << Estimate(f) << ". " << Evidence(out, f)
        << ".\n";
    } else if (f.status == FindingStatus::kTentative) {
      v << "Tentative: " << f.name << Scope(f) << ", " << Estimate(f)
        << ", improves the fit significantly (" << Evidence(out, f)
        << "), but the residuals still show structure that no effect explains.\n";
    } else {
      v << "Cannot be told apart with these data: " << f.name << " and " << f.partner
        << ". A measurement that would separate them: " << f.separating_measurement << ".\n";
    }
  }
  return any_named;
}

/// Every significant candidate (at `alpha`), with why it was not added; and in a later round,
/// every candidate that was significant in an earlier one, so that what became of it is said.
void WriteNotAdded(std::ostream& v, const DiscoveryResult& out, double alpha) {
  for (const auto& rd : out.rounds)
    for (const auto& c : rd.candidates)
      if (c.outcome != CandidateOutcome::kAdded &&
          ((c.fitted && c.p_value < alpha) ||
           (!c.measurement_effect && EarlierSignificance(out.rounds, rd.index, c.key))))
        v << "Round " << rd.index << ", " << c.name << " (p = " << FmtP(c.p_value)
          << "): not added, " << c.reason << ".\n";
}

/// What the last round's candidates could have missed (their detection limits), and those no
/// trial is sensitive to.
void WriteLimits(std::ostream& v, const Round& last) {
  std::vector<std::string> limits, untested;
  std::map<std::string, std::vector<std::string>> inapplicable;  // by why (OutOfPlaneGap)
  for (const auto& c : last.candidates) {
    const bool gap = c.outcome == CandidateOutcome::kNotTested && IsOutOfPlaneGap(c.message);
    if (gap) {
      inapplicable[c.message].push_back(c.name);
      continue;
    }
    // (A rotation the image cannot see, but whose velocities speak, has its own line above.)
    if (c.outcome == CandidateOutcome::kNotTested &&
        !(IsRotationRate(c.key) && c.p_value < last.naming_level))
      untested.push_back(c.name);
    if ((!c.measurement_effect || IsRotationRate(c.key)) &&
        (c.outcome == CandidateOutcome::kNotSignificant ||
         c.outcome == CandidateOutcome::kWorseHeldOut ||
         c.outcome == CandidateOutcome::kRestsOnOneTrial ||
         c.outcome == CandidateOutcome::kConfounded)) {
      // No limit: the ladder reached the library's largest value without 80 % power (the
      // effect's change there is still within the noise, or zeta and mu take it back).
      if (std::isfinite(c.detection_limit))
        limits.push_back(c.name + ": " + c.parameter + " = " + Fmt(c.detection_limit, 2) +
                         UnitSuffix(c.unit));
      else
        limits.push_back(c.name + ": none up to " + c.parameter + " = " +
                         Fmt(Entry(c.key).upper, 2) + UnitSuffix(c.unit) +
                         " (the library's largest value)");
    }
  }
  if (!limits.empty()) {
    v << "\nWhat these trials could have missed: the smallest size of each effect not added that "
         "this design and "
         "noise detect with 80 % power at the naming level (shared by all surfaces; from the "
         "study's expected data with the effect simulated at a ladder of sizes, zeta and mu "
         "refitted):\n";
    for (const auto& l : limits) v << "  - " << l << "\n";
  }
  for (const auto& [why, names] : inapplicable) {
    v << "\nNot tested: ";
    for (std::size_t i = 0; i < names.size(); ++i) v << (i ? "; " : "") << names[i];
    v << ": " << why << ".\n";
  }
  if (!untested.empty()) {
    v << "\nNot tested by these data (no trial is sensitive to them): ";
    for (std::size_t i = 0; i < untested.size(); ++i) v << (i ? "; " : "") << untested[i];
    v << ".\n";
  }
}

}  // namespace

std::string MassNote(const Workspace& ws) {
  int without = 0;
  for (const Obs& o : ws.obs) without += compare::BodyToSimulate(*o.trial).mass_known ? 0 : 1;
  if (without == 0) return "";
  return "\nMass: " + std::to_string(without) +
         " trial(s) of a ball of unknown mass, simulated at the reference mass of " +
         Fmt(compare::kReferenceMass_kg * 1e3, 3) +
         " g; no velocity depends on it, but an effect sized in force units (Hunt-Crossley "
         "damping c, in N s/m^2) is that mass's, not the ball's.\n";
}

std::string VerdictText(const DiscoveryResult& out, const DiscoveryOptions& options, int skipped) {
  std::ostringstream v;
  v << "Data: " << out.trials_used << " measured trial(s) on " << out.baseline.size()
    << " surface(s)";
  if (skipped) v << " (" << skipped << " skipped: not measured or no surface model)";
  v << ". Baseline: the paper's two-phase model with zeta and mu fitted per surface (k is not "
       "identified by "
       "velocities and stays the paper's). Noise model: zeta and mu scatter from trial to trial "
       "(s.d. of zeta";
  for (const auto& s : out.final_model) v << " " << Fmt(s.zeta_sd, 2) << " on " << s.surface << ";";
  v << " fitted), plus each velocity's own measurement error.\n\n";
  const bool any_named = WriteFindings(v, out);
  WriteNotAdded(v, out, options.alpha);
  if (out.unexplained) {
    v << "\nUnexplained disagreement: with "
      << (out.effects.empty() ? "the baseline" : "the effects above added") << ", "
      << out.remaining.size() << " test(s) of the residuals remain significant:\n";
    for (std::size_t i = 0; i < std::min<std::size_t>(3, out.remaining.size()); ++i)
      v << "  - " << out.remaining[i].scope << ": " << out.remaining[i].description
        << " (p = " << FmtP(out.remaining[i].p) << ")\n";
    v << "The model lacks something that the library does not hold; no effect is named with "
         "confidence.\n";
  } else if (!any_named) {
    v << "Nothing is named: no candidate of the library improves the model significantly under the "
         "noise model.\n";
  }
  if (!out.rounds.empty()) WriteLimits(v, out.rounds.back());
  return v.str();
}

}  // namespace hoof::discovery::internal
