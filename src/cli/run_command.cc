// hoofimpact run: the whole study (study::RunStudyJob, src/study/study_job.h): every trial
// measured, the study file written, the contact law fitted per surface and every trial simulated
// against its measurement, the paper's statistics, optionally the discovery workflow
// (--discover), the figures and the report. Here: the options, and what is printed as each step
// starts and ends.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/json_output.h"
#include "cli/trial_output.h"
#include "core/parallel.h"
#include "discovery/discovery_json.h"
#include "format/number_format.h"
#include "study/statistics_text.h"
#include "study/study_job.h"

namespace hoof::cli {
namespace {

struct RunArgs {
  std::string study_dir;
  std::string output_dir = "hoofimpact-output";
  int jobs = 0;
  double alpha = 0.05;
  bool trial_figures = false;
  bool discover = false;
  bool json = false;
  pipeline::TrialAnalysisOptions options;
  std::string method = "centroid";
};

/// Prints each step of the job as it starts and ends (stdout), and the trials measured so far
/// on a terminal (stderr).
class RunPrinter : public study::StudyJobObserver {
 public:
  RunPrinter(const RunArgs& args, const DiscoverSettings& discover)
      : args_(args), discover_(discover), tty_(::isatty(STDERR_FILENO) != 0) {}

  void StepStarted(study::StudyJobStep step, const study::StudyJobSummary& s) override {
    using Step = study::StudyJobStep;
    switch (step) {
      case Step::kMeasure:
        if (s.stale_removed > 0)
          std::cerr << "hoofimpact: removed " << s.stale_removed
                    << " temporary file(s) a killed run left\n";
        std::cout << "== 1. Measuring " << s.study.trial_dirs.size() << " trial(s) of "
                  << args_.study_dir << " on " << s.jobs << " thread(s)\n";
        break;
      case Step::kCompare:
        std::cout << "\n== 2. The contact law per surface, and every trial simulated from its "
                     "measured state\n";
        break;
      case Step::kStatistics:
        std::cout << "\n== " << step_++ << ". Statistics (as the paper ran them in SAS)\n";
        break;
      case Step::kDiscover:
        std::cout << "\n== " << step_++
                  << ". Discovery: where the model and the measurements disagree\n"
                  << std::flush;
        break;
      case Step::kFigures:
      case Step::kReport:
        break;
    }
  }

  void TrialsMeasured(std::size_t done, std::size_t total) override {
    if (tty_) std::cerr << "\r  " << done << "/" << total << " trials" << std::flush;
  }

  void DiscoveryProgress(const std::string& line) override {
    std::cerr << "  discover: " << line << std::endl;
  }

  void StepDone(study::StudyJobStep step, const study::StudyJobSummary& s) override {
    using Step = study::StudyJobStep;
    switch (step) {
      case Step::kMeasure:
        if (tty_) std::cerr << "\n";
        for (const auto& t : s.trials)
          if (!t.success) std::cout << "  FAILED " << t.spec.id << ": " << t.error << "\n";
        std::cout << "  " << s.measured << " measured, " << s.trials.size() - s.measured
                  << " failed (" << format::Seconds(s.measure_seconds) << ")\n";
        break;
      case Step::kCompare:
        PrintComparison(s);
        break;
      case Step::kStatistics:
        PrintStudyStatistics(s.statistics, s.stats_csv.string());
        break;
      case Step::kDiscover: {
        DiscoverSettings shown = discover_;
        shown.shown_as = s.study_h5.string();
        PrintDiscoveryStep(*s.discovery, shown);
        break;
      }
      case Step::kFigures:
        std::cout << "\n== " << step_++ << ". " << s.figures.size() << " figure file(s) in "
                  << s.figures_dir.string() << "\n";
        break;
      case Step::kReport:
        std::cout << "\n== " << step_++ << ". Report: " << s.report.output.string() << " ("
                  << s.report.bytes / 1024 << " KiB, " << s.report.replays
                  << " replay(s); open it in a browser, no network needed)\n";
        // What the report left out (a replay whose frames were not found), as `report` says it.
        if (!s.report.notes.empty()) std::cerr << s.report.notes;
        break;
    }
  }

