// The report's Trials section: each trial's measurement and its disagreement with the model on
// the scale of its prediction interval (/prediction), beside the precision-only z of
// /comparison (docs/report.md, "Trials").
#include <cmath>
#include <map>
#include <optional>
#include <sstream>

#include "core/frames.h"
#include "discovery/discovery_tables.h"
#include "format/number_format.h"
#include "report/html_parts.h"

namespace hoof::report::internal {
namespace {

namespace fs = std::filesystem;

/// Probability that |z| > 3 for a standard normal z.
constexpr double kBeyond3 = 0.0026997960632601866;

std::string Cell(double v, bool mark, const char* extra = "") {
  std::ostringstream h;
  h << "<td class=\"num" << extra << (mark && std::abs(v) > 3.0 ? " bad" : "") << "\">"
    << format::Number(v, format::Kind::kStatistic) << "</td>";
  return h.str();
}

/// The paragraph that says what the two z are and how they relate to the Discovery section.
std::string Explanation(const std::optional<discovery::BaselinePredictions>& p,
                        const std::string& read_error, bool has_discovery) {
  std::ostringstream h;
  h << "<div class=\"note\" id=\"trial-z-note\"><p><b>Prediction z</b> = (measured &minus; "
       "predicted) / s.d. of a new trial's residual, for the velocity after impact along the "
       "surface (v<sub>x</sub>), normal to it (v<sub>y</sub>) and the spin (w d<sub>EC</sub>). "
       "The s.d. is that of a 95&nbsp;% prediction interval: the trial's own measurement error, "
       "the trial-to-trial scatter of its surface's &zeta; and &mu; carried through the model, "
       "and a systematic measurement error, fitted as the discovery workflow fits its baseline, "
       "to the study's other trials, and the error of the fitted &zeta; and &mu; "
       "(<code>/prediction</code>). As the scatter is estimated from the surface's few trials, "
       "the ratio is read as Student's t on the surface's degrees of freedom and shown as the "
       "normal z of the same tail probability. |z| &gt; 3 is marked.</p>";
  if (!read_error.empty()) {
    h << "<p class=\"bad\">The prediction tables cannot be read: " << HtmlEscape(read_error)
      << "</p>";
  } else if (!p) {
    h << "<p class=\"bad\">This study file has no prediction intervals (it was written before "
         "they were computed): run <code>hoofimpact run</code> again to get them. Only the "
         "precision-only z is shown.</p>";
  } else if (!p->success) {
    h << "<p class=\"bad\">No prediction intervals: " << HtmlEscape(p->message) << ".</p>";
  } else {
    int n = 0, over = 0;
    for (const auto& t : p->trials)
      for (int c = 0; c < 3; ++c)
        if (std::isfinite(t.z[c])) {
          ++n;
          over += std::abs(t.z[c]) > 3.0 ? 1 : 0;
        }
    h << "<p id=\"prediction-z-count\">" << over << " of " << n
      << " trial components have |prediction z| &gt; 3; by chance alone about "
      << format::Significant(n * kBeyond3, 2) << " would (0.27&nbsp;% each).</p>";
  }
  h << "<p><b>Precision-only z</b> = (measured &minus; simulated) / the combined standard error "
       "of the measurement and of the surface's <em>mean</em> coefficients (<code>/comparison/"
       "trials</code>). It leaves out the trial-to-trial scatter of the coefficients, so on a "
       "study with realistic scatter it is large for many trials although the model holds: it "
       "says how precisely each trial is measured, not whether the model fails.</p>"
    << "<p>"
    << (has_discovery ? "The <a href=\"#discovery\">Discovery</a> section"
                      : "Discovery (<code>hoofimpact discover</code>, not run on this study)")
    << " tests the same residuals under the same noise model for structure that trials share: a "
       "trend with speed or angle, a level per surface. Such structure widens the noise model "
       "that these intervals come from, so a missing effect shows there, not as single trials "
       "beyond 3; a trial beyond 3 is an outlier to look at.</p></div>";
  return h.str();
}

/// The Impacts table: every impact of every trial (/impacts), when some trial's clip holds more
/// than one; empty otherwise.
std::string ImpactsTable(const std::vector<studyfile::ImpactResult>& impacts) {
  bool several = false;
  for (const auto& k : impacts) several = several || k.impact_index > 0;
  if (!several) return "";
  const std::string pm = " &plusmn; ";
  std::ostringstream h;
  h << "<h3 id=\"impacts\">Impacts</h3><p>Every impact found in each trial's clip, each measured "
       "on its own from the flight on either side (docs/tracking.md, &ldquo;Several "
       "impacts&rdquo;); the trial's row above is its first impact measured (&#9679;).</p>"
       "<table class=\"data\" id=\"impact-table\"><thead><tr><th>trial</th><th>impact</th>"
       "<th>frame</th><th>time (ms)</th><th>v<sub>y</sub> before (m/s)</th>"
       "<th>v<sub>y</sub> after (m/s)</th><th>e</th><th>&mu;<sub>eff</sub></th><th>note</th>"
       "</tr></thead><tbody>";
  for (const auto& k : impacts) {
    h << "<tr class=\"" << (k.success ? "impact" : "impact failed") << "\"><td>"
      << HtmlEscape(k.trial) << "</td><td class=\"num\">" << k.impact_index
      << (k.is_main ? " &#9679;" : "") << "</td><td class=\"num\">" << k.lowest_frame << "</td>";
    if (!k.success) {
      h << "<td colspan=\"5\" class=\"bad\">not measured</td><td>" << HtmlEscape(k.error)
        << "</td></tr>";
      continue;
    }
    h << "<td class=\"num\">" << format::Number(k.impact_time_s * 1e3) << "</td><td class=\"num\">"
      << format::WithError(k.v_SC_before_m_s.y(), k.v_SC_before_se_m_s.y(), format::Kind::kMeasured,
                           pm)
      << "</td><td class=\"num\">"
      << format::WithError(k.v_SC_after_m_s.y(), k.v_SC_after_se_m_s.y(), format::Kind::kMeasured,
                           pm)
      << "</td><td class=\"num\">" << format::WithError(k.e, k.e_se, format::Kind::kCoefficient, pm)
      << "</td><td class=\"num\">"
      << format::WithError(k.mu_eff, k.mu_eff_se, format::Kind::kCoefficient, pm)
      << "</td><td></td></tr>";
  }
  h << "</tbody></table>";
  return h.str();
}

}  // namespace

std::string TrialsSection(const studyfile::StudyResults& study,
                          const std::vector<compare::ComparedTrial>& compared, const fs::path& h5,
                          HtmlReportSummary& summary) {
  std::map<std::string, const compare::TrialComparison*> row_of;
  for (const compare::ComparedTrial& t : compared) row_of[t.id] = &t.comparison;
  std::optional<discovery::BaselinePredictions> predictions;
  std::string read_error;
  try {
    predictions = discovery::ReadPredictions(h5);
  } catch (const std::exception& e) {
    read_error = e.what();
    summary.notes += std::string("prediction: ") + e.what() + "\n";
  }
  std::map<std::string, const discovery::TrialPrediction*> prediction_of;
  if (predictions)
    for (const auto& p : predictions->trials) prediction_of[p.id] = &p;

  std::ostringstream h;
  h << "<section id=\"trials\"><h2>Trials</h2>"
    << Explanation(predictions, read_error, summary.discovery)
    << "<table class=\"data\" id=\"trial-table\"><thead><tr><th rowspan=\"2\">trial</th>"
       "<th rowspan=\"2\">surface</th><th rowspan=\"2\">angle (&deg;)</th>"
       "<th rowspan=\"2\">speed (m/s)</th><th rowspan=\"2\">e</th><th rowspan=\"2\">"
       "&mu;<sub>eff</sub></th><th rowspan=\"2\">flags</th>"
       "<th colspan=\"3\" class=\"group\">prediction z</th>"
       "<th colspan=\"3\" class=\"group secondary\">precision-only z</th>"
       "<th rowspan=\"2\">note</th></tr><tr>"
       "<th>v<sub>x</sub></th><th>v<sub>y</sub></th><th>w</th>"
       "<th class=\"secondary\">v<sub>x</sub></th><th class=\"secondary\">v<sub>y</sub></th>"
       "<th class=\"secondary\">w</th></tr></thead><tbody>";
  const std::string pm = " &plusmn; ";
  for (const auto& t : study.trials) {
    h << "<tr class=\"" << (t.success ? "trial" : "trial failed") << "\"><td>" << HtmlEscape(t.id)
      << "</td><td>" << HtmlEscape(t.surface) << "</td><td class=\"num\">"
      << format::Number(t.surface_angle_deg) << "</td><td class=\"num\">"
      << format::Number(t.nominal_speed_m_s) << "</td>";
    if (!t.success) {
      h << "<td colspan=\"9\" class=\"bad\">failed</td><td>" << HtmlEscape(t.error) << "</td></tr>";
      continue;
    }
    // mu_eff is an oblique-impact measure (as in the paper): undefined for normal impacts.
    h << "<td class=\"num\">" << format::WithError(t.e, t.e_se, format::Kind::kCoefficient, pm)
      << "</td><td class=\"num\">"
      << format::WithError(t.mu_eff, t.mu_eff_se, format::Kind::kCoefficient, pm) << "</td><td>";
    for (const auto& f : t.flags) h << "<span class=\"flag\">" << HtmlEscape(f) << "</span> ";
    h << "</td>";
    const auto p = prediction_of.find(t.id);
    for (int c = 0; c < 3; ++c)
      h << Cell(p == prediction_of.end() ? core::kNaN : p->second->z[c], true, " prediction-z");
    const auto it = row_of.find(t.id);
    const compare::TrialComparison* cmp = it == row_of.end() ? nullptr : it->second;
    for (const double v :
         {cmp ? cmp->v_SC_after_z.x() : core::kNaN, cmp ? cmp->v_SC_after_z.y() : core::kNaN,
          cmp ? cmp->w_after_z : core::kNaN})
      h << Cell(v, false, " secondary precision-z");
    std::string note;
    if (cmp && !cmp->success) note = cmp->message;
    if (predictions && predictions->success && p == prediction_of.end())
      note +=
          std::string(note.empty() ? "" : "; ") + "no prediction (no fitted surface model for it)";
    h << "<td>" << HtmlEscape(note) << "</td></tr>";
  }
  h << "</tbody></table>" << ImpactsTable(studyfile::ReadStudyImpacts(h5)) << "</section>";
  return h.str();
}

}  // namespace hoof::report::internal
