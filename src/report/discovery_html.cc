// The report's Discovery section: the verdict, the findings, each round's candidates and
// structure tests, and the discovery figures, read from the study file's /discovery
// (docs/discovery.md).
#include <cmath>
#include <exception>
#include <sstream>
#include <string>
#include <vector>

#include "core/frames.h"
#include "discovery/discovery_tables.h"
#include "format/number_format.h"
#include "io/atomic_file.h"
#include "io/interrupt.h"
#include "report/discovery_figures.h"
#include "report/html_parts.h"

namespace hoof::report::internal {
namespace {

namespace fs = std::filesystem;
using studyfile::Table;

// ---- discovery ---------------------------------------------------------------------------

/// "estimate +- se unit" (the estimate to the decimal of its s.e.), or n/a when undefined.
std::string EstimateHtml(double estimate, double se, const std::string& unit) {
  if (!std::isfinite(estimate)) return format::kUndefined;
  std::string out = format::WithError(estimate, se, format::Kind::kCoefficient, " &plusmn; ");
  if (!unit.empty() && unit != "1") out += " " + HtmlEscape(unit);
  return out;
}

/// A fraction as a percentage ("12.3 %"), or n/a.
std::string PercentHtml(double fraction) {
  return std::isfinite(fraction) ? Fmt(100.0 * fraction, 3) + " %" : format::kUndefined;
}

/// Degrees of freedom: whole numbers as such, fractional ones (Welch's) to 3 digits.
std::string Df(double df) {
  return std::isfinite(df) && df == std::round(df) ? std::to_string(static_cast<long long>(df))
                                                   : Fmt(df, 3);
}

/// A p-value cell, bold when `significant`.
std::string PCell(double p, bool significant) {
  return std::string("<td class=\"num") + (significant ? " sig" : "") + "\">" +
         HtmlEscape(format::P(p)) + "</td>";
}

/// The verdict's paragraphs (separated by blank lines), each line of its own, and its lists
/// (lines that start with "  - "), escaped.
std::string VerdictHtml(const std::string& verdict) {
  std::string out, paragraph, items;
  std::istringstream in(verdict);
  std::string line;
  const auto flush = [&] {
    if (!paragraph.empty()) out += "<p>" + paragraph + "</p>";
    if (!items.empty()) out += "<ul>" + items + "</ul>";
    paragraph.clear();
    items.clear();
  };
  while (std::getline(in, line)) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) {
      flush();
      continue;
    }
    if (line.rfind("  - ", 0) == 0) {
      items += "<li>" + HtmlEscape(line.substr(4)) + "</li>";
      continue;
    }
    if (!items.empty()) flush();
    paragraph += (paragraph.empty() ? "" : "<br>") + HtmlEscape(line);
  }
  flush();
  return out;
}

/// One sentence that sums the verdict up.
std::string Headline(const discovery::DiscoveryResult& r) {
  std::vector<std::string> named, tentative;
  for (const auto& f : r.findings) {
    const std::string what = f.name.empty() ? f.key : f.name;
    if (f.status == discovery::FindingStatus::kNamed) named.push_back(what);
    if (f.status == discovery::FindingStatus::kTentative) tentative.push_back(what);
  }
  const auto join = [](const std::vector<std::string>& v) {
    std::string out;
    for (std::size_t i = 0; i < v.size(); ++i) out += (i ? "; " : "") + v[i];
    return out;
  };
  if (!named.empty())
    return "The missing effect is named: " + join(named) +
           ". With it in the model no significant disagreement remains.";
  if (r.unexplained && !tentative.empty())
    return "A significant disagreement remains unexplained. Tentatively added: " + join(tentative) +
           ".";
  if (r.unexplained) return "A significant disagreement remains unexplained by every candidate.";
  return "No significant disagreement between the model and the measurements.";
}

