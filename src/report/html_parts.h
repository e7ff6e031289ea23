#pragma once
/// @file
/// Parts of the HTML report (html_report.cc) that its Discovery section (discovery_html.cc) and
/// its Statistics section (stats_html.cc) share. Internal to hoof::report.
/// Parts of the HTML report (html_report.cc) that its other sections (summary_html.cc,
/// replay_html.cc, discovery_html.cc) share. Internal to hoof::report.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "compare/comparison_tables.h"
#include "report/html_report.h"
#include "studyfile/stats_tables.h"
#include "studyfile/study_file.h"

namespace hoof::report::internal {

/// A number for the page to `precision` significant digits, "n/a" when it is not finite
/// (format::Significant: the number policy of src/format/number_format.h).
std::string Fmt(double v, int precision = 4);
/// A number for the embedded JSON: NaN and infinities become null.
std::string JsonNumber(double v);
/// A JSON string literal that is also safe inside <script> ("</" cannot close the element).
std::string JsonString(std::string_view text);
/// A cell of a numeric column (NaN when the column is absent).
double Num(const studyfile::Table& t, const std::string& name, std::size_t row);
/// Rows of a table (0 without columns).
std::size_t Rows(const studyfile::Table& t);
/// A fresh folder for figures drawn only to be embedded (removed by an interrupt).
std::filesystem::path TemporaryFigureDir();
/// A TemporaryFigureDir() owned for one section: removed, and forgotten by the interrupt
/// handler, when it goes out of scope, whether the section was written or threw.
class TemporaryFigureFolder {
 public:
  TemporaryFigureFolder();
  ~TemporaryFigureFolder();
  TemporaryFigureFolder(const TemporaryFigureFolder&) = delete;
  TemporaryFigureFolder& operator=(const TemporaryFigureFolder&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};
/// A PNG figure embedded as a data URI, captioned with its file stem.
std::string FigureHtml(const std::filesystem::path& png);

/// The Trials section: each trial's measurement, its prediction z (/prediction) and its
/// precision-only z (`compared`, /comparison) (trials_html.cc). A /prediction that cannot be
/// read is said in the section and in `summary`'s notes.
std::string TrialsSection(const studyfile::StudyResults& study,
                          const std::vector<compare::ComparedTrial>& compared,
                          const std::filesystem::path& h5, HtmlReportSummary& summary);

/// The Study section: the summary of `study` and how the study file and the page were made
/// (summary_html.cc).
std::string SummarySection(const studyfile::StudyResults& study, const std::filesystem::path& h5,
                           const HtmlReportOptions& options);

/// The Replay section: a few trials' frames around the impact with the measured and simulated
/// markers and the magnified residuals, or why none could be drawn (replay_html.cc). Each
/// replay that cannot be drawn is added to the summary's notes and missing_replays.
std::string ReplaySection(const studyfile::StudyResults& study, const std::filesystem::path& h5,
                          const HtmlReportOptions& options, HtmlReportSummary& summary);

/// The Discovery section of the study file's /discovery, or nothing without one
/// (discovery_html.cc).
std::string DiscoverySection(const std::filesystem::path& h5, HtmlReportSummary& summary);

/// The Statistics section of the study file's /stats (stats_html.cc): per response and factor
/// the test chain (Bartlett, the Box-Cox transform where Bartlett rejects, the ANOVA on the
/// analysed scale with Welch beside it, Fisher's LSD groups as letters), the cells and the
/// two-way table. Tables that cannot be read leave the section saying so and the summary's
/// notes naming the file and the table; the rest of the report is written.
std::string StatsSection(const std::filesystem::path& h5, HtmlReportSummary& summary);
/// The body of that section for tables already read (no <section> around it). Throws
/// std::invalid_argument when an LSD pair names a group the groups table lacks.
std::string StatsHtml(const studyfile::StoredStatistics& statistics);

}  // namespace hoof::report::internal
