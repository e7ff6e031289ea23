// hoof::study tested directly, without the program: the statistics of a study (which trials
// enter, against hand-computed sums of squares) and the whole job on sample_frames/ (its steps
// in order, its outputs, and a discovery that cannot run recorded as such).
#include "study/study_job.h"

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "study/statistics.h"
#include "studyfile/stats_tables.h"
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

// e by surface: steel {0.80, 0.84, 0.82, 0.86}, concrete {0.70, 0.74, 0.72, 0.78}.
const double e_steel[] = {0.80, 0.84, 0.82, 0.86}, e_concrete[] = {0.70, 0.74, 0.72, 0.78};

/// Eight successful trials (two surfaces, 0 and 20 deg, one speed) and one failed.
studyfile::StudyResults HandStudy() {
  studyfile::StudyResults study;
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
  return study;
}

TEST(StudyStatisticsTest, TrialsEnterAsThePaperChoseThemAndTheAnovaMatchesItsSums) {
  const studyfile::StudyResults study = HandStudy();
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
  none.trials.push_back(study.trials.back());
  hoof::testing::ExpectErrorContaining([&] { AnalyzeStatistics(none, {}, "empty.h5"); },
                                       "empty.h5");
}

// The /stats tables as stored and read back through their typed reader (studyfile/stats_tables.h):
// every table the analysis has, with the numbers it computed.
TEST(StudyStatisticsTest, StoredTablesReadBackAsComputed) {
  const StudyStatistics s = AnalyzeStatistics(HandStudy(), {}, "study.h5");
  const fs::path h5 = hoof::testing::FreshDir("stats_tables") / "study.h5";
  studyfile::StudyInfo info;
  info.name = "hand";
  studyfile::WriteStudyFile(h5, info, {});
  EXPECT_FALSE(studyfile::HasStatistics(h5));
  studyfile::WriteTables(h5, "/stats", StatisticsDescription(s.options), StatisticsTables(s));
  ASSERT_TRUE(studyfile::HasStatistics(h5));
  const studyfile::StoredStatistics read = studyfile::ReadStatistics(h5);

  EXPECT_EQ(read.description, StatisticsDescription(s.options));
  ASSERT_EQ(read.excluded.size(), 1u);
  EXPECT_EQ(read.excluded[0].id, "x");
  EXPECT_EQ(read.excluded[0].reason, "marker M1 lost in frame 12");
  ASSERT_EQ(read.responses.size(), 2u);
  const studyfile::StoredResponse& e = read.responses[0];
  EXPECT_EQ(e.response, "e");
  // Cells: steel|0 holds 0.80 and 0.84.
  ASSERT_EQ(e.cells.rows.size(), 4u);
  EXPECT_EQ(e.cells.rows[0].cell, "steel|0");
  EXPECT_EQ(e.cells.rows[0].surface, "steel");
  EXPECT_EQ(e.cells.rows[0].angle_deg, "0");
  EXPECT_EQ(e.cells.rows[0].n, 2u);
  EXPECT_DOUBLE_EQ(e.cells.rows[0].mean, 0.82);
  // Surface and angle analysed; speed (one level) not, with its note.
  ASSERT_EQ(e.factors.size(), 2u);
  EXPECT_EQ(e.factors[0].factor, "surface");
  EXPECT_EQ(e.factors[1].factor, "angle");
  const auto& computed = s.responses[0].factors[0].analysis->original;
  const auto& anova = e.factors[0].original.anova.rows;
  ASSERT_EQ(anova.size(), 3u);
  EXPECT_EQ(anova[0].source, "between");
  EXPECT_EQ(anova[0].df, 1u);
  EXPECT_EQ(anova[1].df, 6u);
  EXPECT_EQ(anova[2].df, 7u);
  EXPECT_EQ(anova[0].ss, computed.anova.ss_between);
  EXPECT_EQ(anova[0].p, computed.anova.p);
  EXPECT_TRUE(std::isnan(anova[2].f));
  ASSERT_EQ(e.factors[0].original.groups.rows.size(), 2u);
  EXPECT_EQ(e.factors[0].original.groups.rows[1].group, "concrete");
  EXPECT_DOUBLE_EQ(e.factors[0].original.groups.rows[1].mean, 0.735);
  ASSERT_EQ(e.factors[0].original.tests.rows.size(), 2u);
  EXPECT_EQ(e.factors[0].original.tests.rows[0].test, "bartlett");
  EXPECT_EQ(e.factors[0].original.tests.rows[0].p, computed.bartlett.p);
  EXPECT_EQ(e.factors[0].original.lsd.rows.size(), computed.lsd.size());
  for (std::size_t i = 0; i < computed.lsd.size(); ++i) {
    EXPECT_EQ(e.factors[0].original.lsd.rows[i].significant, computed.lsd[i].significant);
    EXPECT_EQ(e.factors[0].original.lsd.rows[i].df, computed.lsd[i].df);
  }
  const auto& transform = s.responses[0].factors[0].analysis->transform;
  EXPECT_EQ(e.factors[0].transform.considered, transform.considered);
  EXPECT_EQ(e.factors[0].transform.applied, transform.applied);
  EXPECT_EQ(e.factors[0].transformed.has_value(), transform.rerun.has_value());
  // The two-way table: surface, angle, their interaction and the error, 8 - 4 = 4 error df.
  ASSERT_TRUE(e.two_way);
  ASSERT_EQ(e.two_way->rows.size(), 4u);
  EXPECT_EQ(e.two_way->rows[3].df, 4u);
  ASSERT_EQ(e.notes.size(), 1u);
  EXPECT_EQ(e.notes[0].analysis, "by_speed");
  // mu_eff: the four oblique trials.
  EXPECT_EQ(read.responses[1].response, "mu_eff");
  std::size_t n = 0;
  for (const auto& c : read.responses[1].cells.rows) n += c.n;
  EXPECT_EQ(n, 4u);
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