std::string TestsTableHtml(const std::vector<discovery::StructureTest>& tests,
                           const std::string& caption) {
  std::ostringstream h;
  h << "<table class=\"data discovery-tests\"><caption>" << HtmlEscape(caption)
    << "</caption><thead><tr><th>quantity</th><th>scope</th><th>covariate</th><th>test</th>"
       "<th>statistic</th><th>p</th><th>Holm p</th><th>in words</th></tr></thead><tbody>";
  for (const auto& t : tests) {
    std::string stat = Fmt(t.statistic, 4);
    if (t.test.find('F') != std::string::npos && std::isfinite(t.df2))
      stat = "F(" + Df(t.df1) + ", " + Df(t.df2) + ") = " + stat;
    else if (std::isfinite(t.df1) && t.df1 > 0)
      stat = "t(" + Df(t.df1) + ") = " + stat;
    else if (t.test.find(" z") != std::string::npos)
      stat = "z = " + stat;
    h << "<tr><td>" << HtmlEscape(t.quantity) << "</td><td>" << HtmlEscape(t.scope) << "</td><td>"
      << HtmlEscape(t.covariate) << "</td><td>" << HtmlEscape(t.test) << "</td><td class=\"num\">"
      << stat << "</td><td class=\"num\">" << HtmlEscape(format::P(t.p)) << "</td><td class=\"num"
      << (t.significant ? " sig" : "") << "\">" << HtmlEscape(format::P(t.p_holm)) << "</td><td>"
      << HtmlEscape(t.description) << "</td></tr>";
  }
  h << "</tbody></table>";
  return h.str();
}

/// Every value of an effect, one per line ("steel: c = 0.7 &plusmn; 0.1 N s/m^2"; "all
/// surfaces" for a shared value).
std::string ValuesHtml(const std::vector<discovery::EffectValue>& values,
                       const std::string& parameter, const std::string& unit) {
  std::string out;
  for (const auto& v : values)
    out += (out.empty() ? "" : "<br>") +
           HtmlEscape(v.surface.empty() ? std::string("all surfaces") : v.surface) + ": " +
           (parameter.empty() ? "" : HtmlEscape(parameter) + " = ") +
           EstimateHtml(v.value, v.se, unit) +
           HtmlEscape(discovery::UpperBoundNote(v.key, v.value));
  return out;
}

/// The estimate cell: the shared value, or every surface value of a per-surface effect.
std::string EstimateCellHtml(const std::string& key, discovery::EffectForm form, double estimate,
                             double se, const std::vector<discovery::EffectValue>& values,
                             const std::string& parameter, const std::string& unit) {
  if (form == discovery::EffectForm::kPerSurface && !values.empty())
    return ValuesHtml(values, parameter, unit);
  return (parameter.empty() ? "" : HtmlEscape(parameter) + " = ") +
         EstimateHtml(estimate, se, unit) + HtmlEscape(discovery::UpperBoundNote(key, estimate));
}

/// The held-out score a candidate is judged by, against the current model's.
std::string HeldOutCell(const discovery::CandidateResult& c) {
  const auto [now, current] = discovery::HeldOutScores(c);
  return HtmlEscape(now) + " vs " + HtmlEscape(current);
}

