#include "pipeline/study_analysis.h"

#include <algorithm>
#include <atomic>
#include <map>
#include <mutex>
#include <thread>

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
  std::atomic<std::size_t> next{0};
  std::size_t finished = 0;
  std::mutex mutex;
  const auto worker = [&] {
    for (std::size_t i = next++; i < n; i = next++) {
      results[i] = AnalyzeTrialFolder(study.trial_dirs[i], study, options);
      const std::lock_guard<std::mutex> lock(mutex);
      ++finished;
      if (done) done(finished);
    }
  };
  const std::size_t threads = std::min<std::size_t>(static_cast<std::size_t>(std::max(jobs, 1)), n);
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  // Results are keyed by id: a second trial with an id already taken fails, naming both folders.
  std::map<std::string, std::size_t> first;
  for (std::size_t i = 0; i < n; ++i) {
    if (!results[i].success) continue;
    const auto [it, added] = first.try_emplace(results[i].spec.id, i);
    if (added) continue;
    results[i].success = false;
    results[i].error = (study.trial_dirs[i] / "trial.json").string() + ": field \"id\" is \"" + results[i].spec.id +
                       "\", already the id of " + study.trial_dirs[it->second].string();
  }
  return results;
}

}  // namespace hoof::pipeline
