#pragma once
/// @file
/// The whole one-way workflow the `hoofimpact stats` command prints, as one call:
///  1. group summaries, the ANOVA table and eta^2 (one_way_anova.h);
///  2. Bartlett's test of equal variances (bartlett.h) and Welch's ANOVA (welch_anova.h),
///     which does not assume them;
///  3. Fisher's protected LSD (fisher_lsd.h), only when the ANOVA p < alpha;
///  4. when Bartlett rejects (p < alpha): the Box-Cox lambda by the rule of box_cox.h; if
///     that lambda is not 1, the data are transformed and steps 1-3 are rerun on the
///     transformed scale, so the reader sees whether the transform equalized the variances
///     (Bartlett again) and whether the conclusion about the means changes.
/// Each step's failure that is an expected outcome (Welch undefined because a group is
/// constant, LSD not run because the ANOVA is not significant) is recorded as a note, not
/// thrown.

#include <optional>
#include <string>
#include <vector>

#include "stats/bartlett.h"
#include "stats/box_cox.h"
#include "stats/fisher_lsd.h"
#include "stats/grouping.h"
#include "stats/one_way_anova.h"
#include "stats/welch_anova.h"

namespace hoof::stats {

/// Settings of the workflow.
struct OneWayAnalysisOptions {
  /// Significance level, in (0, 1), for all three decisions: Bartlett (transform or not),
  /// the ANOVA F test (LSD or not) and each LSD pair and its confidence interval.
  double alpha = 0.05;
  BoxCoxOptions box_cox;  ///< The lambda search (used only when Bartlett rejects).
  /// Throws std::invalid_argument naming the field that is out of range.
  void Validate() const;
};

/// Steps 1-3 on one scale (the original data, or the transformed data).
struct OneWayScaleResults {
  std::vector<GroupSummary> groups;  ///< In order of first appearance.
  OneWayAnovaResult anova;
  BartlettResult bartlett;
  std::optional<WelchAnovaResult> welch;  ///< Absent when a group has zero variance.
  std::string welch_note;                 ///< Why `welch` is absent; empty otherwise.
  bool lsd_performed = false;             ///< True when anova.p < alpha.
  std::string lsd_note;                   ///< Why LSD was not performed; empty otherwise.
  std::vector<PairComparison> lsd;        ///< Every pair, when performed.
};

/// Step 4.
struct TransformDecision {
  bool considered = false;              ///< Bartlett rejected equal variances.
  bool applied = false;                 ///< The data were transformed and steps 1-3 rerun.
  std::string reason;                   ///< The decision in words, with the p-value and alpha.
  std::optional<BoxCoxResult> box_cox;  ///< When considered.
  std::string formula;                  ///< The transform in words (DescribeBoxCox), when applied.
  std::optional<OneWayScaleResults> rerun;  ///< Steps 1-3 on the transformed data.
};

/// The full one-way analysis.
struct OneWayAnalysis {
  double alpha = 0.05;
  OneWayScaleResults original;
  TransformDecision transform;
};

/// Runs steps 1-4 on `data`. Throws std::invalid_argument for invalid options and for data
/// that OneWayAnova rejects (fewer than 2 groups, a group of one, constant data, every group
/// constant), naming the problem and the group.
OneWayAnalysis AnalyzeOneWay(const GroupedData& data, const OneWayAnalysisOptions& options = {});

}  // namespace hoof::stats