std::string CandidatesTableHtml(const discovery::Round& round) {
  std::ostringstream h;
  h << "<table class=\"data discovery-candidates\"><caption>Candidate effects in rank order "
       "(1 = added or strongest evidence); held-out score: for a contact effect the "
    << HtmlEscape(discovery::kHeldOutDensityUnit)
    << ", under each model's own noise model; for an out-of-plane candidate the held-out error "
       "in "
    << HtmlEscape(discovery::kHeldOutErrorUnit)
    << "; lower is "
       "better</caption><thead><tr><th>rank</th><th>effect</th><th>form</th><th>estimate "
       "&plusmn; s.e.</th><th>LR p</th><th>&Delta;AIC</th><th>&Delta;BIC</th><th>held-out "
       "score vs current</th><th>identifiability</th><th>outcome</th><th>why</th></tr></thead>"
       "<tbody>";
  for (const auto& c : round.candidates) {
    const bool accepted = !round.accepted.empty() && c.key == round.accepted;
    h << "<tr class=\"candidate" << (accepted ? " accepted" : "") << "\" data-key=\""
      << HtmlEscape(c.key) << "\"><td class=\"num\">" << c.rank << "</td><td>"
      << HtmlEscape(c.name.empty() ? c.key : c.name) << " <code>" << HtmlEscape(c.key) << "</code>"
      << (c.measurement_effect ? " <span class=\"flag\">measurement</span>" : "")
      << (accepted ? " <span class=\"ok\">added</span>" : "") << "</td>";
    if (!c.fitted) {
      h << "<td colspan=\"7\" class=\"bad\">not fitted</td><td>"
        << HtmlEscape(discovery::ToString(c.outcome)) << "</td><td>"
        << HtmlEscape(c.message.empty() ? c.reason : c.message) << "</td></tr>";
      continue;
    }
    h << "<td>" << HtmlEscape(discovery::ToString(c.form)) << "</td><td class=\"num\">"
      << EstimateCellHtml(c.key, c.form, c.estimate, c.se, c.values, c.parameter, c.unit) << "</td>"
      << PCell(c.p_value, c.significant) << "<td class=\"num\">" << Fmt(c.delta_aic, 3)
      << "</td><td class=\"num\">" << Fmt(c.delta_bic, 3) << "</td><td class=\"num"
      << (discovery::HeldOutFell(c) ? " ok" : "") << "\">" << HeldOutCell(c) << "</td><td>"
      << HtmlEscape(discovery::ToString(c.identifiability))
      << (c.confounded_with.empty() ? "" : " (absorbed by " + HtmlEscape(c.confounded_with) + ")")
      << "</td><td" << (accepted ? " class=\"ok\"" : "") << ">"
      << HtmlEscape(discovery::ToString(c.outcome)) << "</td><td>" << HtmlEscape(c.reason)
      << "</td></tr>";
  }
  if (round.candidates.empty()) h << "<tr><td colspan=\"11\">(no candidate)</td></tr>";
  h << "</tbody></table>";
  return h.str();
}

std::string FindingsTableHtml(const std::vector<discovery::Finding>& findings) {
  std::ostringstream h;
  h << "<table class=\"data discovery-findings\"><caption>Findings</caption><thead><tr>"
       "<th>effect</th><th>status</th><th>scope</th><th>estimate &plusmn; s.e.</th>"
       "<th>cannot be told from</th><th>what would separate them</th><th>held-out gap "
       "shrink</th></tr></thead><tbody>";
  for (const auto& f : findings) {
    const std::string cls = f.status == discovery::FindingStatus::kNamed       ? "ok"
                            : f.status == discovery::FindingStatus::kTentative ? "bad"
                                                                               : "";
    std::string scope = "all surfaces";
    if (f.form == discovery::EffectForm::kPerSurface) {
      scope = discovery::ToString(f.form);
      std::string on;
      for (const auto& surface : f.surfaces) on += (on.empty() ? "" : ", ") + surface;
      if (!on.empty()) scope += ": found on " + on;
    }
    h << "<tr><td>" << HtmlEscape(f.name.empty() ? f.key : f.name) << " <code>" << HtmlEscape(f.key)
      << "</code></td><td class=\"" << cls << "\">" << HtmlEscape(discovery::ToString(f.status))
      << "</td><td>" << HtmlEscape(scope) << "</td><td class=\"num\">"
      << EstimateCellHtml(f.key, f.form, f.estimate, f.se, f.values, f.parameter, f.unit)
      << "</td><td>" << HtmlEscape(f.partner) << "</td><td>" << HtmlEscape(f.separating_measurement)
      << "</td><td class=\"num\">" << PercentHtml(f.gap_shrink) << "</td></tr>";
  }
  if (findings.empty()) h << "<tr><td colspan=\"7\">(no effect found)</td></tr>";
  h << "</tbody></table>";
  return h.str();
}

