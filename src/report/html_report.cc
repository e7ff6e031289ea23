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

#include "compare/comparison_tables.h"
#include "compare/replay_convention.h"
#include "core/frames.h"
#include "discovery/discovery_tables.h"
#include "io/atomic_file.h"
#include "io/interrupt.h"
#include "pipeline/study_format.h"
#include "report/comparison_figures.h"
#include "report/discovery_figures.h"
#include "report/figures.h"
#include "report/html_parts.h"
#include "report/report_assets.h"
#include "studyfile/stats_tables.h"
#include "studyfile/study_file.h"
#include "tracking/frame_source.h"

namespace hoof::report {
// The report's parts, shared with discovery_html.cc through report/html_parts.h.
namespace internal {

namespace fs = std::filesystem;
using studyfile::Table;

// ---- small helpers ------------------------------------------------------------------------

std::string Fmt(double v, int precision) {
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

const studyfile::Column* FindColumn(const Table& t, const std::string& name) {
  for (const auto& c : t.columns)
    if (c.name == name) return &c;
  return nullptr;
}

double Num(const Table& t, const std::string& name, std::size_t row) {
  const auto* c = FindColumn(t, name);
  if (!c || row >= c->size()) return core::kNaN;
  if (const auto* d = std::get_if<std::vector<double>>(&c->values)) return (*d)[row];
  if (const auto* i = std::get_if<std::vector<std::int64_t>>(&c->values))
    return static_cast<double>((*i)[row]);
  return core::kNaN;
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

std::string ModelSection(const std::vector<compare::SurfaceModel>& surfaces) {
  std::ostringstream h;
  h << "<section id=\"model\"><h2>Contact model per surface</h2>"
    << "<p class=\"note\">Fitted from the measured trials (<code>/comparison/surfaces</code>): "
       "zeta from the normal impacts, mu from the oblique ones. The stiffness k is not "
       "identified by velocities alone.</p>"
    << "<table class=\"data\"><thead><tr><th>surface</th><th>normal trials</th><th>oblique "
       "trials</th><th>zeta</th><th>zeta 95 % interval</th><th>mu</th><th>k</th><th>note</th>"
       "</tr></thead><tbody>";
  for (const compare::SurfaceModel& m : surfaces) {
    h << "<tr><td>" << HtmlEscape(m.surface) << "</td><td class=\"num\">" << Fmt(m.normal_trials)
      << "</td><td class=\"num\">" << Fmt(m.oblique_trials) << "</td>";
    if (!m.success) {
      h << "<td colspan=\"4\" class=\"bad\">no model</td><td>" << HtmlEscape(m.message)
        << "</td></tr>";
      continue;
    }
    const double lo = m.zeta_fit.zeta_ci_low, hi = m.zeta_fit.zeta_ci_high;
    h << "<td class=\"num\">" << Fmt(m.zeta_fit.zeta) << "</td><td class=\"num\">"
      << (std::isfinite(lo) && std::isfinite(hi) ? Fmt(lo) + " .. " + Fmt(hi)
                                                 : std::string("not available"))
      << "</td><td class=\"num\">";
    if (m.mu_only_lower_bound)
      h << "&ge; " << Fmt(m.mu) << " (contacts stick)";
    else
      h << Fmt(m.mu) << (std::isfinite(m.mu_se) ? " &plusmn; " + Fmt(m.mu_se, 2) : "");
    h << "</td><td>k not identified</td><td>" << HtmlEscape(m.message) << "</td></tr>";
  }
  h << "</tbody></table></section>";
  return h.str();
}

/// `t` as an HTML table, its columns as their Serialize declares them (studyfile/stats_tables.h).
template <class Row>
std::string RenderRows(const studyfile::StoredTable<Row>& t, const std::string& caption,
                       const Row& declared = Row{}) {
  return RenderTable(studyfile::TableWriter::Of(
                         "", t.description, t.rows,
                         [](auto& a, const auto& row) { studyfile::Serialize(a, row); }, declared),
                     caption);
}

/// The statistics of /stats. Tables that cannot be read leave the section saying so (and the
/// summary's notes naming the file and the table); the rest of the report is written.
std::string StatsSection(const fs::path& h5, HtmlReportSummary& summary) {
  std::ostringstream h;
  h << "<section id=\"statistics\"><h2>Statistics</h2>";
  bool any = false;
  std::optional<studyfile::StoredStatistics> stored;
  try {
    if (studyfile::HasStatistics(h5)) stored = studyfile::ReadStatistics(h5);
  } catch (const std::exception& e) {
    h << "<p class=\"bad\">The statistics tables cannot be read: " << HtmlEscape(e.what())
      << "</p></section>";
    summary.notes += std::string("statistics: ") + e.what() + "\n";
    return h.str();
  }
  for (const studyfile::StoredResponse& r :
       stored ? stored->responses : std::vector<studyfile::StoredResponse>{}) {
    const std::string label =
        r.response == "e" ? "e (restitution)" : "mu_eff (effective friction, oblique trials)";
    std::ostringstream part;
    studyfile::CellRow cell;
    cell.response = r.response;
    part << RenderRows(r.cells, "Mean (s.d., n) per surface x angle", cell);
    for (const studyfile::StoredFactor& f : r.factors)
      part << RenderRows(f.original.anova, "One-way ANOVA by " + f.factor);
    if (r.two_way) part << RenderRows(*r.two_way, "Two-way ANOVA, surface x angle");
    if (!r.notes.empty())
      part << RenderRows(studyfile::StoredTable<studyfile::NoteRow>{"", r.notes}, "Notes");
    h << "<h3>" << HtmlEscape(label) << "</h3><div class=\"tables\">" << part.str() << "</div>";
    any = true;
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

TemporaryFigureFolder::TemporaryFigureFolder() : path_(TemporaryFigureDir()) {}

TemporaryFigureFolder::~TemporaryFigureFolder() {
  std::error_code ec;
  fs::remove_all(path_, ec);
  io::UntrackTemporary(path_);
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
  const TemporaryFigureFolder folder;
  const fs::path& dir = folder.path();
  std::ostringstream h;
  h << "<section id=\"figures\"><h2>Figures</h2><div class=\"figures\">";
  {
    // Figures 4-5 (e and mu_eff by angle and speed) and 6-8 (velocities after normal and
    // oblique impacts against the simulation, kinetic energy through an impact).
    std::vector<fs::path> paths = WriteStudyFigures(study, dir);
    for (const auto& p : WriteComparisonFigures(study_h5, dir)) paths.push_back(p);
    for (const auto& path : paths) {
      if (path.extension() != ".png") continue;
      h << FigureHtml(path);
      ++count;
    }
  }
  if (count == 0) h << "<p>No figure: no trial was measured.</p>";
  h << "</div></section>";
  return h.str();
}

std::string TrialsSection(const studyfile::StudyResults& study,
                          const std::vector<compare::ComparedTrial>& compared) {
  std::map<std::string, const compare::TrialComparison*> row_of;
  for (const compare::ComparedTrial& t : compared) row_of[t.id] = &t.comparison;
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
    const compare::TrialComparison* c = it == row_of.end() ? nullptr : it->second;
    for (const double v : {c ? c->v_SC_after_z.x() : core::kNaN,
                           c ? c->v_SC_after_z.y() : core::kNaN, c ? c->w_after_z : core::kNaN})
      h << "<td class=\"num" << (std::abs(v) > 3.0 ? " bad" : "") << "\">" << Fmt(v, 3) << "</td>";
    if (c && !c->success) note = c->message;
    h << "<td>" << HtmlEscape(note) << "</td></tr>";
  }
  h << "</tbody></table></section>";
  return h.str();
}

}  // namespace internal

using namespace internal;

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
  compare::replay::ValidateResidualScale(residual_scale, "HtmlReportOptions.residual_scale");
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
  if (!compare::HasComparison(study_h5))
    throw std::runtime_error(study_h5.string() +
                             ": no /comparison in the study file; run `hoofimpact run` first");
  const std::vector<compare::SurfaceModel> surfaces = compare::ReadSurfaceModels(study_h5);
  const std::vector<compare::ComparedTrial> compared = compare::ReadComparedTrials(study_h5);
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
    << SummarySection(study, study_h5, options) << ModelSection(surfaces)
    << ReplaySection(study, study_h5, options, summary)
    << FiguresSection(study, study_h5, summary.figures) << discovery_section
    << TrialsSection(study, compared) << StatsSection(study_h5, summary) << "</main><script>"
    << assets::kReplayJs << "</script></body></html>\n";
  summary.figures += discovery_figures;
  const std::string page = h.str();
  io::WriteTextAtomically(output, page);
  summary.bytes = page.size();
  return summary;
}

}  // namespace hoof::report
