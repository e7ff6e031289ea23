#include "report/html_report.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include <unistd.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "discovery/discovery_tables.h"
#include "io/atomic_file.h"
#include "io/interrupt.h"
#include "pipeline/study_format.h"
#include "report/comparison_figures.h"
#include "report/discovery_figures.h"
#include "report/figures.h"
#include "report/report_assets.h"
#include "studyfile/study_file.h"
#include "tracking/frame_source.h"

namespace hoof::report {
namespace {

namespace fs = std::filesystem;
using studyfile::Table;

// ---- small helpers ------------------------------------------------------------------------

std::string Fmt(double v, int precision = 4) {
  if (!std::isfinite(v)) return "&ndash;";
  std::ostringstream s;
  s.precision(precision);
  s << v;
  return s.str();
}

/// A number for the embedded JSON: NaN and infinities become null.
std::string JsonNumber(double v) {
  if (!std::isfinite(v)) return "null";
  std::ostringstream s;
  s.precision(7);
  s << v;
  return s.str();
}

/// A JSON string literal that is also safe inside <script> ("</" cannot close the element).
std::string JsonString(std::string_view text) {
  std::string out = "\"";
  for (char c : text) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '<':
        out += "\\u003c";
        break;
      case '>':
        out += "\\u003e";
        break;
      case '&':
        out += "\\u0026";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c));
          out += buf;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

std::string ReadBinary(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot read");
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::optional<Table> TryReadTable(const fs::path& h5, const std::string& path) {
  try {
    return studyfile::ReadTable(h5, path);
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

const studyfile::Column* FindColumn(const Table& t, const std::string& name) {
  for (const auto& c : t.columns)
    if (c.name == name) return &c;
  return nullptr;
}

double Num(const Table& t, const std::string& name, std::size_t row) {
  const auto* c = FindColumn(t, name);
  if (!c || row >= c->size()) return std::nan("");
  if (const auto* d = std::get_if<std::vector<double>>(&c->values)) return (*d)[row];
  if (const auto* i = std::get_if<std::vector<std::int64_t>>(&c->values))
    return static_cast<double>((*i)[row]);
  return std::nan("");
}

std::string Text(const Table& t, const std::string& name, std::size_t row) {
  const auto* c = FindColumn(t, name);
  if (!c || row >= c->size()) return "";
  if (const auto* s = std::get_if<std::vector<std::string>>(&c->values)) return (*s)[row];
  return "";
}

std::size_t Rows(const Table& t) { return t.columns.empty() ? 0 : t.columns.front().size(); }

/// Any table as an HTML table: numbers to 4 significant digits, p-values to 3.
std::string RenderTable(const Table& t, const std::string& caption) {
  std::ostringstream h;
  h << "<table class=\"data\"><caption>" << HtmlEscape(caption) << "</caption><thead><tr>";
  for (const auto& c : t.columns)
    h << "<th title=\"" << HtmlEscape(c.description) << "\">" << HtmlEscape(c.name) << "</th>";
  h << "</tr></thead><tbody>";
  for (std::size_t r = 0; r < Rows(t); ++r) {
    h << "<tr>";
    for (const auto& c : t.columns) {
      if (const auto* s = std::get_if<std::vector<std::string>>(&c.values)) {
        h << "<td>" << HtmlEscape((*s)[r]) << "</td>";
      } else {
        const double v = Num(t, c.name, r);
        const bool small_p = c.name == "p" && std::isfinite(v) && v < 0.05;
        h << "<td class=\"num" << (small_p ? " sig" : "") << "\">" << Fmt(v, c.name == "p" ? 3 : 4)
          << "</td>";
      }
    }
    h << "</tr>";
  }
  if (Rows(t) == 0) h << "<tr><td colspan=\"" << t.columns.size() << "\">(no rows)</td></tr>";
  h << "</tbody></table>";
  return h.str();
}

// ---- sections ----------------------------------------------------------------------------

std::string SummarySection(const studyfile::StudyResults& study, const fs::path& h5) {
  std::ostringstream h;
  int measured = 0;
  for (const auto& t : study.trials) measured += t.success ? 1 : 0;
  const int failed = static_cast<int>(study.trials.size()) - measured;
  h << "<section id=\"summary\"><h2>Study</h2><dl class=\"facts\">"
    << "<dt>Name</dt><dd>" << HtmlEscape(study.name) << "</dd>"
    << "<dt>Study file</dt><dd><code>" << HtmlEscape(fs::absolute(h5).string()) << "</code></dd>"
    << "<dt>Study folder</dt><dd><code>" << HtmlEscape(study.study_dir) << "</code></dd>"
    << "<dt>Created</dt><dd>" << HtmlEscape(study.created_utc) << " by hoofimpact "
    << HtmlEscape(study.hoofimpact_version) << "</dd>"
    << "<dt>Trials</dt><dd><span id=\"n-trials\">" << study.trials.size() << "</span>: "
    << "<span class=\"ok\">" << measured << " measured</span>, <span class=\""
    << (failed > 0 ? "bad" : "ok") << "\">" << failed << " failed</span></dd></dl>";
  if (failed > 0) {
    h << "<h3>Failed trials</h3><ul class=\"failed\">";
    for (const auto& t : study.trials)
      if (!t.success)
        h << "<li><b>" << HtmlEscape(t.id) << "</b>: " << HtmlEscape(t.error) << "</li>";
    h << "</ul>";
  }
  h << "</section>";
  return h.str();
}

std::string ModelSection(const Table& surfaces) {
  std::ostringstream h;
  h << "<section id=\"model\"><h2>Contact model per surface</h2>"
    << "<p class=\"note\">Fitted from the measured trials (<code>/comparison/surfaces</code>): "
       "zeta from the normal impacts, mu from the oblique ones. The stiffness k is not "
       "identified by velocities alone.</p>"
    << "<table class=\"data\"><thead><tr><th>surface</th><th>normal trials</th><th>oblique "
       "trials</th><th>zeta</th><th>zeta 95 % interval</th><th>mu</th><th>k</th><th>note</th>"
       "</tr></thead><tbody>";
  for (std::size_t r = 0; r < Rows(surfaces); ++r) {
    const bool ok = Num(surfaces, "success", r) == 1.0;
    h << "<tr><td>" << HtmlEscape(Text(surfaces, "surface", r)) << "</td><td class=\"num\">"
      << Fmt(Num(surfaces, "normal_trials", r)) << "</td><td class=\"num\">"
      << Fmt(Num(surfaces, "oblique_trials", r)) << "</td>";
    if (!ok) {
      h << "<td colspan=\"4\" class=\"bad\">no model</td><td>"
        << HtmlEscape(Text(surfaces, "message", r)) << "</td></tr>";
      continue;
    }
    const double lo = Num(surfaces, "zeta_ci_low", r), hi = Num(surfaces, "zeta_ci_high", r);
    h << "<td class=\"num\">" << Fmt(Num(surfaces, "zeta", r)) << "</td><td class=\"num\">"
      << (std::isfinite(lo) && std::isfinite(hi) ? Fmt(lo) + " .. " + Fmt(hi)
                                                 : std::string("not available"))
      << "</td><td class=\"num\">";
    const double mu = Num(surfaces, "mu", r), mu_se = Num(surfaces, "mu_se", r);
    if (Num(surfaces, "mu_only_lower_bound", r) == 1.0)
      h << "&ge; " << Fmt(mu) << " (contacts stick)";
    else
      h << Fmt(mu) << (std::isfinite(mu_se) ? " &plusmn; " + Fmt(mu_se, 2) : "");
    h << "</td><td>k not identified</td><td>" << HtmlEscape(Text(surfaces, "message", r))
      << "</td></tr>";
  }
  h << "</tbody></table></section>";
  return h.str();
}

std::string StatsSection(const fs::path& h5) {
  std::ostringstream h;
  h << "<section id=\"statistics\"><h2>Statistics</h2>";
  bool any = false;
  for (const std::string r : {"e", "mu_eff"}) {
    const std::string label =
        r == "e" ? "e (restitution)" : "mu_eff (effective friction, oblique trials)";
    std::ostringstream part;
    bool have = false;
    if (auto cells = TryReadTable(h5, "/stats/" + r + "/cells")) {
      part << RenderTable(*cells, "Mean (s.d., n) per surface x angle");
      have = true;
    }
    for (const std::string factor : {"surface", "angle", "speed"})
      if (auto anova = TryReadTable(h5, "/stats/" + r + "/by_" + factor + "/anova")) {
        part << RenderTable(*anova, "One-way ANOVA by " + factor);
        have = true;
      }
    if (auto two = TryReadTable(h5, "/stats/" + r + "/two_way")) {
      part << RenderTable(*two, "Two-way ANOVA, surface x angle");
      have = true;
    }
    if (auto notes = TryReadTable(h5, "/stats/" + r + "/notes"); notes && Rows(*notes) > 0)
      part << RenderTable(*notes, "Notes");
    if (have)
      h << "<h3>" << HtmlEscape(label) << "</h3><div class=\"tables\">" << part.str() << "</div>";
    any = any || have;
  }
  if (!any)
    h << "<p class=\"bad\">No statistics in the study file: run <code>hoofimpact stats</code>.</p>";
  h << "</section>";
  return h.str();
}

/// A fresh folder for figures drawn only to be embedded, "hoofimpact-report.tmp-<pid>-<n>" in the
/// system's temporary folder: an interrupt removes it, and the next report removes one that a
/// killed process left (RemoveStaleReportFolders).
fs::path TemporaryFigureDir() {
  return io::TemporaryPathFor(fs::temp_directory_path() / "hoofimpact-report");
}

void RemoveStaleReportFolders() {
  std::error_code ec;
  const fs::path tmp = fs::temp_directory_path(ec);
  if (ec) return;
  io::RemoveStaleTemporaries(
      tmp, [](const std::string& name) { return name.rfind("hoofimpact-report.tmp-", 0) == 0; });
}

/// A PNG figure embedded as a data URI, captioned with its file stem.
std::string FigureHtml(const fs::path& png) {
  return "<figure><img alt=\"" + HtmlEscape(png.stem().string()) +
         "\" src=\"data:image/png;base64," + Base64(ReadBinary(png)) + "\"><figcaption>" +
         HtmlEscape(png.stem().string()) + "</figcaption></figure>";
}

std::string FiguresSection(const studyfile::StudyResults& study, const fs::path& study_h5,
                           int& count) {
  const fs::path dir = TemporaryFigureDir();
  std::ostringstream h;
  h << "<section id=\"figures\"><h2>Figures</h2><div class=\"figures\">";
  try {
    // Figures 4-5 (e and mu_eff by angle and speed) and 6-8 (velocities after normal and
    // oblique impacts against the simulation, kinetic energy through an impact).
    std::vector<fs::path> paths = WriteStudyFigures(study, dir);
    for (const auto& p : WriteComparisonFigures(study_h5, dir)) paths.push_back(p);
    for (const auto& path : paths) {
      if (path.extension() != ".png") continue;
      h << FigureHtml(path);
      ++count;
    }
  } catch (...) {
    fs::remove_all(dir);
    io::UntrackTemporary(dir);
    throw;
  }
  fs::remove_all(dir);
  io::UntrackTemporary(dir);
  if (count == 0) h << "<p>No figure: no trial was measured.</p>";
  h << "</div></section>";
  return h.str();
}

std::string TrialsSection(const studyfile::StudyResults& study, const Table& cmp) {
  std::map<std::string, std::size_t> row_of;
  for (std::size_t r = 0; r < Rows(cmp); ++r) row_of[Text(cmp, "id", r)] = r;
  std::ostringstream h;
  h << "<section id=\"trials\"><h2>Trials</h2><p class=\"note\">z = (measured &minus; "
       "simulated) / combined standard error of the velocity after impact (along the surface, "
       "normal) and of the spin; |z| &gt; 3 is marked.</p><table class=\"data\" "
       "id=\"trial-table\"><thead><tr><th>trial</th><th>surface</th><th>angle (deg)</th>"
       "<th>speed (m/s)</th><th>e</th><th>mu_eff</th><th>flags</th><th>z v<sub>x</sub></th>"
       "<th>z v<sub>y</sub></th><th>z w</th><th>note</th></tr></thead><tbody>";
  for (const auto& t : study.trials) {
    h << "<tr class=\"" << (t.success ? "trial" : "trial failed") << "\"><td>" << HtmlEscape(t.id)
      << "</td><td>" << HtmlEscape(t.surface) << "</td><td class=\"num\">"
      << Fmt(t.surface_angle_deg) << "</td><td class=\"num\">" << Fmt(t.nominal_speed_m_s)
      << "</td>";
    if (!t.success) {
      h << "<td colspan=\"6\" class=\"bad\">failed</td><td>" << HtmlEscape(t.error) << "</td></tr>";
      continue;
    }
    h << "<td class=\"num\">" << Fmt(t.e) << " &plusmn; " << Fmt(t.e_se, 2)
      << "</td><td class=\"num\">"
      // mu_eff is an oblique-impact measure (as in the paper): none for normal impacts.
      << (std::isfinite(t.mu_eff) && std::abs(t.surface_angle_deg) > 0
              ? Fmt(t.mu_eff) + " &plusmn; " + Fmt(t.mu_eff_se, 2)
              : "&ndash;")
      << "</td><td>";
    for (const auto& f : t.flags) h << "<span class=\"flag\">" << HtmlEscape(f) << "</span> ";
    h << "</td>";
    const auto it = row_of.find(t.id);
    std::string note;
    for (const char* z : {"z_v_x", "z_v_y", "z_w"}) {
      const double v = it == row_of.end() ? std::nan("") : Num(cmp, z, it->second);
      h << "<td class=\"num" << (std::abs(v) > 3.0 ? " bad" : "") << "\">" << Fmt(v, 3) << "</td>";
    }
    if (it != row_of.end() && Num(cmp, "success", it->second) != 1.0)
      note = Text(cmp, "message", it->second);
    h << "<td>" << HtmlEscape(note) << "</td></tr>";
  }
  h << "</tbody></table></section>";
  return h.str();
}

// ---- discovery ---------------------------------------------------------------------------

/// "estimate +- se unit", or a dash when the estimate is undefined.
std::string EstimateHtml(double estimate, double se, const std::string& unit) {
  if (!std::isfinite(estimate)) return "&ndash;";
  std::string out = Fmt(estimate, 3);
  if (std::isfinite(se)) out += " &plusmn; " + Fmt(se, 2);
  if (!unit.empty() && unit != "1") out += " " + HtmlEscape(unit);
  return out;
}

/// A fraction as a percentage ("12.3 %"), or a dash.
std::string PercentHtml(double fraction) {
  return std::isfinite(fraction) ? Fmt(100.0 * fraction, 3) + " %" : "&ndash;";
}

/// A p-value cell, bold when `significant`.
std::string PCell(double p, bool significant) {
  return std::string("<td class=\"num") + (significant ? " sig" : "") + "\">" + Fmt(p, 3) + "</td>";
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
      stat = "F(" + Fmt(t.df1, 3) + ", " + Fmt(t.df2, 3) + ") = " + stat;
    else if (std::isfinite(t.df1) && t.df1 > 0)
      stat = "t(" + Fmt(t.df1, 3) + ") = " + stat;
    else if (t.test.find(" z") != std::string::npos)
      stat = "z = " + stat;
    h << "<tr><td>" << HtmlEscape(t.quantity) << "</td><td>" << HtmlEscape(t.scope) << "</td><td>"
      << HtmlEscape(t.covariate) << "</td><td>" << HtmlEscape(t.test) << "</td><td class=\"num\">"
      << stat << "</td><td class=\"num\">" << Fmt(t.p, 3) << "</td><td class=\"num"
      << (t.significant ? " sig" : "") << "\">" << Fmt(t.p_holm, 3) << "</td><td>"
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

std::string CandidatesTableHtml(const discovery::Round& round) {
  std::ostringstream h;
  h << "<table class=\"data discovery-candidates\"><caption>Candidate effects in rank order "
       "(1 = added or strongest evidence); held-out error in "
    << HtmlEscape(discovery::kHeldOutErrorUnit)
    << "</caption><thead><tr><th>rank</th><th>effect</th><th>form</th><th>estimate "
       "&plusmn; s.e.</th><th>LR p</th><th>&Delta;AIC</th><th>&Delta;BIC</th><th>held-out "
       "error vs current</th><th>identifiability</th><th>outcome</th><th>why</th></tr></thead>"
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
      << (c.cv_error < c.cv_error_current ? " ok" : "") << "\">" << Fmt(c.cv_error, 3) << " vs "
      << Fmt(c.cv_error_current, 3) << "</td><td>"
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
    const double nan = std::nan("");
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
       "measurement error (s.d., % of the impact speed)</caption><thead><tr><th>surface</th>"
       "<th>zeta s.d.</th><th>mu s.d.</th></tr></thead><tbody>";
  for (const auto& f : r.final_model)
    h << "<tr><td>" << HtmlEscape(f.surface) << "</td><td class=\"num\">" << Fmt(f.zeta_sd, 3)
      << "</td><td class=\"num\">" << Fmt(f.mu_sd, 3) << "</td></tr>";
  h << "</tbody></table><table class=\"data discovery-measurement\"><caption>Systematic "
       "measurement error (s.d., % of the impact speed)</caption><thead><tr><th>v_x</th>"
       "<th>v_y</th><th>w d_EC</th></tr></thead><tbody><tr>";
  for (int k = 0; k < 3; ++k)
    h << "<td class=\"num\">" << PercentHtml(r.measurement_sd[k]) << "</td>";
  h << "</tr></tbody></table>";
  return h.str();
}

/// The Discovery section, or "" when the study file has no /discovery.
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
       "impact speed).</p>"
    << "<div class=\"verdict" << (r.unexplained ? " unexplained" : "")
    << "\" id=\"discovery-verdict\"><p class=\"headline\">" << HtmlEscape(Headline(r)) << "</p>"
    << VerdictHtml(r.verdict) << "</div>"
    << "<dl class=\"facts\"><dt>Trials</dt><dd>" << r.trials_used << " used, " << r.trials_skipped
    << " skipped (not measured)</dd><dt>Rounds</dt><dd>" << r.rounds.size()
    << "</dd><dt>Effort</dt><dd>" << r.simulations << " simulations, " << Fmt(r.seconds, 3)
    << " s</dd>";
  if (const auto options = TryReadTable(h5, "/discovery/options"); options && Rows(*options) == 1)
    h << "<dt>Settings</dt><dd>alpha " << Fmt(Num(*options, "alpha", 0)) << ", "
      << Fmt(Num(*options, "folds", 0)) << " folds, at most " << Fmt(Num(*options, "max_rounds", 0))
      << " rounds, candidates: "
      << HtmlEscape(Text(*options, "candidates", 0).empty() ? "all"
                                                            : Text(*options, "candidates", 0))
      << (Num(*options, "per_surface", 0) == 0.0 ? ", shared values only" : "")
      << (std::isfinite(Num(*options, "measurement_floor", 0))
              ? ", measurement floor " + PercentHtml(Num(*options, "measurement_floor", 0)) +
                    " of the impact speed"
              : "")
      << "</dd>";
  h << "</dl>";
  h << "<div class=\"tables\">" << FindingsTableHtml(r.findings) << SurfacesTableHtml(r)
    << NoiseTableHtml(r) << "</div>";

  const fs::path dir = TemporaryFigureDir();
  std::vector<fs::path> figures;
  try {
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
      const auto& round = r.rounds[i];
      h << "<h3>Round " << i + 1 << "</h3><p>" << HtmlEscape(round.decision) << "</p>";
      if (!round.accepted.empty())
        h << "<p>Held-out gap " << PercentHtml(round.gap_before) << " &rarr; "
          << PercentHtml(round.gap_after) << " (shrinks " << PercentHtml(round.gap_shrink)
          << ") with <code>" << HtmlEscape(round.accepted) << "</code>.</p>";
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
      h << figure_of("discovery_gap_round" + std::to_string(i + 1));
    }
    h << "<h3>What the final model leaves</h3>";
    if (r.remaining.empty())
      h << "<p class=\"ok\">No significant disagreement remains.</p>";
    else
      h << TestsTableHtml(r.remaining, "Significant disagreements that remain");
    h << figure_of("discovery_residuals");
  } catch (...) {
    fs::remove_all(dir);
    io::UntrackTemporary(dir);
    throw;
  }
  fs::remove_all(dir);
  io::UntrackTemporary(dir);
  h << "</section>";
  return h.str();
}

// ---- replay ------------------------------------------------------------------------------

/// The trials to replay: successful ones, one per surface first, then in file order.
std::vector<const studyfile::TrialResult*> PickReplays(const studyfile::StudyResults& study,
                                                       int n) {
  std::vector<const studyfile::TrialResult*> candidates, picked;
  for (const auto& t : study.trials)
    if (t.success) candidates.push_back(&t);
  std::set<std::string> surfaces;
  for (const auto* t : candidates)
    if (static_cast<int>(picked.size()) < n && surfaces.insert(t->surface).second)
      picked.push_back(t);
  for (const auto* t : candidates)
    if (static_cast<int>(picked.size()) < n &&
        std::find(picked.begin(), picked.end(), t) == picked.end())
      picked.push_back(t);
  return picked;
}

fs::path TrialFolder(const studyfile::TrialResult& t, const std::string& study_dir) {
  fs::path dir = t.dir;
  if (fs::exists(dir / "trial.json")) return dir;
  const fs::path alt = fs::path(study_dir) / dir.filename();
  if (fs::exists(alt / "trial.json")) return alt;
  throw std::runtime_error("trial folder " + dir.string() + " not found");
}

/// Frames [first, last) of the trial as JPEG data URIs, grey levels stretched over the range
/// of those frames, downscaled to max_width. Sets `scale` (shown px per image px).
std::vector<std::string> EncodeFrames(const studyfile::TrialResult& t, const std::string& study_dir,
                                      int first, int last, const HtmlReportOptions& o,
                                      double& scale) {
  const pipeline::TrialSpec spec = pipeline::ReadTrial(TrialFolder(t, study_dir));
  std::unique_ptr<tracking::FrameSource> source;
  if (spec.frames.is_video())
    source = std::make_unique<tracking::VideoSource>(spec.dir / spec.frames.video);
  else
    source = std::make_unique<tracking::ImageSequenceSource>(spec.dir, spec.frames.pattern,
                                                             spec.frames.first, spec.frames.count);
  std::vector<cv::Mat> frames;
  double lo = 1e300, hi = -1e300;
  for (int f = first; f < last && f < source->count(); ++f) {
    cv::Mat grey;
    source->Read(f).convertTo(grey, CV_32F);
    double a = 0, b = 0;
    cv::minMaxLoc(grey, &a, &b);
    lo = std::min(lo, a);
    hi = std::max(hi, b);
    frames.push_back(grey);
  }
  std::vector<std::string> uris;
  if (frames.empty()) return uris;
  scale = std::min(1.0, o.replay_max_width_px / static_cast<double>(frames[0].cols));
  const double gain = hi > lo ? 255.0 / (hi - lo) : 1.0;
  for (const cv::Mat& f : frames) {
    cv::Mat small, bytes;
    cv::resize(f, small, cv::Size(), scale, scale, cv::INTER_AREA);
    small.convertTo(bytes, CV_8U, gain, -lo * gain);
    std::vector<uchar> jpeg;
    cv::imencode(".jpg", bytes, jpeg, {cv::IMWRITE_JPEG_QUALITY, o.jpeg_quality});
    uris.push_back(
        "data:image/jpeg;base64," +
        Base64(std::string_view(reinterpret_cast<const char*>(jpeg.data()), jpeg.size())));
  }
  return uris;
}

/// Marker names of a /comparison/frames table: the columns "<M>_sim_x_px".
std::vector<std::string> MarkerNames(const Table& t) {
  const std::string suffix = "_sim_x_px";
  std::vector<std::string> names;
  for (const auto& c : t.columns)
    if (c.name.size() > suffix.size() && c.name.ends_with(suffix))
      names.push_back(c.name.substr(0, c.name.size() - suffix.size()));
  return names;
}

/// One replay as a JSON object, with its frames as hidden <img> elements appended to `imgs`
/// (in the document, so the page's load event waits for them).
std::string ReplayJson(const studyfile::TrialResult& t, const std::string& study_dir,
                       const Table& frames_table, const HtmlReportOptions& o, int index,
                       std::string& imgs) {
  const int n_frames = static_cast<int>(Rows(frames_table));
  const int impact = static_cast<int>(std::lround(t.impact_time_s * t.fps));
  const int first = std::clamp(impact - o.frames_per_replay / 2, 0, std::max(0, n_frames - 1));
  const int last = std::min(n_frames, first + o.frames_per_replay);
  double scale = 1.0;
  const auto uris = EncodeFrames(t, study_dir, first, last, o, scale);
  if (uris.empty()) throw std::runtime_error("no frames could be read");
  const std::vector<std::string> markers = MarkerNames(frames_table);
  std::ostringstream j;
  j << "{\"id\":" << JsonString(t.id) << ",\"surface\":" << JsonString(t.surface)
    << ",\"scale\":" << JsonNumber(scale) << ",\"impact\":" << impact << ",\"markers\":[";
  for (std::size_t m = 0; m < markers.size(); ++m) j << (m ? "," : "") << JsonString(markers[m]);
  j << "],\"frames\":[";
  for (int k = 0; k < static_cast<int>(uris.size()); ++k) {
    const auto r = static_cast<std::size_t>(first + k);
    imgs += "<img class=\"frame\" id=\"f" + std::to_string(index) + "_" + std::to_string(k) +
            "\" alt=\"\" src=\"" + uris[static_cast<std::size_t>(k)] + "\">";
    j << (k ? "," : "") << "{\"frame\":" << first + k
      << ",\"t_ms\":" << JsonNumber(Num(frames_table, "t_s", r) * 1e3) << ",\"sim\":[";
    for (std::size_t m = 0; m < markers.size(); ++m)
      j << (m ? "," : "") << "[" << JsonNumber(Num(frames_table, markers[m] + "_sim_x_px", r))
        << "," << JsonNumber(Num(frames_table, markers[m] + "_sim_y_px", r)) << "]";
    j << "],\"meas\":[";
    for (std::size_t m = 0; m < markers.size(); ++m)
      j << (m ? "," : "") << "[" << JsonNumber(Num(frames_table, markers[m] + "_meas_x_px", r))
        << "," << JsonNumber(Num(frames_table, markers[m] + "_meas_y_px", r)) << "]";
    j << "]}";
  }
  j << "]}";
  return j.str();
}

std::string ReplaySection(const studyfile::StudyResults& study, const fs::path& h5,
                          const HtmlReportOptions& o, HtmlReportSummary& summary) {
  std::string json = "[", imgs;
  for (const auto* t : PickReplays(study, o.replay_trials)) {
    try {
      const Table frames = studyfile::ReadTable(h5, "/comparison/frames/" + t->id);
      std::string trial_imgs;
      const std::string one =
          ReplayJson(*t, study.study_dir, frames, o, summary.replays, trial_imgs);
      json += (summary.replays ? "," : "") + one;
      imgs += trial_imgs;
      ++summary.replays;
    } catch (const std::exception& e) {
      summary.notes += t->id + ": no replay (" + e.what() + ")\n";
    }
  }
  json += "]";
  std::ostringstream h;
  h << "<section id=\"replay\"><h2>Replay</h2>";
  if (summary.replays == 0) {
    h << "<p>No replay: "
      << (o.replay_trials == 0 ? "none asked for" : "no trial's frames could be read") << ".</p>";
  } else {
    h << "<p class=\"note\">The " << o.frames_per_replay << " frames around the impact. "
      << "<span class=\"key meas\">&#9675; measured marker</span> "
      << "<span class=\"key sim\">+ simulated marker</span> (the surface's fitted contact law, "
         "started from the measured state before impact). Arrow keys step frames.</p>"
      << "<div class=\"replay-controls\"><label>Trial <select id=\"replay-trial\"></select></label>"
      << "<button id=\"replay-prev\" type=\"button\">&#9664; prev</button>"
      << "<input id=\"replay-frame\" type=\"range\" min=\"0\" max=\"0\" value=\"0\" step=\"1\">"
      << "<button id=\"replay-next\" type=\"button\">next &#9654;</button>"
      << "<label><input id=\"replay-overlay\" type=\"checkbox\" checked> overlay</label>"
      << "<span id=\"replay-info\"></span></div>"
      << "<canvas id=\"replay-canvas\" width=\"480\" height=\"270\"></canvas>";
  }
  h << "<div class=\"frames-store\">" << imgs << "</div>"
    << "<script type=\"application/json\" id=\"replay-data\">" << json << "</script></section>";
  return h.str();
}

}  // namespace

void HtmlReportOptions::Validate() const {
  auto check = [](bool ok, const char* field, int value, const char* range) {
    if (!ok)
      throw std::invalid_argument(std::string("HtmlReportOptions.") + field + " = " +
                                  std::to_string(value) + ": must be in " + range);
  };
  check(replay_trials >= 0 && replay_trials <= 50, "replay_trials", replay_trials, "0..50");
  check(frames_per_replay >= 2 && frames_per_replay <= 400, "frames_per_replay", frames_per_replay,
        "2..400");
  check(replay_max_width_px >= 64 && replay_max_width_px <= 4096, "replay_max_width_px",
        replay_max_width_px, "64..4096");
  check(jpeg_quality >= 1 && jpeg_quality <= 100, "jpeg_quality", jpeg_quality, "1..100");
}

std::string HtmlEscape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string Base64(std::string_view bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const std::uint32_t v = static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[i])) << 16 |
                            static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[i + 1]))
                                << 8 |
                            static_cast<unsigned char>(bytes[i + 2]);
    for (int s = 18; s >= 0; s -= 6) out += kAlphabet[(v >> s) & 63u];
  }
  if (i < bytes.size()) {
    std::uint32_t v = static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[i])) << 16;
    if (i + 1 < bytes.size())
      v |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[i + 1])) << 8;
    out += kAlphabet[(v >> 18) & 63u];
    out += kAlphabet[(v >> 12) & 63u];
    out += i + 1 < bytes.size() ? kAlphabet[(v >> 6) & 63u] : '=';
    out += '=';
  }
  return out;
}

