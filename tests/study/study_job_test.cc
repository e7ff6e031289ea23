// hoof::study tested directly, without the program: the statistics of a study (which trials
// enter, against hand-computed sums of squares) and the whole job on sample_frames/ (its steps
// in order, its outputs, and a discovery that cannot run recorded as such).
#include "study/study_job.h"

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "studyfile/study_file.h"
#include "support/test_util.h"

namespace hoof::study {
namespace {

namespace fs = std::filesystem;

studyfile::TrialResult Trial(const std::string& id, const std::string& surface, double angle,
                             double e, double mu) {
  studyfile::TrialResult t;
  t.id = id;
  t.surface = surface;
  t.surface_angle_deg = angle;
  t.nominal_speed_m_s = 3.0;
  t.success = true;
  t.e = e;
  t.mu_eff = mu;
  return t;
}

TEST(StudyStatisticsTest, TrialsEnterAsThePaperChoseThemAndTheAnovaMatchesItsSums) {
  studyfile::StudyResults study;
  // e by surface: steel {0.80, 0.84, 0.82, 0.86}, concrete {0.70, 0.74, 0.72, 0.78}.
  const double e_steel[] = {0.80, 0.84, 0.82, 0.86}, e_concrete[] = {0.70, 0.74, 0.72, 0.78};
  for (int i = 0; i < 4; ++i) {
    const double angle = i < 2 ? 0.0 : 20.0;
    study.trials.push_back(Trial("s" + std::to_string(i), "steel", angle, e_steel[i],
                                 angle > 0 ? 0.2 + 0.01 * i : 1e-5));
    study.trials.push_back(Trial("c" + std::to_string(i), "concrete", angle, e_concrete[i],
                                 angle > 0 ? 0.3 + 0.01 * i : 1e-5));
  }
  auto failed = Trial("x", "steel", 20.0, 0.9, 0.1);
  failed.success = false;
  failed.error = "marker M1 lost in frame 12";
  study.trials.push_back(failed);

  const StudyStatistics s = AnalyzeStatistics(study, {}, "study.h5");
  EXPECT_EQ(s.trials, 9u);
  ASSERT_EQ(s.excluded.size(), 1u);
  EXPECT_EQ(s.excluded[0].first, "x");
  EXPECT_EQ(s.excluded[0].second, "marker M1 lost in frame 12");
  ASSERT_EQ(s.responses.size(), 2u);
  EXPECT_EQ(s.responses[0].values.size(), 8u);  // e: every successful trial
  EXPECT_EQ(s.responses[1].values.size(), 4u);  // mu_eff: the oblique ones only, as the paper
  // One-way ANOVA of e by surface, by hand: grand mean 0.7825; means 0.83 and 0.735.
  double ssb = 0, ssw = 0;
  for (const double x : e_steel) ssw += (x - 0.83) * (x - 0.83);
  for (const double x : e_concrete) ssw += (x - 0.735) * (x - 0.735);
  ssb = 4 * (0.83 - 0.7825) * (0.83 - 0.7825) + 4 * (0.735 - 0.7825) * (0.735 - 0.7825);
  const auto& by_surface = s.responses[0].factors[0];
  ASSERT_EQ(by_surface.factor, "surface");
  ASSERT_TRUE(by_surface.analysis);
  const auto& anova = by_surface.analysis->original.anova;
  EXPECT_NEAR(anova.ss_between, ssb, 1e-14);
  EXPECT_NEAR(anova.ss_within, ssw, 1e-14);
  EXPECT_NEAR(anova.f, (ssb / 1) / (ssw / 6), 1e-9);
  // Speed has one level: its analysis is not computed, and says why.
  EXPECT_FALSE(s.responses[0].factors[2].analysis);
  EXPECT_NE(s.responses[0].factors[2].note.find("not computed"), std::string::npos);
  // No successful trial: an error naming the file.
  studyfile::StudyResults none;
  none.trials.push_back(failed);
  hoof::testing::ExpectErrorContaining([&] { AnalyzeStatistics(none, {}, "empty.h5"); },
                                       "empty.h5");
}

/// Records the steps as the job reports them.
struct Recorder : StudyJobObserver {
  std::vector<std::string> events;
  std::size_t measured_calls = 0;
  void StepStarted(StudyJobStep step, const StudyJobSummary&) override {
    events.push_back("start " + std::to_string(static_cast<int>(step)));
  }
  void StepDone(StudyJobStep step, const StudyJobSummary& s) override {
    events.push_back("done " + std::to_string(static_cast<int>(step)));
    if (step == StudyJobStep::kMeasure) {
      EXPECT_EQ(s.trials.size(), s.study.trial_dirs.size());
    }
  }
  void TrialsMeasured(std::size_t, std::size_t) override { ++measured_calls; }
};

TEST(StudyJobTest, TheWholeJobOnTheSampleTrials) {
  const fs::path out = hoof::testing::FreshDir("study_job");
  StudyJobOptions options;
  options.study_dir = fs::path(HOOF_SOURCE_DIR) / "sample_frames";
  options.output_dir = out;
  options.jobs = 2;
  options.discovery = discovery::DiscoveryOptions{};  // four trials: too few, recorded as such
  Recorder recorder;
  const StudyJobSummary s = RunStudyJob(options, &recorder);

  EXPECT_EQ(s.trials.size(), 4u);
  EXPECT_EQ(s.measured, 4u);
  EXPECT_EQ(recorder.measured_calls, 4u);
  const std::vector<std::string> order = {"start 0", "done 0", "start 1", "done 1",
                                          "start 2", "done 2", "start 3", "done 3",
                                          "start 4", "done 4", "start 5", "done 5"};
  EXPECT_EQ(recorder.events, order);
  // A contact law for steel only (the one surface with a normal trial, to fit zeta to); its two
  // trials simulated against their measurement, the others recorded without a model.
  EXPECT_EQ(s.comparison.surfaces.size(), 3u);
  EXPECT_TRUE(s.comparison.surfaces.at("steel").success);
  EXPECT_FALSE(s.comparison.surfaces.at("asphalt").success);
  EXPECT_EQ(s.compared, 2);
  EXPECT_EQ(s.worst_z_id.rfind("steel", 0), 0u);
  EXPECT_TRUE(std::isfinite(s.worst_z));
  // The outputs, complete: the study file with its comparison, statistics and discovery.
  EXPECT_EQ(studyfile::ReadStudyResults(s.study_h5).trials.size(), 4u);
  EXPECT_NO_THROW(studyfile::ReadTable(s.study_h5, "/comparison/surfaces"));
  EXPECT_NO_THROW(studyfile::ReadTable(s.study_h5, "/stats/e/cells"));
  EXPECT_NO_THROW(studyfile::ReadTable(s.study_h5, "/discovery/summary"));
  EXPECT_TRUE(fs::exists(s.results_csv));
  EXPECT_TRUE(fs::exists(s.stats_csv));
  EXPECT_GT(s.report.bytes, 1000u);
  EXPECT_FALSE(s.figures.empty());
  for (const auto& f : s.figures) EXPECT_TRUE(fs::exists(f)) << f;
  // Discovery could not run on four trials: the job still completes, and says so.
  ASSERT_TRUE(s.discovery);
  EXPECT_FALSE(s.discovery->result.success);
  EXPECT_FALSE(s.discovery->result.message.empty());
  EXPECT_FALSE(s.Complete());
  // No temporary left beside the outputs.
  for (const auto& e : fs::directory_iterator(out))
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
}

TEST(StudyJobTest, AStudyWithoutTrialsIsAnErrorNamingTheFolder) {
  const fs::path dir = hoof::testing::FreshDir("study_job_empty");
  hoof::testing::ExpectErrorContaining(
      [&] {
        StudyJobOptions options;
        options.study_dir = dir;
        options.output_dir = dir / "out";
        RunStudyJob(options);
      },
      dir.string());
}

}  // namespace
}  // namespace hoof::study
