#pragma once
/// @file
/// Every trial of a study, measured in parallel. A trial that cannot be read or measured
/// becomes a failed TrialAnalysis with its reason; it never stops the others.

#include <cstddef>
#include <filesystem>
#include <functional>
#include <vector>

#include "pipeline/study_format.h"
#include "pipeline/trial_analysis.h"

namespace hoof::pipeline {

/// Reads and analyses one trial folder. Never throws: a trial.json that cannot be read (or any
/// other exception) becomes a failed TrialAnalysis whose error names the file.
TrialAnalysis AnalyzeTrialFolder(const std::filesystem::path& dir, const StudySpec& study,
                                 const TrialAnalysisOptions& options);

/// Analyses every trial of `study` on `jobs` threads (at least 1); results are in the study's
/// order whatever the scheduling. `done(n)` is called, serialized, after each trial.
std::vector<TrialAnalysis> AnalyzeStudy(const StudySpec& study, const TrialAnalysisOptions& options,
                                        int jobs,
                                        const std::function<void(std::size_t)>& done = {});

}  // namespace hoof::pipeline
