// The report's Study section (report/html_parts.h): what the study is, and how the study file
// and the page were made: the command lines, the analysis, statistics, discovery and report
// options, and the versions of hoofimpact, so that a reader can remake both.
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include "format/number_format.h"
#include "report/html_parts.h"
#include "report/html_report.h"
#include "studyfile/stats_tables.h"
#include "studyfile/study_file.h"

#ifndef HOOF_VERSION
#define HOOF_VERSION "unknown"
#endif

namespace hoof::report::internal {
namespace {

namespace fs = std::filesystem;

/// "<dt>term</dt><dd>html</dd>".
std::string Fact(const std::string& term, const std::string& html) {
  return "<dt>" + HtmlEscape(term) + "</dt><dd>" + html + "</dd>";
}

std::string Code(const std::string& text) { return "<code>" + HtmlEscape(text) + "</code>"; }

/// The kinematics options of /study/analysis_options, each with its unit and meaning.
std::string KinematicsOptionsHtml(const fs::path& h5) {
  std::ostringstream h;
  try {
    const auto k = studyfile::ReadKinematicsOptions(h5);
    h << "<ul class=\"options\">"
      << "<li><code>fit_frames</code> = " << k.fit_frames
      << " frames per flight fit, before and after the impact</li>"
      << "<li><code>min_fit_frames</code> = " << k.min_fit_frames
      << " (fewer usable frames is an error)</li>"
      << "<li><code>max_contact_s</code> = " << format::Number(k.max_contact_s * 1e6)
      << " &micro;s (longest contact assumed)</li>"
      << "<li><code>exposure_s</code> = "
      << (k.exposure_s < 0 ? std::string("one frame period")
                           : format::Number(k.exposure_s * 1e6) + " &micro;s")
      << "</li><li><code>gravity_m_s2</code> = " << format::Number(k.gravity_m_s2)
      << " m/s&sup2;</li><li><code>confidence</code> = " << format::Number(k.confidence)
      << " (level of the intervals)</li></ul>";
  } catch (const std::exception& e) {
    return "<span class=\"bad\">cannot be read: " + HtmlEscape(e.what()) + "</span>";
  }
  return h.str();
}

/// One table row as a list of "name = value unit" items, the column's description on hover.
std::string OptionsRowHtml(const studyfile::Table& t) {
  std::ostringstream h;
  h << "<ul class=\"options\">";
  for (const studyfile::Column& c : t.columns) {
    if (c.size() == 0) continue;
    std::string value;
    if (const auto* d = std::get_if<std::vector<double>>(&c.values))
      value = format::Number((*d)[0]);
    else if (const auto* i = std::get_if<std::vector<std::int64_t>>(&c.values))
      value = std::to_string((*i)[0]);
    else
      value = std::get<std::vector<std::string>>(c.values)[0];
    const bool unit = !c.units.empty() && c.units != "1";
    h << "<li title=\"" << HtmlEscape(c.description) << "\"><code>" << HtmlEscape(c.name)
      << "</code> = " << HtmlEscape(value.empty() ? "(none)" : value);
    if (unit) h << " " << HtmlEscape(c.units);
    h << "</li>";
  }
  h << "</ul>";
  return h.str();
}

/// How the study file and the page were made.
std::string ProvenanceHtml(const studyfile::StudyResults& study, const fs::path& h5,
                           const HtmlReportOptions& o) {
  std::ostringstream h;
  h << "<h3 id=\"provenance\">How this page was made</h3><dl class=\"facts provenance\">";
  h << Fact("This page", (o.command_line.empty() ? std::string("command line not known")
                                                 : Code(o.command_line)) +
                             " <span class=\"note\">(hoofimpact " + HtmlEscape(HOOF_VERSION) +
                             ", " + HtmlEscape(studyfile::NowUtc()) + ")</span>");
  h << Fact("The study file", (study.command_line.empty() ? std::string("command line not recorded")
                                                          : Code(study.command_line)) +
                                  " <span class=\"note\">(hoofimpact " +
                                  HtmlEscape(study.hoofimpact_version) + ", " +
                                  HtmlEscape(study.created_utc) + ")</span>");
  h << Fact("Analysis options",
            "<span class=\"note\"><code>/study/analysis_options</code>, the impact "
            "measurement:</span>" +
                KinematicsOptionsHtml(h5));
  // The statistics' options are the description of /stats.
  std::string stats = "<span class=\"note\">no statistics in the study file</span>";
  try {
    if (studyfile::HasStatistics(h5)) stats = HtmlEscape(studyfile::ReadStatistics(h5).description);
  } catch (const std::exception& e) {
    stats = "<span class=\"bad\">cannot be read: " + HtmlEscape(e.what()) + "</span>";
  }
  h << Fact("Statistics options", stats);
  std::string discovery = "<span class=\"note\">no discovery in the study file</span>";
  try {
    if (studyfile::HasGroup(h5, "/discovery/options"))
      discovery = OptionsRowHtml(studyfile::ReadTable(h5, "/discovery/options"));
    else if (studyfile::HasGroup(h5, "/discovery"))
      discovery = "<span class=\"note\">not recorded in the study file</span>";
  } catch (const std::exception& e) {
    discovery = "<span class=\"bad\">cannot be read: " + HtmlEscape(e.what()) + "</span>";
  }
  h << Fact("Discovery options", discovery);
  std::ostringstream report;
  report << "<ul class=\"options\"><li>replay trials = " << o.replay_trials
         << "</li><li>frames per replay = " << o.frames_per_replay
         << "</li><li>residual scale = " << o.residual_scale
         << "&times;</li><li>replay frames at most " << o.replay_max_width_px
         << " px wide, JPEG quality " << o.jpeg_quality << "</li><li>study folder searched = "
         << (o.study_dir.empty() ? std::string("none (the recorded folders only)")
                                 : Code(fs::absolute(o.study_dir).string()))
         << "</li></ul>";
  h << Fact("Report options", report.str());
  h << "</dl>";
  return h.str();
}

}  // namespace

std::string SummarySection(const studyfile::StudyResults& study, const fs::path& h5,
                           const HtmlReportOptions& options) {
  std::ostringstream h;
  int measured = 0;
  for (const auto& t : study.trials) measured += t.success ? 1 : 0;
  const int failed = static_cast<int>(study.trials.size()) - measured;
  h << "<section id=\"summary\"><h2>Study</h2><dl class=\"facts\">"
    << "<dt>Name</dt><dd>" << HtmlEscape(study.name) << "</dd>"
    << "<dt>Study file</dt><dd><code>" << HtmlEscape(fs::absolute(h5).string()) << "</code></dd>"
    << "<dt>Study folder</dt><dd><code>" << HtmlEscape(study.study_dir) << "</code>"
    << (options.study_dir.empty()
            ? std::string()
            : " (recorded; frames looked for under <code>" +
                  HtmlEscape(fs::absolute(options.study_dir).string()) + "</code> too)")
    << "</dd>"
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
  h << ProvenanceHtml(study, h5, options) << "</section>";
  return h.str();
}

}  // namespace hoof::report::internal
