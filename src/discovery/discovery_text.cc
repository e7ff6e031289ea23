// The discovery result and a plan as the text `hoofimpact discover` prints (docs/discovery.md,
// "Reading the verdict").
#include "discovery/discovery_text.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace hoof::discovery {

std::string Num(double v, int precision) {
  if (!std::isfinite(v)) return "-";
  std::ostringstream s;
  s << std::setprecision(precision) << v;
  return s.str();
}

namespace {

std::string Estimate(double estimate, double se, const std::string& parameter,
                     const std::string& unit) {
  std::string out = parameter.empty() ? "" : parameter + " = ";
  out += Num(estimate, 3);
  if (std::isfinite(se)) out += " +- " + Num(se, 2);
  if (!unit.empty() && unit != "1") out += " " + unit;
  return out;
}

std::string Percent(double fraction) {
  return std::isfinite(fraction) ? Num(100.0 * fraction, 3) + " %" : "-";
}

/// Every value ("steel: c = 0.7 +- 0.1 N s/m^2; concrete: ..."; "all surfaces" for a shared
/// one).
std::string ValuesText(const std::vector<EffectValue>& values, const std::string& parameter,
                       const std::string& unit) {
  std::string out;
  for (const auto& v : values)
    out += (out.empty() ? "" : "; ") + (v.surface.empty() ? "all surfaces" : v.surface) + ": " +
           Estimate(v.value, v.se, parameter, unit);
  return out;
}

/// Width of a column of enum texts: the longest text, and two spaces.
template <typename Values>
int TextWidth(const Values& values) {
  std::size_t width = 0;
  for (auto v : values) width = std::max(width, std::string(ToString(v)).size());
  return static_cast<int>(width) + 2;
}

/// Whether a candidate gets a line saying why it was or was not added: it is significant, or
/// its likelihood ratio was and something else decided.
bool SaysWhy(const CandidateResult& c) {
  return c.significant || c.outcome == CandidateOutcome::kAdded ||
         c.outcome == CandidateOutcome::kIndistinguishable ||
         c.outcome == CandidateOutcome::kWeakerThanAdded ||
         c.outcome == CandidateOutcome::kWorseHeldOut ||
         c.outcome == CandidateOutcome::kBelowResolution ||
         c.outcome == CandidateOutcome::kAtSmallestValue ||
         c.outcome == CandidateOutcome::kRestsOnOneTrial;
}

/// The held-out score the candidate is judged by, and the current model's.
std::string HeldOutColumn(const CandidateResult& c) {
  const auto [now, current] = HeldOutScores(c);
  return now + " (" + current + ")";
}

/// The widths of the text columns that hold an enum's text: its longest value's.
struct ColumnWidths {
  int outcome = TextWidth(AllCandidateOutcomes());
  int identifiability = TextWidth(std::array{
      Identifiability::kIdentified, Identifiability::kNotTested, Identifiability::kConfounded});
  int form = TextWidth(std::array{EffectForm::kShared, EffectForm::kPerSurface});
};

/// A round's candidates, one row each, under a header.
void WriteCandidateTable(std::ostream& os, const Round& round, const ColumnWidths& widths) {
  if (round.candidates.empty())
    os << "  (no candidate)\n";
  else
    os << "  " << std::left << std::setw(5) << "rank" << std::setw(24) << "effect"
       << std::setw(widths.form) << "form" << std::setw(30) << "estimate +- se" << std::right
       << std::setw(10) << "LR p" << std::setw(11) << "dAIC" << std::setw(11) << "dBIC"
       << "  " << std::left << std::setw(widths.outcome) << "outcome"
       << std::setw(widths.identifiability) << "identifiability"
       << "held-out (current)\n"
       << std::right;
  for (const auto& c : round.candidates) {
    os << "  " << std::left << std::setw(5)
       << (std::to_string(c.rank) + (c.key == round.accepted ? "*" : "")) << std::setw(24) << c.key;
    if (!c.fitted) {
      os << "not fitted: " << c.message << std::right << "\n";
      continue;
    }
    // A per-surface effect's estimate is the largest of its surface values.
    const std::string parameter = c.form == EffectForm::kPerSurface && !c.parameter.empty()
                                      ? "max " + c.parameter
                                      : c.parameter;
    os << std::setw(widths.form) << ToString(c.form) << std::setw(30)
       << Estimate(c.estimate, c.se, parameter, c.unit) << std::right << std::setw(10)
       << (c.p_value > 0 ? Num(c.p_value, 3) : std::string("<1e-300")) << std::setw(11)
       << Num(c.delta_aic, 3) << std::setw(11) << Num(c.delta_bic, 3) << "  " << std::left
       << std::setw(widths.outcome) << ToString(c.outcome) << std::setw(widths.identifiability)
       << ToString(c.identifiability) << std::right << HeldOutColumn(c) << "\n";
  }
}

/// Round `i` (from 0): its decision, candidates, reasons, structure tests and held-out gap.
void WriteRoundText(std::ostream& os, const Round& round, std::size_t i,
                    const ColumnWidths& widths) {
  os << "\nRound " << i + 1 << ": " << round.decision << "\n";
  WriteCandidateTable(os, round, widths);
  if (!round.candidates.empty())
    os << "  held-out: " << kHeldOutDensityUnit
       << " under each model's own noise model for a contact effect; " << kHeldOutErrorUnit
       << " for an out-of-plane candidate\n";
  for (const auto& c : round.candidates) {
    if (!SaysWhy(c)) continue;
    os << "  " << c.key << " (" << ToString(c.outcome)
       << "): " << (c.reason.empty() ? "-" : c.reason);
    if (c.form == EffectForm::kPerSurface && !c.values.empty())
      os << " [per surface: " << ValuesText(c.values, c.parameter, c.unit) << "]";
    os << "\n";
  }
  int significant = 0;
  for (const auto& t : round.tests)
    if (t.significant) {
      if (significant++ == 0) os << "  significant structure (Holm):\n";
      os << "    " << t.quantity << ", " << t.scope << ", " << t.covariate << ", " << t.test << ": "
         << Num(t.statistic) << ", p " << Num(t.p, 3) << ", Holm p " << Num(t.p_holm, 3)
         << (t.description.empty() ? "" : " (" + t.description + ")") << "\n";
    }
  if (significant == 0)
    os << "  no significant structure in the residuals (" << round.tests.size()
       << (round.tests.size() == 1 ? " test" : " tests") << ")\n";
  if (!round.accepted.empty())
    os << "  held-out gap " << Percent(round.gap_before) << " -> " << Percent(round.gap_after)
       << " (" << GapChangeText(round.gap_shrink) << ") with " << round.accepted << "\n";
}

/// The findings, one line each.
void WriteFindingsText(std::ostream& os, const std::vector<Finding>& findings) {
  os << "\nFindings:\n";
  if (findings.empty()) os << "  none\n";
  for (const auto& f : findings) {
    os << "  " << std::left
       << std::setw(TextWidth(std::array{FindingStatus::kNamed, FindingStatus::kTentative,
                                         FindingStatus::kIndistinguishable}))
       << ToString(f.status) << std::right << f.key;
    if (f.form == EffectForm::kPerSurface) {
      std::string on;
      for (const auto& surface : f.surfaces) on += (on.empty() ? "" : ", ") + surface;
      os << " (" << ToString(f.form) << (on.empty() ? "" : ", found on " + on) << "): "
         << (f.values.empty() ? Estimate(f.estimate, f.se, f.parameter, f.unit)
                              : ValuesText(f.values, f.parameter, f.unit));
    } else {
      os << ": " << Estimate(f.estimate, f.se, f.parameter, f.unit);
    }
    if (std::isfinite(f.gap_shrink)) os << "; held-out gap " << GapChangeText(f.gap_shrink);
    if (!f.partner.empty()) os << "; cannot be told from " << f.partner;
    if (!f.separating_measurement.empty()) os << "; to separate: " << f.separating_measurement;
    os << "\n";
  }
}

}  // namespace

