#include "study/study_job.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "compare/comparison_tables.h"
#include "core/parallel.h"
#include "discovery/discovery_tables.h"
#include "io/atomic_file.h"
#include "pipeline/study_analysis.h"
#include "report/comparison_figures.h"
#include "report/figures.h"
#include "report/gnuplot.h"
#include "studyfile/study_file.h"

namespace hoof::study {
namespace {

namespace fs = std::filesystem;

double Since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Removes what a killed earlier job left beside the outputs: only the temporaries of the job's
/// own outputs, as the output folder may hold other files.
int RemoveStaleOutputs(const fs::path& out) {
  const auto own = [](const std::string& name) {
    for (const char* prefix : {"study.h5.tmp-", "results.csv.tmp-", "impacts.csv.tmp-",
                               "stats.csv.tmp-", "report.html.tmp-"})
      if (name.rfind(prefix, 0) == 0) return true;
    return false;
  };
  return io::RemoveStaleTemporaries(out, own) +
         io::RemoveStaleTemporaries(out / "figures", report::IsFigureTemporary);
}

/// The comparison's headline numbers: the worst disagreement after impact, in standard errors
/// and in pixels.
void SummarizeComparison(StudyJobSummary& s) {
  for (std::size_t i = 0; i < s.trials.size(); ++i) {
    const auto& c = s.comparison.trials[i];
    if (!c.success) continue;
    ++s.compared;
    double z = 0;  // a ball's spin is not seen: its z is NaN and does not count
    for (double zi : {c.v_SC_after_z.x(), c.v_SC_after_z.y(), c.w_after_z})
      if (std::isfinite(zi)) z = std::max(z, std::abs(zi));
    if (z > s.worst_z) {
      s.worst_z = z;
      s.worst_z_id = s.trials[i].spec.id;
    }
    // The frames after impact, 20 at most, and none beyond the flight its fit used: at a
    // video's rate 20 frames reach past the next bounce, which the simulation does not hold.
    const int first_after = static_cast<int>(std::ceil(c.t_touch_s * s.trials[i].spec.fps));
    const int flight_end = s.trials[i].impact.after.last_frame;
    const int end = std::min({first_after + 20, static_cast<int>(c.frames.size()),
                              flight_end >= first_after ? flight_end + 1 : first_after + 20});
    for (int f = first_after; f < end; ++f) {
      const auto& frame = c.frames[static_cast<std::size_t>(f)];
      for (double r : frame.marker_residual_px)
        if (std::isfinite(r)) s.worst_marker_px = std::max(s.worst_marker_px, r);
      if (std::isfinite(frame.centre_residual_px))
        s.worst_centre_px = std::max(s.worst_centre_px, frame.centre_residual_px);
    }
  }
  s.mass_gaps = compare::MassGapsOf(s.comparison);
}

/// The prediction z's headline numbers: how many trial components lie beyond 3 and the largest.
void SummarizePredictions(StudyJobSummary& s) {
  for (const discovery::TrialPrediction& t : s.predictions.trials)
    for (int c = 0; c < 3; ++c) {
      const double z = std::abs(t.z[c]);
      if (!std::isfinite(z)) continue;
      ++s.prediction_components;
      s.prediction_z_over_3 += z > 3.0 ? 1 : 0;
      if (z > s.worst_prediction_z) {
        s.worst_prediction_z = z;
        s.worst_prediction_z_id = t.id;
      }
    }
}

/// The job's summary before its first step: the study read, the outputs' paths, the figures'
/// folder made and what a killed earlier job left removed. Throws for a study without trials.
StudyJobSummary Prepare(const StudyJobOptions& options) {
  StudyJobSummary s;
  s.jobs = core::ResolveJobs(options.jobs);
  s.study = pipeline::ReadStudy(options.study_dir);
  if (s.study.trial_dirs.empty())
    throw std::runtime_error(options.study_dir.string() + ": the study has no trials");
  const fs::path& out = options.output_dir;
  s.output_dir = out;
  s.study_h5 = out / "study.h5";
  s.results_csv = out / "results.csv";
  s.impacts_csv = out / "impacts.csv";
  s.stats_csv = out / "stats.csv";
  s.figures_dir = out / "figures";
  s.report_html = out / "report.html";
  fs::create_directories(s.figures_dir);
  s.stale_removed = RemoveStaleOutputs(out);
  return s;
}

/// Step 1: every trial measured, written to the uncommitted study file `h5`, results.csv and
/// impacts.csv.
/// `measure_seconds` counts from `t0`, the job's start, to the last trial measured.
void Measure(const StudyJobOptions& options, const fs::path& h5,
             std::chrono::steady_clock::time_point t0, StudyJobObserver& tell, StudyJobSummary& s) {
  s.trials = pipeline::AnalyzeStudy(s.study, options.analysis, s.jobs, [&](std::size_t done) {
    tell.TrialsMeasured(done, s.study.trial_dirs.size());
  });
  for (const auto& t : s.trials) s.measured += t.success ? 1 : 0;
  s.measure_seconds = Since(t0);
  studyfile::WriteStudyFile(
      h5, studyfile::StudyInfo::Of(s.study, options.analysis, options.command_line), s.trials);
  studyfile::WriteResultsCsv(s.results_csv, s.trials);
  studyfile::WriteImpactsCsv(s.impacts_csv, s.trials);
}

/// The study's figures, the comparison's and each trial's that was asked for (or failed), from
/// the committed study file.
void DrawFigures(const StudyJobOptions& options, StudyJobSummary& s) {
  const auto results = studyfile::ReadStudyResults(s.study_h5);
  s.figures = report::WriteStudyFigures(results, s.figures_dir);
  for (const auto& f : report::WriteComparisonFigures(s.study_h5, s.figures_dir))
    s.figures.push_back(f);
  for (const auto& t : s.trials)
    for (const auto& f : report::WriteTrialFigures(t, options.analysis, s.figures_dir.string(),
                                                   /*always=*/false, options.trial_figures))
      s.figures.emplace_back(f);
}

}  // namespace

bool StudyJobSummary::Complete() const {
  return measured == trials.size() && (!discovery || discovery->result.success);
}

StudyJobSummary RunStudyJob(const StudyJobOptions& options, StudyJobObserver* observer) {
  StudyJobObserver silent;
  StudyJobObserver& tell = observer ? *observer : silent;
  const auto t0 = std::chrono::steady_clock::now();
  StudyJobSummary s = Prepare(options);
  // The study file is built under a temporary name and committed once, complete (measurements,
  // comparison, statistics, discovery): a job killed on the way leaves the previous study.h5.
  const fs::path h5 = io::TemporaryPathFor(s.study_h5);
  struct RemoveUncommitted {
    fs::path path;
    ~RemoveUncommitted() {
      std::error_code ec;
      fs::remove(path, ec);
    }
  } remove_uncommitted{h5};

  // 1. Measure.
  tell.StepStarted(StudyJobStep::kMeasure, s);
  Measure(options, h5, t0, tell, s);
  tell.StepDone(StudyJobStep::kMeasure, s);

  // 2. Simulation against measurement.
  tell.StepStarted(StudyJobStep::kCompare, s);
  s.comparison = compare::CompareStudy(s.trials, s.jobs);
  studyfile::WriteTables(h5, "/comparison", "simulation against measurement (hoofimpact run)",
                         compare::ComparisonTables(s.trials, s.comparison), {},
                         compare::ComparisonLinks(s.trials, s.comparison));
  SummarizeComparison(s);
  // Each trial on the scale of its prediction interval: the baseline fitted with the noise model
  // discovery uses (trial-to-trial scatter of zeta and mu, measurement error).
  {
    discovery::DiscoveryOptions d = options.discovery.value_or(discovery::DiscoveryOptions{});
    d.jobs = s.jobs;
    s.predictions = discovery::PredictBaseline(s.trials, d);
    studyfile::WriteTables(h5, discovery::kPredictionGroup,
                           "each trial's residual after impact on the scale of its prediction "
                           "interval under the baseline model (hoofimpact run)",
                           discovery::PredictionTables(s.predictions));
    SummarizePredictions(s);
  }
  tell.StepDone(StudyJobStep::kCompare, s);

  // 3. Statistics.
  tell.StepStarted(StudyJobStep::kStatistics, s);
  s.statistics = StoreStatistics(h5, options.statistics, s.stats_csv, s.study_h5.string());
  tell.StepDone(StudyJobStep::kStatistics, s);

  // 4. Discovery: where model and measurement disagree, and which effect explains it.
  if (options.discovery) {
    tell.StepStarted(StudyJobStep::kDiscover, s);
    discovery::DiscoveryOptions d = *options.discovery;
    d.jobs = s.jobs;
    s.discovery = DiscoverAndStore(h5, s.trials, d, s.figures_dir,
                                   [&](const std::string& line) { tell.DiscoveryProgress(line); });
    tell.StepDone(StudyJobStep::kDiscover, s);
  }

  io::CommitTemporary(h5, s.study_h5);

  // Figures, from the committed study file.
  tell.StepStarted(StudyJobStep::kFigures, s);
  DrawFigures(options, s);
  tell.StepDone(StudyJobStep::kFigures, s);

  // The report.
  tell.StepStarted(StudyJobStep::kReport, s);
  report::HtmlReportOptions report_options = options.report;
  report_options.command_line = options.command_line;
  report_options.study_dir = options.study_dir;
  s.report = report::WriteHtmlReport(s.study_h5, s.report_html, report_options);
  s.seconds = Since(t0);
  tell.StepDone(StudyJobStep::kReport, s);
  return s;
}

}  // namespace hoof::study