std::string SurfacesTableHtml(const discovery::DiscoveryResult& r) {
  std::ostringstream h;
  h << "<table class=\"data\"><caption>Model per surface (fitted to every used trial)</caption>"
       "<thead><tr><th>surface</th><th>zeta, baseline</th><th>zeta, final</th><th>mu, "
       "baseline</th><th>mu, final</th><th>trials</th></tr></thead><tbody>";
  for (const auto& b : r.baseline) {
    const discovery::SurfaceFit* f = nullptr;
    for (const auto& x : r.final_model)
      if (x.surface == b.surface) f = &x;
    const double nan = core::kNaN;
    h << "<tr><td>" << HtmlEscape(b.surface) << "</td><td class=\"num\">"
      << EstimateHtml(b.zeta, b.zeta_se, "") << "</td><td class=\"num\">"
      << (f ? EstimateHtml(f->zeta, f->zeta_se, "") : EstimateHtml(nan, nan, ""))
      << "</td><td class=\"num\">" << EstimateHtml(b.mu, b.mu_se, "") << "</td><td class=\"num\">"
      << (f ? EstimateHtml(f->mu, f->mu_se, "") : EstimateHtml(nan, nan, ""))
      << "</td><td class=\"num\">" << b.trials << "</td></tr>";
  }
  h << "</tbody></table>";
  return h.str();
}

/// The final model's noise model: per surface the trial-to-trial scatter of zeta and mu, and
/// the systematic measurement error per component.
std::string NoiseTableHtml(const discovery::DiscoveryResult& r) {
  std::ostringstream h;
  h << "<table class=\"data discovery-noise\"><caption>Noise model of the final model: "
       "trial-to-trial scatter (s.d.) of the contact coefficients, and the systematic "
       "measurement error beyond each trial's own s.e. (s.d., % of the impact speed)</caption>"
       "<thead><tr><th>surface</th><th>zeta s.d.</th><th>mu s.d.</th><th>v_x</th><th>v_y</th>"
       "<th>w d_EC</th></tr></thead><tbody>";
  for (const auto& f : r.final_model) {
    h << "<tr><td>" << HtmlEscape(f.surface) << "</td><td class=\"num\">" << Fmt(f.zeta_sd, 3)
      << "</td><td class=\"num\">" << Fmt(f.mu_sd, 3) << "</td>";
    // Study files written before the error was per surface hold only the largest.
    // v_y is used by every trial, so its NaN marks such a file.
    const Eigen::Vector3d& sd =
        std::isnan(f.measurement_sd.y()) ? r.measurement_sd : f.measurement_sd;
    for (int k = 0; k < 3; ++k) h << "<td class=\"num\">" << PercentHtml(sd[k]) << "</td>";
    h << "</tr>";
  }
  h << "</tbody></table>";
  return h.str();
}

/// The Discovery section, or "" when the study file has no /discovery.
}  // namespace

namespace {

/// The facts of the run: trials, rounds, effort, and the settings it ran with where stored.
std::string FactsHtml(const discovery::DiscoveryResult& r, const fs::path& h5) {
  std::ostringstream h;
  h << "<dl class=\"facts\"><dt>Trials</dt><dd>" << r.trials_used << " used, " << r.trials_skipped
    << " skipped (not measured)</dd><dt>Rounds</dt><dd>" << r.rounds.size()
    << "</dd><dt>Effort</dt><dd>" << r.simulations << " simulations, " << format::Seconds(r.seconds)
    << " s</dd>";
  if (const auto o = discovery::ReadDiscoveryOptions(h5)) {
    std::string keys;
    for (const auto& k : o->candidates) keys += (keys.empty() ? "" : ",") + k;
    h << "<dt>Settings</dt><dd>alpha " << Fmt(o->alpha, 2) << ", " << o->folds << " folds, at most "
      << o->max_rounds << " rounds, candidates: " << HtmlEscape(keys.empty() ? "all" : keys)
      << (o->per_surface ? "" : ", shared values only")
      << (std::isfinite(o->measurement_floor)
              ? ", measurement floor " + PercentHtml(o->measurement_floor) + " of the impact speed"
              : "")
      << "</dd>";
  }
  h << "</dl>";
  return h.str();
}

/// Round `i` (from 0): its decision, the gap it closed, its candidates and the structure left.
std::string RoundHtml(const discovery::Round& round, std::size_t i) {
  std::ostringstream h;
  h << "<h3>Round " << i + 1 << "</h3><p>" << HtmlEscape(round.decision) << "</p>";
  if (!round.accepted.empty())
    h << "<p>Held-out gap " << PercentHtml(round.gap_before) << " &rarr; "
      << PercentHtml(round.gap_after) << " ("
      << HtmlEscape(discovery::GapChangeText(round.gap_shrink)) << ") with <code>"
      << HtmlEscape(round.accepted) << "</code>.</p>";
  h << CandidatesTableHtml(round);
  std::vector<discovery::StructureTest> significant;
  for (const auto& t : round.tests)
    if (t.significant) significant.push_back(t);
  if (significant.empty())
    h << "<p class=\"note\">No significant structure in the residuals (" << round.tests.size()
      << (round.tests.size() == 1 ? " test" : " tests") << ", Holm-adjusted).</p>";
  else
    h << TestsTableHtml(significant, "Significant structure in the residuals (" +
                                         std::to_string(significant.size()) + " of " +
                                         std::to_string(round.tests.size()) +
                                         " tests, Holm-adjusted)");
  return h.str();
}

}  // namespace

