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
#include "format/number_format.h"
#include "io/atomic_file.h"
#include "io/interrupt.h"
#include "pipeline/study_format.h"
#include "report/comparison_figures.h"
#include "report/discovery_figures.h"
#include "report/figures.h"
#include "report/html_parts.h"
#include "report/report_assets.h"
#include "studyfile/study_file.h"
#include "tracking/frame_source.h"

namespace hoof::report {
// The report's parts, shared with discovery_html.cc through report/html_parts.h.
namespace internal {

namespace fs = std::filesystem;
using studyfile::Table;

// ---- small helpers ------------------------------------------------------------------------

std::string Fmt(double v, int precision) { return format::Significant(v, precision); }

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

// ---- sections ----------------------------------------------------------------------------

std::string ModelSection(const std::vector<compare::SurfaceModel>& surfaces,
                         const std::vector<compare::ComparedTrial>& compared) {
  compare::MassGaps gaps;
  for (const compare::ComparedTrial& t : compared) {
    if (!t.comparison.success || t.comparison.mass_known) continue;
    ++gaps.without_mass;
    gaps.inertia_assumed += t.comparison.inertia_assumed ? 1 : 0;
  }
  std::ostringstream h;
  h << "<section id=\"model\"><h2>Contact model per surface</h2>"
    << "<p class=\"note\">Fitted from the measured trials (<code>/comparison/surfaces</code>): "
       "zeta from the normal impacts, mu from the oblique ones. The stiffness k is not "
       "identified by velocities alone.</p>";
  if (gaps.without_mass > 0)
    h << "<p class=\"note mass-gaps\">" << HtmlEscape(gaps.Text()) << ".</p>";
  h << "<table class=\"data\"><thead><tr><th>surface</th><th>normal trials</th><th>oblique "
       "trials</th><th>zeta</th><th>zeta 95 % interval</th><th>mu</th><th>k</th><th>note</th>"
       "</tr></thead><tbody>";
  for (const compare::SurfaceModel& m : surfaces) {
    h << "<tr><td>" << HtmlEscape(m.surface) << "</td><td class=\"num\">" << m.normal_trials
      << "</td><td class=\"num\">" << m.oblique_trials << "</td>";
    if (!m.success) {
      h << "<td colspan=\"4\" class=\"bad\">no model</td><td>" << HtmlEscape(m.message)
        << "</td></tr>";
      continue;
    }
    const double lo = m.zeta_fit.zeta_ci_low, hi = m.zeta_fit.zeta_ci_high;
    h << "<td class=\"num\">" << Fmt(m.zeta_fit.zeta) << "</td><td class=\"num\">"
      << (std::isfinite(lo) && std::isfinite(hi)
              ? format::Interval(lo, hi, format::Kind::kCoefficient)
              : std::string("not available"))
      << "</td><td class=\"num\">";
    if (m.mu_only_lower_bound)
      h << "&ge; " << Fmt(m.mu) << " (contacts stick)";
    else
      h << format::WithError(m.mu, m.mu_se, format::Kind::kCoefficient, " &plusmn; ");
    h << "</td><td>" << (m.mass_known ? "k not identified" : "k and b need the mass (not given)")
      << "</td><td>" << HtmlEscape(m.message) << "</td></tr>";
  }
  h << "</tbody></table></section>";
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
    << SummarySection(study, study_h5, options) << ModelSection(surfaces, compared)
    << ReplaySection(study, study_h5, options, summary)
    << FiguresSection(study, study_h5, summary.figures) << discovery_section
    << TrialsSection(study, compared, study_h5, summary) << StatsSection(study_h5, summary)
    << "</main><script>" << assets::kReplayJs << "</script></body></html>\n";
  summary.figures += discovery_figures;
  const std::string page = h.str();
  io::WriteTextAtomically(output, page);
  summary.bytes = page.size();
  return summary;
}

}  // namespace hoof::report
