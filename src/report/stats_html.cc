// The report's Statistics section (docs/cli.md, "report"; docs/statistics.md): what the
// statistics step did, per response and factor, in the order it did it. Bartlett's test of equal
// variances; the Box-Cox transform where Bartlett rejects; the one-way ANOVA on the scale that
// was analysed, with Welch's ANOVA beside it; Fisher's LSD groups as letters. Then the
// original-scale tables where a transform was applied (labelled as not the result), the cells
// and the two-way table. Every number goes through hoof::format.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "format/number_format.h"
#include "report/html_parts.h"
#include "stats/compact_letters.h"
#include "studyfile/stats_tables.h"

namespace hoof::report::internal {
namespace {

namespace fs = std::filesystem;
using format::Kind;
using studyfile::AnovaRow;
using studyfile::GroupRow;
using studyfile::LsdRow;
using studyfile::StoredFactor;
using studyfile::StoredResponse;
using studyfile::StoredScale;
using studyfile::VarianceTestRow;

std::string NumberText(double v, Kind kind) { return HtmlEscape(format::Number(v, kind)); }
std::string P(double p) { return HtmlEscape(format::P(p)); }
std::string PValue(double p) { return HtmlEscape(format::PValue(p)); }
std::string Count(double n) { return std::isfinite(n) ? std::to_string(std::llround(n)) : "n/a"; }

/// A numeric cell; `sig` marks a p below the level.
std::string Td(const std::string& text, bool sig = false) {
  return std::string("<td class=\"num") + (sig ? " sig" : "") + "\">" + text + "</td>";
}

/// The response in words, with its unit.
std::string ResponseTitle(const std::string& response) {
  if (response == "e")
    return "e, the coefficient of restitution (normal velocity after over before impact; "
           "dimensionless)";
  if (response == "mu_eff")
    return "mu_eff, the effective friction coefficient (tangential over normal impulse; oblique "
           "trials only; dimensionless)";
  return response;
}

/// `formula` (DescribeBoxCox's, in y) written in the response's name: "ln(y)" -> "ln(e)".
std::string InResponse(const std::string& formula, const std::string& response) {
  std::string out;
  for (std::size_t i = 0; i < formula.size(); ++i) {
    const auto word = [&](std::size_t j) {
      return j < formula.size() &&
             (std::isalnum(static_cast<unsigned char>(formula[j])) || formula[j] == '_');
    };
    if (formula[i] == 'y' && !(i > 0 && word(i - 1)) && !word(i + 1))
      out += response;
    else
      out += formula[i];
  }
  return out;
}

/// A setting as given ("0.05"), not a measured quantity.
std::string Setting(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

/// The level the statistics ran at, from /stats's description ("... (alpha 0.05, ...").
std::optional<double> Alpha(const std::string& description) {
  std::smatch m;
  static const std::regex re("alpha ([0-9.eE+-]+)");
  if (!std::regex_search(description, m, re)) return std::nullopt;
  try {
    return std::stod(m[1].str());
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

const VarianceTestRow* Test(const StoredScale& s, const std::string& name) {
  for (const auto& t : s.tests.rows)
    if (t.test == name) return &t;
  return nullptr;
}

const AnovaRow* Between(const StoredScale& s) {
  for (const auto& r : s.anova.rows)
    if (r.source == "between") return &r;
  return nullptr;
}

/// "K² = 8.21, df = 2, p = 0.017".
std::string BartlettText(const VarianceTestRow& b) {
  return "K&sup2; = " + NumberText(b.statistic, Kind::kStatistic) + ", df = " + Count(b.df1) +
         ", " + PValue(b.p) + (b.note.empty() ? "" : " (" + HtmlEscape(b.note) + ")");
}

/// The one-way ANOVA table with plain headers.
std::string AnovaTable(const StoredScale& s, const std::string& caption, const std::string& id,
                       double alpha) {
  std::ostringstream h;
  h << "<table class=\"data anova\"" << (id.empty() ? "" : " id=\"" + id + "\"") << "><caption>"
    << caption << "</caption><thead><tr><th>Source</th><th>df</th><th>Sum of squares</th>"
    << "<th>Mean square</th><th>F</th><th>p</th><th>&eta;&sup2;</th></tr></thead><tbody>";
  for (const AnovaRow& r : s.anova.rows) {
    const std::string source = r.source == "between"  ? "Between groups"
                               : r.source == "within" ? "Within groups (error)"
                               : r.source == "total"  ? "Total"
                                                      : HtmlEscape(r.source);
    const bool test = r.source == "between";
    h << "<tr><td>" << source << "</td>" << Td(std::to_string(r.df))
      << Td(NumberText(r.ss, Kind::kSum))
      << Td(r.source == "total" ? "" : NumberText(r.ms, Kind::kSum))
      << Td(test ? NumberText(r.f, Kind::kStatistic) : "")
      << Td(test ? P(r.p) : "", test && r.p < alpha)
      << Td(test ? NumberText(r.eta_squared, Kind::kCoefficient) : "") << "</tr>";
  }
  h << "</tbody></table>";
  return h.str();
}

/// Welch's ANOVA as a small table (or why it was not computed).
std::string WelchTable(const StoredScale& s, const std::string& id, double alpha) {
  const VarianceTestRow* w = Test(s, "welch");
  std::ostringstream h;
  h << "<table class=\"data welch\" id=\"" << id << "\"><caption>Welch's ANOVA (does not assume "
    << "equal variances)</caption><thead><tr><th>F</th><th>df1</th><th>df2</th><th>p</th></tr>"
    << "</thead><tbody><tr>";
  if (w && std::isfinite(w->statistic))
    h << Td(NumberText(w->statistic, Kind::kStatistic)) << Td(Count(w->df1))
      << Td(NumberText(w->df2, Kind::kStatistic)) << Td(P(w->p), w->p < alpha);
  else
    h << "<td colspan=\"4\">n/a: " << HtmlEscape(w ? w->note : "not stored") << "</td>";
  h << "</tr></tbody></table>";
  return h.str();
}

/// The group means with their LSD letters; `original` holds the groups on the scale of the
/// data when `analysed` is a transformed scale (then both means are shown).
std::string LetterTable(const StoredScale& analysed, const StoredScale* original,
                        const std::string& factor, const std::string& response,
                        const std::string& scale_name, const std::string& id) {
  std::vector<std::string> labels;
  std::vector<double> means;
  for (const GroupRow& g : analysed.groups.rows) {
    labels.push_back(g.group);
    means.push_back(g.mean);
  }
  std::vector<std::pair<std::string, std::string>> different;
  for (const LsdRow& r : analysed.lsd.rows)
    if (r.significant) different.emplace_back(r.a, r.b);
  const stats::LetterDisplay letters = stats::CompactLetters(labels, means, different);
  std::ostringstream h;
  h << "<table class=\"data letters\" id=\"" << id << "\"><caption>Means by " << HtmlEscape(factor)
    << " with Fisher's LSD groups</caption><thead><tr><th>" << HtmlEscape(factor)
    << "</th><th>n</th><th>Mean " << HtmlEscape(response) << "</th><th>s.d.</th>";
  if (original) h << "<th>Mean of " << HtmlEscape(scale_name) << "</th>";
  h << "<th>LSD group</th></tr></thead><tbody>";
  // Rows by the analysed mean, highest first, as papers print them.
  std::vector<std::size_t> order(labels.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return means[a] > means[b]; });
  for (const std::size_t g : order) {
    const GroupRow& a = analysed.groups.rows[g];
    // The group as measured: `a` itself, or its row on the original scale.
    const GroupRow* measured = original ? nullptr : &a;
    if (original)
      for (const GroupRow& r : original->groups.rows)
        if (r.group == a.group) measured = &r;
    const bool sd = measured && measured->n > 1;  // one trial has no s.d.
    h << "<tr><td>" << HtmlEscape(a.group) << "</td>" << Td(std::to_string(a.n))
      << Td(measured ? NumberText(measured->mean, Kind::kCoefficient) : format::kUndefined)
      << Td(sd ? NumberText(measured->sd, Kind::kError) : format::kUndefined);
    if (original) h << Td(NumberText(a.mean, Kind::kCoefficient));
    h << "<td class=\"lsd-letters\" data-group=\"" << HtmlEscape(a.group) << "\">"
      << letters.letters[g] << "</td></tr>";
  }
  h << "</tbody></table>";
  return h.str();
}

/// The LSD pairs (differences on the analysed scale).
std::string LsdPairsTable(const StoredScale& s, const std::string& scale_name) {
  std::ostringstream h;
  h << "<details><summary>Fisher's LSD pairs (" << s.lsd.rows.size()
    << ", unadjusted)</summary><table class=\"data lsd\"><thead><tr><th>Pair</th>"
    << "<th>Difference of " << HtmlEscape(scale_name) << "</th><th>s.e.</th><th>t</th>"
    << "<th>df</th><th>p</th><th>95 % interval</th><th>Different</th></tr></thead><tbody>";
  for (const LsdRow& r : s.lsd.rows)
    h << "<tr><td>" << HtmlEscape(r.a) << " &minus; " << HtmlEscape(r.b) << "</td>"
      << Td(NumberText(r.difference, Kind::kCoefficient))
      << Td(NumberText(r.standard_error, Kind::kError)) << Td(NumberText(r.t, Kind::kStatistic))
      << Td(std::to_string(r.df)) << Td(P(r.p), r.significant)
      << Td(HtmlEscape(format::Interval(r.ci_low, r.ci_high, Kind::kCoefficient))) << "<td>"
      << (r.significant ? "yes" : "no") << "</td></tr>";
  h << "</tbody></table></details>";
  return h.str();
}

/// One response by one factor: the test chain, the result and the conclusion.
std::string FactorPart(const StoredResponse& r, const StoredFactor& f,
                       const std::optional<double>& alpha) {
  const std::string id = "stats-" + r.response + "-" + f.factor;
  const std::string level = alpha ? Setting(*alpha) : std::string(format::kUndefined);
  const double mark = alpha.value_or(0.05);  // the level p is marked at
  const bool transformed = f.transform.applied && f.transformed.has_value();
  const StoredScale& analysed = transformed ? *f.transformed : f.original;
  const std::string scale_name =
      transformed ? InResponse(f.transform.formula, r.response) : r.response;
  const VarianceTestRow* bartlett = Test(f.original, "bartlett");
  const AnovaRow* between = Between(analysed);
  const VarianceTestRow* welch = Test(analysed, "welch");
  const bool lsd_ran = !analysed.lsd.rows.empty();

  std::ostringstream h;
  h << "<div class=\"factor\" id=\"" << id << "\"><h4>" << HtmlEscape(r.response) << " by "
    << HtmlEscape(f.factor) << "</h4>";
  // The conclusion in one line.
  h << "<p class=\"conclusion\">";
  if (between) {
    const bool effect = lsd_ran;  // the LSD runs exactly when the ANOVA's p < alpha
    h << (effect ? "<b>" + HtmlEscape(f.factor) + " affects " + HtmlEscape(r.response) + "</b>"
                 : "No significant effect of " + HtmlEscape(f.factor) + " on " +
                       HtmlEscape(r.response))
      << " (ANOVA" << (transformed ? " on " + HtmlEscape(scale_name) : "") << ", "
      << PValue(between->p) << "; Welch "
      << (welch && std::isfinite(welch->p) ? PValue(welch->p) : std::string("n/a")) << ")";
    if (welch && std::isfinite(welch->p) && alpha && (welch->p < *alpha) != effect)
      h << ". Welch's ANOVA, which does not assume equal variances, "
        << (welch->p < *alpha ? "finds" : "does not find") << " an effect at &alpha; = " << level;
    h << ".";
  }
  h << "</p><ol class=\"test-chain\">";

  // 1. Bartlett.
  h << "<li class=\"bartlett\"><b>Bartlett's test of equal variances</b> across the "
    << HtmlEscape(f.factor) << " groups: ";
  if (bartlett)
    h << "<span class=\"bartlett-result\" data-p=\"" << format::Significant(bartlett->p, 17)
      << "\">" << BartlettText(*bartlett) << "</span>: "
      << (f.transform.considered ? "<b>equal variances rejected</b>"
                                 : "equal variances not rejected")
      << " at &alpha; = " << level << ".";
  else
    h << "not stored.";
  h << "</li>";

  // 2. The transform.
  h << "<li class=\"transform\"><b>Variance-stabilizing transform</b>: ";
  const auto& t = f.transform;
  if (!t.considered) {
    h << "none needed (Bartlett did not reject); the analysis is on " << HtmlEscape(r.response)
      << " as measured.";
  } else {
    h << "Box-Cox power transform, maximum-likelihood &lambda; = "
      << NumberText(t.lambda_ml, Kind::kStatistic) << " (95 % interval "
      << HtmlEscape(format::Interval(t.ci_low, t.ci_high, Kind::kStatistic)) << "); ";
    static const double kSimple[] = {-2, -1, -0.5, 0, 0.5, 1, 2};
    const bool simple =
        std::find(std::begin(kSimple), std::end(kSimple), t.lambda) != std::end(kSimple);
    h << "&lambda; = " << NumberText(t.lambda, Kind::kStatistic)
      << (simple ? " used, the simple power nearest it inside that interval"
                 : " used (no simple power lies inside the interval)");
    if (std::isfinite(t.shift) && t.shift != 0)
      h << ", after shifting every value by " << NumberText(t.shift, Kind::kCoefficient)
        << " to make it positive";
    if (transformed) {
      h << ". <b>The analysis below is on the transformed scale, <span class=\"transform-formula\">"
        << HtmlEscape(scale_name) << "</span></b>";
      if (const VarianceTestRow* again = Test(analysed, "bartlett"))
        h << "; Bartlett on it: " << BartlettText(*again)
          << (again->p < mark ? " (variances still differ)" : " (no longer rejected)");
      h << ".";
    } else {
      h << ": &lambda; = 1 is no transform, so the data are analysed as measured.";
    }
  }
  h << "</li>";

  // 3. The ANOVA on the analysed scale, Welch beside it.
  h << "<li class=\"anova\"><b>One-way ANOVA on " << HtmlEscape(scale_name) << "</b>"
    << (transformed ? " (the result)" : "") << ", with Welch's ANOVA beside it:"
    << "<div class=\"tables\">"
    << AnovaTable(analysed,
                  "One-way ANOVA of " + HtmlEscape(scale_name) + " by " + HtmlEscape(f.factor),
                  id + "-anova", mark)
    << WelchTable(analysed, id + "-welch", mark) << "</div></li>";

  // 4. LSD letters.
  h << "<li class=\"lsd\"><b>Fisher's LSD</b>"
    << (transformed ? " on " + HtmlEscape(scale_name) : "") << ": ";
  if (lsd_ran)
    h << "groups that share a letter do not differ significantly (p &ge; &alpha; = " << level
      << ", unadjusted); letter a holds the highest mean.";
  else
    h << "not run, as the ANOVA is not significant (protected LSD): no pair is declared "
         "different, so every group carries the letter a.";
  h << LetterTable(analysed, transformed ? &f.original : nullptr, f.factor, r.response, scale_name,
                   id + "-letters");
  if (lsd_ran) h << LsdPairsTable(analysed, scale_name);
  h << "</li></ol>";

  // The original scale, where it is not the result.
  if (transformed) {
    h << "<details class=\"original-scale\"><summary>The same on " << HtmlEscape(r.response)
      << " as measured: <b>not the result</b>, as its variances differ</summary>"
      << "<div class=\"tables\">"
      << AnovaTable(f.original,
                    "Not the result: one-way ANOVA of " + HtmlEscape(r.response) +
                        " (untransformed) by " + HtmlEscape(f.factor),
                    "", mark)
      << WelchTable(f.original, id + "-welch-original", mark) << "</div></details>";
  }
  h << "</div>";
  return h.str();
}

/// Mean (s.d., n) per surface x angle cell.
std::string CellsTable(const StoredResponse& r) {
  std::ostringstream h;
  h << "<table class=\"data cells\" id=\"stats-" << r.response << "-cells\"><caption>"
    << HtmlEscape(r.response) << " per surface and angle</caption><thead><tr><th>Cell</th>"
    << "<th>n</th><th>Mean</th><th>s.d.</th></tr></thead><tbody>";
  for (const auto& c : r.cells.rows)
    h << "<tr><td>" << HtmlEscape(c.surface) << ", " << HtmlEscape(c.angle_deg) << "&deg;</td>"
      << Td(std::to_string(c.n)) << Td(NumberText(c.mean, Kind::kCoefficient))
      << Td(c.n > 1 ? NumberText(c.sd, Kind::kError) : std::string(format::kUndefined)) << "</tr>";
  if (r.cells.rows.empty()) h << "<tr><td colspan=\"4\">(no cells)</td></tr>";
  h << "</tbody></table>";
  return h.str();
}

std::string TwoWayTable(const StoredResponse& r, double alpha) {
  std::ostringstream h;
  const std::string& d = r.two_way->description;
  h << "<table class=\"data two-way\"><caption>" << HtmlEscape(d.empty() ? "Two-way ANOVA" : d)
    << " (on " << HtmlEscape(r.response) << " as measured)</caption><thead><tr><th>Source</th>"
    << "<th>df</th><th>Sum of squares</th><th>Mean square</th><th>F</th><th>p</th></tr></thead>"
    << "<tbody>";
  for (const auto& w : r.two_way->rows) {
    const bool test = std::isfinite(w.f);
    std::string source = w.source == "error" ? "Error" : w.source;
    for (std::size_t pos; (pos = source.find(" x ")) != std::string::npos;)
      source.replace(pos, 3, " \xC3\x97 ");
    if (!source.empty()) source[0] = static_cast<char>(std::toupper(source[0]));
    h << "<tr><td>" << HtmlEscape(source) << "</td>" << Td(std::to_string(w.df))
      << Td(NumberText(w.ss, Kind::kSum)) << Td(NumberText(w.ms, Kind::kSum))
      << Td(test ? NumberText(w.f, Kind::kStatistic) : "")
      << Td(test ? P(w.p) : "", test && w.p < alpha) << "</tr>";
  }
  h << "</tbody></table>";
  return h.str();
}

std::string NotesList(const StoredResponse& r) {
  if (r.notes.empty()) return "";
  std::ostringstream h;
  h << "<p class=\"note\">Not computed:</p><ul class=\"stats-notes\">";
  for (const auto& n : r.notes) {
    std::string what = n.analysis;
    if (what.rfind("by_", 0) == 0) what = "by " + what.substr(3);
    if (what == "two_way") what = "two-way ANOVA";
    std::string why = n.note;
    if (why.rfind("not computed: ", 0) == 0) why = why.substr(14);
    if (why.empty()) why = "no reason stored";
    h << "<li>" << HtmlEscape(r.response) << " " << HtmlEscape(what) << ": " << HtmlEscape(why)
      << "</li>";
  }
  h << "</ul>";
  return h.str();
}

}  // namespace

std::string StatsHtml(const studyfile::StoredStatistics& s) {
  std::ostringstream h;
  const std::optional<double> alpha = Alpha(s.description);
  h << "<p class=\"note\">For each response and factor, the steps the statistics took, in order "
       "(docs/statistics.md): Bartlett's test of equal variances; where it rejects, a Box-Cox "
       "transform, after which everything is computed on the transformed scale; the one-way "
       "ANOVA on the scale analysed, with Welch's ANOVA beside it; and Fisher's LSD groups as "
       "letters. Significance level &alpha; = "
    << (alpha ? Setting(*alpha) : std::string(format::kUndefined))
    << ". e and mu_eff are ratios (dimensionless): their means, s.d. and differences carry no "
       "unit, and sums of squares and mean squares are in squared units of the scale analysed. "
       "The s.d. of a single trial is undefined (n/a).</p>";
  if (!s.excluded.empty()) {
    h << "<p class=\"note\">Left out of every analysis:</p><ul>";
    for (const auto& x : s.excluded)
      h << "<li>" << HtmlEscape(x.id) << ": " << HtmlEscape(x.reason) << "</li>";
    h << "</ul>";
  }
  for (const StoredResponse& r : s.responses) {
    h << "<div class=\"response\" id=\"stats-" << r.response << "\"><h3>"
      << HtmlEscape(ResponseTitle(r.response)) << "</h3>";
    const std::string& d = r.cells.description;
    if (const auto comma = d.find("angle, "); comma != std::string::npos)
      h << "<p class=\"note\">Trials: " << HtmlEscape(d.substr(comma + 7)) << ".</p>";
    if (r.cells.rows.empty() && r.factors.empty()) {
      h << "<p class=\"note\">No trial to analyse.</p></div>";
      continue;
    }
    for (const StoredFactor& f : r.factors) h << FactorPart(r, f, alpha);
    h << "<h4>Cells and the two-way table</h4><div class=\"tables\">" << CellsTable(r);
    if (r.two_way) h << TwoWayTable(r, alpha.value_or(0.05));
    h << "</div>" << NotesList(r) << "</div>";
  }
  if (s.responses.empty()) h << "<p class=\"bad\">No response in the statistics tables.</p>";
  return h.str();
}

std::string StatsSection(const fs::path& h5, HtmlReportSummary& summary) {
  std::ostringstream h;
  h << "<section id=\"statistics\"><h2>Statistics</h2>";
  try {
    if (!studyfile::HasStatistics(h5)) {
      h << "<p class=\"bad\">No statistics in the study file: run <code>hoofimpact stats</code>."
        << "</p></section>";
      return h.str();
    }
    h << StatsHtml(studyfile::ReadStatistics(h5));
  } catch (const std::exception& e) {
    h << "<p class=\"bad\">The statistics tables cannot be read: " << HtmlEscape(e.what())
      << "</p></section>";
    summary.notes += std::string("statistics: ") + e.what() + "\n";
    return h.str();
  }
  h << "</section>";
  return h.str();
}

}  // namespace hoof::report::internal
