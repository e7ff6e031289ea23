#include "pipeline/study_analysis.h"

#include <algorithm>
#include <map>
#include <mutex>

#include "core/parallel.h"

namespace hoof::pipeline {

TrialAnalysis AnalyzeTrialFolder(const std::filesystem::path& dir, const StudySpec& study,
                                 const TrialAnalysisOptions& options) {
  try {
    return AnalyzeTrial(ReadTrial(dir, study), options);
  } catch (const std::exception& e) {
    TrialAnalysis failed;
    failed.spec.dir = dir;
    failed.spec.id = dir.filename().string();
    failed.success = false;
    failed.error = e.what();
    return failed;
  }
}

std::vector<TrialAnalysis> AnalyzeStudy(const StudySpec& study, const TrialAnalysisOptions& options,
                                        int jobs, const std::function<void(std::size_t)>& done) {
  const std::size_t n = study.trial_dirs.size();
  std::vector<TrialAnalysis> results(n);
  std::size_t finished = 0;
  std::mutex mutex;
  core::ParallelFor(n, std::max(jobs, 1), [&](std::size_t i) {
    results[i] = AnalyzeTrialFolder(study.trial_dirs[i], study, options);
    const std::lock_guard<std::mutex> lock(mutex);
    ++finished;
    if (done) done(finished);
  });
  // Results are keyed by id: a second trial with an id already taken fails, naming both folders.
  std::map<std::string, std::size_t> first;
  for (std::size_t i = 0; i < n; ++i) {
    if (!results[i].success) continue;
    const auto [it, added] = first.try_emplace(results[i].spec.id, i);
    if (added) continue;
    results[i].success = false;
    results[i].error = (study.trial_dirs[i] / "trial.json").string() + ": field \"id\" is \"" +
                       results[i].spec.id + "\", already the id of " +
                       study.trial_dirs[it->second].string();
  }
  return results;
}

}  // namespace hoof::pipeline
