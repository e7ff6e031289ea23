#pragma once
/// @file
/// The statistics as `hoofimpact stats` prints and writes them: the terminal text, the JSON
/// and the long CSV (columns table,row,statistic,value) of one response grouped by a factor,
/// and the text and JSON of a whole study's tables (StoreStatistics). Any program or test gets
/// the same output without running the command.

#include <cstddef>
#include <optional>
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "stats/one_way_analysis.h"
#include "stats/two_way_anova.h"
#include "study/statistics.h"

namespace hoof::study {

/// Groups, ANOVA, Bartlett, Welch and Fisher's LSD at level `alpha`; numbers that are not
/// finite are null.
nlohmann::json OneWayJson(const stats::OneWayScaleResults& results, double alpha);
/// Whether a Box-Cox transform was considered and applied, and the analysis rerun on it.
nlohmann::json TransformJson(const stats::TransformDecision& transform, double alpha);
/// The two-way table: its cells and rows.
nlohmann::json TwoWayJson(const stats::TwoWayAnovaResult& result);
/// A study's tables: the trials excluded and why, and per response its cells, its one-way
/// analyses by each factor and its two-way table.
nlohmann::json StudyStatisticsJson(const StudyStatistics& statistics);

/// The one-way tables (groups, ANOVA, Bartlett, Welch, LSD) as indented text.
void WriteOneWayText(std::ostream& os, const stats::OneWayScaleResults& results, double alpha);
/// The two-way ANOVA table as text.
void WriteTwoWayText(std::ostream& os, const stats::TwoWayAnovaResult& result);
/// `response` by `factor` from `source` (`observations` values): the one-way analysis, its
/// transform and rerun, and the two-way table when there is one.
void WriteOneWayAnalysisText(std::ostream& os, const std::string& response,
                             const std::string& factor, const std::string& source,
                             std::size_t observations, const stats::OneWayAnalysis& analysis,
                             const std::optional<stats::TwoWayAnovaResult>& two_way);
/// A study's tables as text: per response its cells (mean, s.d., n per surface x angle), each
/// factor's analysis and the two-way table.
void WriteStudyStatisticsText(std::ostream& os, const StudyStatistics& statistics);

/// Every table of a one-way analysis (and the two-way table) to `path` as one long CSV, written
/// to a temporary file and renamed. Throws std::runtime_error naming the file on failure.
void WriteLongCsv(const std::string& path, const stats::OneWayAnalysis& analysis,
                  const std::optional<stats::TwoWayAnovaResult>& two_way);

}  // namespace hoof::study