void WriteDiscoveryText(std::ostream& os, const DiscoveryResult& r, const std::string& h5) {
  if (!r.success) {
    os << "Discovery on " << h5 << ": could not run (" << r.trials_used << " trial(s) used, "
       << r.trials_skipped << " skipped): " << r.message << "\n";
    return;
  }
  os << "Discovery on " << h5 << ": " << r.trials_used << " trial(s) used, " << r.trials_skipped
     << " skipped; " << r.rounds.size() << " round(s), " << r.simulations << " simulations, "
     << Num(r.seconds, 3) << " s\n\nVerdict:\n";
  std::istringstream verdict(r.verdict);
  for (std::string line; std::getline(verdict, line);)
    os << (line.empty() ? "" : "  ") << line << "\n";
  const ColumnWidths widths;
  for (std::size_t i = 0; i < r.rounds.size(); ++i) WriteRoundText(os, r.rounds[i], i, widths);
  WriteFindingsText(os, r.findings);
  os << "\nRemaining significant disagreement: " << (r.remaining.empty() ? "none" : "") << "\n";
  for (const auto& t : r.remaining)
    os << "  " << t.quantity << ", " << t.scope << ", " << t.covariate << ", " << t.test
       << ": Holm p " << Num(t.p_holm, 3)
       << (t.description.empty() ? "" : " (" + t.description + ")") << "\n";
}

