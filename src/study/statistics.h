#pragma once
/// @file
/// The study statistics, as the paper ran them in SAS: e and mu_eff by surface, angle and speed
/// (one-way ANOVA with Bartlett, Welch, the Box-Cox transform when variances differ and Fisher's
/// LSD), their surface x angle cells, and the two-way ANOVA surface x angle. Which trials enter
/// and which analyses can be computed are decided here; the numbers come from hoof::stats.
/// docs/statistics.md says what each table holds.

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "stats/one_way_analysis.h"
#include "stats/two_way_anova.h"
#include "studyfile/study_file.h"

namespace hoof::study {

struct StatisticsOptions {
  double alpha = 0.05;  ///< for Bartlett (transform), the ANOVA (LSD) and the LSD pairs; in (0, 1)
  stats::SumOfSquaresType ss_type = stats::SumOfSquaresType::kTypeIII;  ///< of the two-way table
};

/// The one-way analysis of one response by one factor, or why it was not computed.
struct FactorAnalysis {
  std::string factor;  ///< "surface", "angle", "speed"
  std::optional<stats::OneWayAnalysis> analysis;
  std::string note;  ///< why `analysis` is absent
};

/// Everything computed for one response (e or mu_eff).
struct ResponseAnalysis {
  std::string response;
  std::string selection;  ///< which trials, in words
  std::vector<double> values;
  std::vector<std::string> surface, angle, speed;
  std::vector<stats::GroupSummary> cells;  ///< surface x angle, label "surface|angle"
  std::vector<FactorAnalysis> factors;
  std::optional<stats::TwoWayAnovaResult> two_way;
  std::string two_way_note;
};

/// The study's analyses, and the trials left out of them.
struct StudyStatistics {
  std::string path;  ///< the study file, as named in messages
  StatisticsOptions options;
  std::size_t trials = 0;
  std::vector<std::pair<std::string, std::string>> excluded;  ///< id, reason
  std::vector<std::string> notes;
  std::vector<ResponseAnalysis> responses;  ///< e, then mu_eff
};

/// Analyses the successful trials of `study` (e: every trial with e measured; mu_eff: the
/// oblique ones). Throws std::runtime_error naming `path` when no trial succeeded.
StudyStatistics AnalyzeStatistics(const studyfile::StudyResults& study,
                                  const StatisticsOptions& options, const std::string& path);

/// The analyses as the tables stored under /stats (docs/hdf5-schema.md).
std::vector<studyfile::Table> StatisticsTables(const StudyStatistics& statistics);

/// The tables as one long CSV (table,row,statistic,value), written atomically.
void WriteTablesCsv(const std::string& path, const std::vector<studyfile::Table>& tables);

/// The description stored with /stats.
std::string StatisticsDescription(const StatisticsOptions& options);

/// Reads the study file, analyses it, stores the tables under /stats (and into `out_csv` when
/// not empty) and returns the analyses. `shown_as` names the file in messages when `study_h5` is
/// a temporary (run).
StudyStatistics StoreStatistics(const std::filesystem::path& study_h5,
                                const StatisticsOptions& options,
                                const std::filesystem::path& out_csv = {},
                                const std::string& shown_as = {});

}  // namespace hoof::study