std::string DiscoverySection(const fs::path& h5, HtmlReportSummary& summary) {
  if (!discovery::HasDiscovery(h5)) return "";
  summary.discovery = true;
  std::ostringstream h;
  h << "<section id=\"discovery\"><h2>Discovery</h2>";
  discovery::DiscoveryResult r;
  try {
    r = discovery::ReadDiscovery(h5);
  } catch (const std::exception& e) {
    h << "<p class=\"bad\">The discovery tables cannot be read: " << HtmlEscape(e.what())
      << "</p></section>";
    summary.notes += std::string("discovery: ") + e.what() + "\n";
    return h.str();
  }
  if (!r.success) {
    h << "<p class=\"bad\" id=\"discovery-verdict\">The discovery workflow could not run: "
      << HtmlEscape(r.message) << "</p></section>";
    return h.str();
  }
  h << "<p class=\"note\">Where the baseline model (the paper's) and the measurements "
       "disagree, which candidate effect explains it, and how much it shrinks the gap on "
       "trials the fit never saw (<code>/discovery</code>, written by <code>hoofimpact "
       "discover</code>; residuals are measured &minus; simulated after impact, in % of the "
       "impact speed). The <a href=\"#trials\">Trials</a> table shows each trial's residuals "
       "on the scale of the same noise model (prediction z).</p>"
    << "<div class=\"verdict" << (r.unexplained ? " unexplained" : "")
    << "\" id=\"discovery-verdict\"><p class=\"headline\">" << HtmlEscape(Headline(r)) << "</p>"
    << VerdictHtml(r.verdict) << "</div>" << FactsHtml(r, h5);
  h << "<div class=\"tables\">" << FindingsTableHtml(r.findings) << SurfacesTableHtml(r)
    << NoiseTableHtml(r) << "</div>";

  const TemporaryFigureFolder folder;
  const fs::path& dir = folder.path();
  std::vector<fs::path> figures;
  {
    figures = WriteDiscoveryFigures(r, dir);
    const auto figure_of = [&](const std::string& stem) -> std::string {
      for (const auto& p : figures)
        if (p.extension() == ".png" && p.stem() == stem) {
          ++summary.figures;
          return "<div class=\"figures\">" + FigureHtml(p) + "</div>";
        }
      return "";
    };
    for (std::size_t i = 0; i < r.rounds.size(); ++i) {
      h << RoundHtml(r.rounds[i], i);
      h << figure_of("discovery_gap_round" + std::to_string(i + 1));
    }
    h << "<h3>What the final model leaves</h3>";
    if (r.remaining.empty())
      h << "<p class=\"ok\">No significant disagreement remains.</p>";
    else
      h << TestsTableHtml(r.remaining, "Significant disagreements that remain");
    h << figure_of("discovery_residuals");
  }
  h << "</section>";
  return h.str();
}

}  // namespace hoof::report::internal
