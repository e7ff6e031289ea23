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
#include "cli/trial_output.h"
#include "core/parallel.h"
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
                  << " failed (" << std::fixed << std::setprecision(1) << s.measure_seconds
                  << " s)\n";
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
    std::cout << std::defaultfloat << std::setprecision(4);
    for (const auto& [surface, m] : s.comparison.surfaces) {
      std::cout << "  " << std::left << std::setw(9) << surface << std::right;
      if (!m.success) {
        std::cout << " no model: " << m.message << "\n";
        continue;
      }
      std::cout << " zeta " << m.zeta_fit.zeta << " (95 % " << m.zeta_fit.zeta_ci_low << " .. "
                << m.zeta_fit.zeta_ci_high << ", " << m.normal_trials << " normal trials), mu "
                << m.mu;
      if (m.mu_only_lower_bound)
        std::cout << " (a lower bound: contacts stick)";
      else if (std::isfinite(m.mu_se))
        std::cout << " +- " << m.mu_se;
      std::cout << " (" << m.oblique_trials << " oblique trials); k not identified\n";
    }
    std::cout << "  " << s.compared << " trial(s) compared; ";
    if (s.predictions.success)
      std::cout << s.prediction_z_over_3 << " of " << s.prediction_components
                << " trial components beyond 3 on the scale of their prediction interval "
                   "(largest |z| "
                << s.worst_prediction_z
                << (s.worst_prediction_z_id.empty() ? "" : " (" + s.worst_prediction_z_id + ")")
                << ")";
    else
      std::cout << "no prediction intervals (" << s.predictions.message << ")";
    std::cout << "; largest marker residual over the 20 frames after impact: " << s.worst_marker_px
              << " px\n";
  }

  const RunArgs& args_;
  DiscoverSettings discover_;
  bool tty_;
  int step_ = 3;  // the numbered steps after the comparison
};

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
  const study::StudyJobSummary s = study::RunStudyJob(options, &printer);
  std::cout
      << "\nDone in " << std::fixed << std::setprecision(1) << s.seconds << " s. Outputs in "
      << std::filesystem::absolute(s.output_dir).string() << ":\n"
      << "  report.html  the report: summary, model, replay, figures, trials, statistics\n"
      << "  study.h5     everything (docs/hdf5-schema.md)\n"
      << "  results.csv  per-trial results\n"
      << "  stats.csv    the statistics tables\n"
      << "  figures/     the paper's figures 4-8 (3 with --trial-figures), out-of-plane checks"
      << (a.discover ? ", discovery" : "") << "\n";
  state.exit_code = s.measured == s.trials.size() ? kExitOk
                    : s.measured == 0             ? kExitFailure
                                                  : kExitPartial;
  // Asked for, the discovery must have run (why not is on stderr and in the report).
  if (s.discovery && !s.discovery->result.success) state.exit_code = kExitFailure;
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
  cmd->add_option("-o,--output", args->output_dir, "Output folder")->capture_default_str();
  cmd->add_option("--jobs", args->jobs, "Threads (0 = all cores)")
      ->check(CLI::Range(0, 4096))
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
  AddAnalysisOptions(cmd, args->options, args->method);
  cmd->callback([args, &state] { Run(*args, state); });
}

}  // namespace hoof::cli