 private:
  static void PrintComparison(const study::StudyJobSummary& s) {
    using format::Kind;
    for (const auto& [surface, m] : s.comparison.surfaces) {
      std::cout << "  " << std::left << std::setw(9) << surface << std::right;
      if (!m.success) {
        std::cout << " no model: " << m.message << "\n";
        continue;
      }
      std::cout << " zeta " << format::Number(m.zeta_fit.zeta, Kind::kCoefficient) << " (95 % "
                << format::Interval(m.zeta_fit.zeta_ci_low, m.zeta_fit.zeta_ci_high,
                                    Kind::kCoefficient)
                << ", " << m.normal_trials << " normal trials), mu ";
      if (m.mu_only_lower_bound)
        std::cout << format::Number(m.mu, Kind::kCoefficient) << " (a lower bound: contacts stick)";
      else
        std::cout << format::WithError(m.mu, m.mu_se, Kind::kCoefficient);
      std::cout << " (" << m.oblique_trials << " oblique trials); "
                << (m.mass_known ? "k not identified" : "k and b need the mass (not given)")
                << "\n";
    }
    if (const std::string gaps = s.mass_gaps.Text(); !gaps.empty())
      std::cout << "  " << gaps << "\n";
    std::cout << "  " << s.compared << " trial(s) compared; ";
    if (s.predictions.success)
      std::cout << s.prediction_z_over_3 << " of " << s.prediction_components
                << " trial components beyond 3 on the scale of their prediction interval "
                   "(largest |z| "
                << format::Number(s.worst_prediction_z, Kind::kStatistic)
                << (s.worst_prediction_z_id.empty() ? "" : " (" + s.worst_prediction_z_id + ")")
                << ")";
    else
      std::cout << "no prediction intervals (" << s.predictions.message << ")";
    std::cout << "; largest residual over the flight after impact (20 frames at most): ";
    if (s.worst_marker_px > 0)  // a study of bodies without markers has none
      std::cout << format::Number(s.worst_marker_px) << " px of a marker, ";
    std::cout << format::Number(s.worst_centre_px) << " px of the centre of mass\n";
  }