HtmlReportSummary WriteHtmlReport(const fs::path& study_h5, const fs::path& output,
                                  const HtmlReportOptions& options) {
  options.Validate();
  if (!fs::is_regular_file(study_h5))
    throw std::runtime_error(study_h5.string() + ": no such study file");
  RemoveStaleReportFolders();
  const studyfile::StudyResults study = studyfile::ReadStudyResults(study_h5);
  const auto surfaces = TryReadTable(study_h5, "/comparison/surfaces");
  const auto cmp = TryReadTable(study_h5, "/comparison/trials");
  if (!surfaces || !cmp)
    throw std::runtime_error(study_h5.string() +
                             ": no /comparison in the study file; run `hoofimpact run` first");
  HtmlReportSummary summary;
  summary.output = output;
  summary.trials = static_cast<int>(study.trials.size());
  const std::string discovery_section = DiscoverySection(study_h5, summary);
  const bool has_discovery = summary.discovery;
  const int discovery_figures = std::exchange(summary.figures, 0);  // FiguresSection counts its own
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
    << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
    << "<title>hoofimpact report: " << HtmlEscape(study.name) << "</title>"
    << "<script>" << assets::kErrorJs << "</script><style>" << assets::kReportCss
    << "</style></head><body>"
    << "<header><h1>hoofimpact report: " << HtmlEscape(study.name) << "</h1><p>"
    << study.trials.size() << " trials &middot; " << HtmlEscape(study.created_utc)
    << "</p></header><nav><a href=\"#summary\">Study</a><a href=\"#model\">Contact model</a>"
    << "<a href=\"#replay\">Replay</a><a href=\"#figures\">Figures</a>"
    << (has_discovery ? "<a href=\"#discovery\">Discovery</a>" : "")
    << "<a href=\"#trials\">Trials</a><a href=\"#statistics\">Statistics</a></nav><main>"
    << SummarySection(study, study_h5) << ModelSection(*surfaces)
    << ReplaySection(study, study_h5, options, summary)
    << FiguresSection(study, study_h5, summary.figures) << discovery_section
    << TrialsSection(study, *cmp) << StatsSection(study_h5) << "</main><script>"
    << assets::kReplayJs << "</script></body></html>\n";
  summary.figures += discovery_figures;
  const std::string page = h.str();
  io::WriteTextAtomically(output, page);
  summary.bytes = page.size();
  return summary;
}

}  // namespace hoof::report
