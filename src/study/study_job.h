#pragma once
/// @file
/// The whole study job (`hoofimpact run`), as a library: options in, a summary out, in the
/// shape of COLMAP's AutomaticReconstructionController. The steps, in order:
///   1. measure every trial (hoof::pipeline), write the study file, results.csv and impacts.csv;
///   2. fit the contact law per surface and simulate every trial from its measured state
///      against its measurement (hoof::compare), stored under /comparison; and each trial's
///      residual on the scale of its prediction interval (discovery::PredictBaseline: the
///      baseline with the noise model of discovery), stored under /prediction;
///   3. the statistics (study/statistics.h), stored under /stats and in stats.csv;
///   4. optionally discovery (study/discovery_step.h), stored under /discovery;
///   then the study file is committed, once and complete, and the figures and the report
///   (hoof::report) are drawn from it.
/// An observer hears of each step as it starts and ends, for progress and printing; the job
/// itself prints nothing.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "compare/study_comparison.h"
#include "discovery/discovery.h"
#include "pipeline/study_format.h"
#include "pipeline/trial_analysis.h"
#include "report/html_report.h"
#include "study/discovery_step.h"
#include "study/statistics.h"

namespace hoof::study {

struct StudyJobOptions {
  std::filesystem::path study_dir;  ///< the study folder, with study.json (docs/format.md)
  std::filesystem::path output_dir = "hoofimpact-output";
  int jobs = 0;  ///< threads (0 = all cores)
  pipeline::TrialAnalysisOptions analysis;
  StatisticsOptions statistics;
  bool trial_figures = false;  ///< also every trial's displacement figure (the paper's Figure 3)
  /// Run discovery with these options (its jobs are set to the job's); none = no discovery.
  std::optional<discovery::DiscoveryOptions> discovery;
  std::string command_line;  ///< stored in the study file, and shown by the report
  /// The report's options (its command_line and study_dir are set from the job's).
  report::HtmlReportOptions report;
};

enum class StudyJobStep { kMeasure, kCompare, kStatistics, kDiscover, kFigures, kReport };

/// What the job did; filled step by step (an observer sees it grow).
struct StudyJobSummary {
  pipeline::StudySpec study;
  int jobs = 1;  ///< threads used
  std::filesystem::path output_dir, study_h5, results_csv, stats_csv, figures_dir, report_html;
  std::filesystem::path impacts_csv;  ///< one row per impact of every trial (/impacts)
  int stale_removed = 0;  ///< temporaries of a killed earlier run removed from the output folder
  std::vector<pipeline::TrialAnalysis> trials;
  std::size_t measured = 0;  ///< trials measured successfully
  double measure_seconds = 0;
  compare::StudyComparison comparison;
  int compared = 0;            ///< trials simulated against their measurement
  double worst_z = 0;          ///< largest |measured - simulated| / s.e. after impact
  std::string worst_z_id;      ///< of that trial
  double worst_marker_px = 0;  ///< largest marker residual over the 20 frames after impact
  /// Largest residual of the centre of mass C in the image over those frames (every body; the
  /// one residual of a ball or an outline).
  double worst_centre_px = 0;
  /// The compared trials without a known mass (a ball without a specimen) and what they lack.
  compare::MassGaps mass_gaps;
  /// Each trial on the scale of its prediction interval (stored under /prediction).
  discovery::BaselinePredictions predictions;
  int prediction_components = 0;  ///< trial components with a prediction z
  int prediction_z_over_3 = 0;    ///< of them, with |z| > 3
  double worst_prediction_z = 0;  ///< largest |prediction z|
  std::string worst_prediction_z_id;
  StudyStatistics statistics;
  std::optional<DiscoveryStep> discovery;
  std::vector<std::filesystem::path> figures;
  report::HtmlReportSummary report;
  double seconds = 0;  ///< the whole job

  /// Every trial measured, and discovery (when asked for) ran.
  bool Complete() const;
};

/// Hears of the job's steps; every method has an empty default.
class StudyJobObserver {
 public:
  virtual ~StudyJobObserver() = default;
  virtual void StepStarted(StudyJobStep /*step*/, const StudyJobSummary& /*so_far*/) {}
  virtual void StepDone(StudyJobStep /*step*/, const StudyJobSummary& /*so_far*/) {}
  /// `done` of `total` trials measured (from the thread that finished one, one at a time).
  virtual void TrialsMeasured(std::size_t /*done*/, std::size_t /*total*/) {}
  /// A line of discovery's progress.
  virtual void DiscoveryProgress(const std::string& /*line*/) {}
};

/// Runs the job. Throws std::runtime_error (naming the file) when the study cannot be read or
/// has no trials, or an output cannot be written; std::invalid_argument for discovery options
/// out of range. A trial that fails is recorded in the summary and the study file, and never
/// stops the job. Outputs are written atomically: a job that is killed leaves the previous
/// study.h5, results and report in place, and the next job removes its temporaries.
StudyJobSummary RunStudyJob(const StudyJobOptions& options, StudyJobObserver* observer = nullptr);

}  // namespace hoof::study