void WritePlanText(std::ostream& os, const Plan& p, const std::string& h5) {
  const std::string unit = p.unit == "1" ? "" : " " + p.unit;
  os << "Plan for " << p.name << " at " << p.parameter << " = " << Num(p.size, 3) << unit << " ("
     << h5 << ", " << p.trials << " trials, naming level " << Num(p.level, 2) << "):\n"
     << "  this study detects " << p.parameter << " >= " << Num(p.detection_limit, 2) << unit
     << " with 80 % power; its power at " << Num(p.size, 3) << unit << " is " << Percent(p.power)
     << "\n"
     << "  80 % power at " << Num(p.size, 3) << unit << " needs about " << Num(p.trials_needed, 6)
     << " trials of this design (its conditions in the same proportions)\n";
  if (p.bootstrap_draws > 0)
    os << "  parametric bootstrap: detected in " << p.bootstrap_detected << " of "
       << p.bootstrap_draws << " studies simulated from the baseline with " << p.parameter << " = "
       << Num(p.size, 3) << unit << ": power " << Percent(p.bootstrap_power) << " (Wilson 95 % "
       << Percent(p.bootstrap_low) << " to " << Percent(p.bootstrap_high)
       << "); the likelihood ratio alone below the naming "
       << "level in " << p.bootstrap_lr_significant << " of " << p.bootstrap_draws << "\n";
  os << "  information per trial, most informative condition first (zeta and mu profiled out):\n";
  for (const auto& c : p.conditions)
    os << "    " << std::left << std::setw(10) << c.surface << std::right << std::setw(5)
       << Num(c.angle_deg, 3) << " deg  " << Num(c.speed_low_m_s, 3) << "-"
       << Num(c.speed_high_m_s, 3) << " m/s  " << std::setw(3) << c.trials << " trials  "
       << std::setw(10) << Num(c.information_per_trial, 3) << " per trial  (" << Percent(c.share)
       << " of the study's)\n";
  os << "  (the limit and the power from the study's expected data: the effect simulated "
        "without scatter or error, the baseline's zeta and mu refitted to it, under its "
        "noise model; the information per trial from the tangent plane; "
        "docs/discovery.md, \"Detection limits and plans\")\n";
}

}  // namespace hoof::discovery