  const RunArgs& args_;
  DiscoverSettings discover_;
  bool tty_;
  int step_ = 3;  // the numbered steps after the comparison
};

/// The envelope of `run --json`: the outputs, the counts, the model per surface, the
/// statistics, the discovery (null without --discover) and every trial.
void PrintRunJson(const RunArgs& a, const study::StudyJobSummary& s, int exit_code) {
  nlohmann::json surfaces = nlohmann::json::array();
  for (const auto& [surface, m] : s.comparison.surfaces) surfaces.push_back(SurfaceModelJson(m));
  nlohmann::json trials = nlohmann::json::array();
  std::vector<JsonError> errors;
  for (const auto& t : s.trials) {
    trials.push_back(TrialJson(t));
    if (!t.success) errors.push_back({t.error, "", t.spec.dir.string(), t.spec.id, ""});
  }
  nlohmann::json discovery = nullptr;
  if (s.discovery) {
    discovery = discovery::DiscoveryJson(s.discovery->result);
    if (!s.discovery->result.success)
      errors.push_back({"the discovery workflow could not run: " + s.discovery->result.message, "",
                        s.study_h5.string(), "", ""});
  }
  std::vector<std::string> figures;
  for (const auto& f : s.figures) figures.push_back(f.string());
  const nlohmann::json results = {{"study_dir", a.study_dir},
                                  {"output_dir", s.output_dir.string()},
                                  {"study_h5", s.study_h5.string()},
                                  {"results_csv", s.results_csv.string()},
                                  {"impacts_csv", s.impacts_csv.string()},
                                  {"stats_csv", s.stats_csv.string()},
                                  {"figures_dir", s.figures_dir.string()},
                                  {"report_html", s.report.output.string()},
                                  {"jobs", s.jobs},
                                  {"trials_total", s.trials.size()},
                                  {"measured", s.measured},
                                  {"failed", s.trials.size() - s.measured},
                                  {"compared", s.compared},
                                  {"worst_z", JsonNumber(s.worst_z)},
                                  {"worst_z_id", s.worst_z_id},
                                  {"worst_marker_px", JsonNumber(s.worst_marker_px)},
                                  {"worst_centre_px", JsonNumber(s.worst_centre_px)},
                                  {"trials_without_mass", s.mass_gaps.without_mass},
                                  {"mass_note", s.mass_gaps.Text()},
                                  {"prediction",
                                   {{"success", s.predictions.success},
                                    {"message", s.predictions.message},
                                    {"components", s.prediction_components},
                                    {"beyond_3", s.prediction_z_over_3},
                                    {"worst_z", JsonNumber(s.worst_prediction_z)},
                                    {"worst_z_id", s.worst_prediction_z_id}}},
                                  {"surfaces", surfaces},
                                  {"statistics", study::StudyStatisticsJson(s.statistics)},
                                  {"discovery", discovery},
                                  {"figures", figures},
                                  {"report", ReportJson(s.report)},
                                  {"measure_seconds", s.measure_seconds},
                                  {"seconds", s.seconds},
                                  {"trials", trials}};
  PrintEnvelope("run", exit_code, results, errors);
}

void Run(RunArgs& a, RunState& state) {
  ApplyMethod(a.method, a.options);
  DiscoverSettings discover;
  discover.jobs = core::ResolveJobs(a.jobs);
  discover.figures_dir = (std::filesystem::path(a.output_dir) / "figures").string();
  if (a.discover) CheckDiscoverSettings(discover);
  study::StudyJobOptions options;
  options.study_dir = a.study_dir;
  options.output_dir = a.output_dir;
  options.jobs = a.jobs;
  options.analysis = a.options;
  options.statistics.alpha = a.alpha;
  options.trial_figures = a.trial_figures;
  if (a.discover) options.discovery = DiscoveryOptionsOf(discover);
  options.command_line = state.command_line.empty()
                             ? "hoofimpact run " + a.study_dir + " -o " + a.output_dir
                             : state.command_line;
  RunPrinter printer(a, discover);
  // With --json, stdout holds the envelope alone: the steps' text goes to stderr.
  std::streambuf* const stdout_buffer = a.json ? std::cout.rdbuf(std::cerr.rdbuf()) : nullptr;
  study::StudyJobSummary s;
  try {
    s = study::RunStudyJob(options, &printer);
  } catch (...) {
    if (stdout_buffer != nullptr) std::cout.rdbuf(stdout_buffer);
    throw;
  }
  std::cout
      << "\nDone in " << format::Seconds(s.seconds) << ". Outputs in "
      << std::filesystem::absolute(s.output_dir).string() << ":\n"
      << "  report.html  the report: summary, model, replay, figures, trials, statistics\n"
      << "  study.h5     everything (docs/hdf5-schema.md)\n"
      << "  results.csv  per-trial results\n"
      << "  impacts.csv  per-impact results (every impact of each clip)\n"
      << "  stats.csv    the statistics tables\n"
      << "  figures/     the paper's figures 4-8 (3 with --trial-figures), out-of-plane checks"
      << (a.discover ? ", discovery" : "") << "\n";
  state.exit_code = s.measured == s.trials.size() ? kExitOk
                    : s.measured == 0             ? kExitFailure
                                                  : kExitPartial;
  // Asked for, the discovery must have run (why not is on stderr and in the report).
  if (s.discovery && !s.discovery->result.success) state.exit_code = kExitFailure;
  if (stdout_buffer != nullptr) {
    std::cout.rdbuf(stdout_buffer);
    PrintRunJson(a, s, state.exit_code);
  }
}

}  // namespace

void RegisterRun(CLI::App& app, RunState& state) {
  auto args = std::make_shared<RunArgs>();
  CLI::App* cmd =
      app.add_subcommand("run",
                         "The whole study: measure every trial, fit and compare the contact model, "
                         "statistics and figures");
  cmd->add_option("study_dir", args->study_dir, "Study folder with study.json (docs/format.md)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option(
         "-o,--output", args->output_dir,
         "Output folder: study.h5, results.csv, impacts.csv, stats.csv, figures/, report.html")
      ->capture_default_str();
  cmd->add_option("--jobs", args->jobs, "Threads (0 = all cores)")
      ->check(InRange(0, 4096))
      ->capture_default_str();
  cmd->add_option("--alpha", args->alpha, "Significance level of the statistics, in (0, 0.5)")
      ->check(CLI::Validator(
          [](std::string& text) {
            const double a = std::strtod(text.c_str(), nullptr);
            return a > 0 && a < 0.5 ? std::string() : "must be in (0, 0.5), got " + text;
          },
          "(0, 0.5)"))
      ->capture_default_str();
  cmd->add_flag("--trial-figures", args->trial_figures,
                "Also draw every trial's displacement figure (paper Figure 3)");
  cmd->add_flag("--discover", args->discover,
                "Also run the discovery workflow (as `hoofimpact discover` with its defaults) "
                "after the comparison: /discovery, its figures and the report's Discovery section");
  AddJsonFlag(cmd, args->json);
  AddAnalysisOptions(cmd, args->options, args->method);
  cmd->callback([args, &state] { Run(*args, state); });
}

}  // namespace hoof::cli
