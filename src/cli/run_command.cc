// hoofimpact run: the whole study. Every trial measured, the study file written, the contact
// law fitted per surface and every trial simulated against its measurement, the paper's
// statistics, optionally the discovery workflow (--discover), the figures and the report.
// Prints where everything is.
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cmath>
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
#include "compare/study_comparison.h"
#include "core/parallel.h"
#include "io/atomic_file.h"
#include "pipeline/study_analysis.h"
#include "report/comparison_figures.h"
#include "report/figures.h"
#include "report/html_report.h"
#include "studyfile/study_file.h"

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

double Since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void Run(RunArgs& a, RunState& state) {
  ApplyMethod(a.method, a.options);
  const int jobs = core::ResolveJobs(a.jobs);
  DiscoverSettings discover;
  discover.jobs = jobs;
  discover.figures_dir = (std::filesystem::path(a.output_dir) / "figures").string();
  if (a.discover) CheckDiscoverSettings(discover);
  int step = 3;  // the numbered steps after the comparison
  const auto t0 = std::chrono::steady_clock::now();
  const pipeline::StudySpec study = pipeline::ReadStudy(a.study_dir);
  if (study.trial_dirs.empty()) throw std::runtime_error(a.study_dir + ": the study has no trials");
  const std::filesystem::path out = a.output_dir;
  std::filesystem::create_directories(out / "figures");
  // What a killed earlier run left (its temporaries) goes now.
  // Only the temporaries of run's own outputs: -o may name a folder that holds other files.
  const auto run_output = [](const std::string& name) {
    for (const char* own : {"study.h5.tmp-", "results.csv.tmp-", "stats.csv.tmp-", "report.html.tmp-"})
      if (name.rfind(own, 0) == 0) return true;
    return false;
  };
  const auto figure = [](const std::string& name) {
    return name.find(".png.tmp-") != std::string::npos || name.find(".svg.tmp-") != std::string::npos;
  };
  if (const int stale = io::RemoveStaleTemporaries(out, run_output) + io::RemoveStaleTemporaries(out / "figures", figure);
      stale > 0)
    std::cerr << "hoofimpact: removed " << stale << " temporary file(s) a killed run left\n";
  // The study file is built under a temporary name and committed once, complete (measurements,
  // comparison, statistics, discovery): a run killed on the way leaves the previous study.h5.
  const std::filesystem::path study_h5 = out / "study.h5";
  const std::filesystem::path h5 = io::TemporaryPathFor(study_h5);
  struct RemoveUncommitted {
    std::filesystem::path path;
    ~RemoveUncommitted() {
      std::error_code ec;
      std::filesystem::remove(path, ec);
    }
  } remove_uncommitted{h5};
  const bool tty = ::isatty(STDERR_FILENO) != 0;

  // 1. Measure.
  std::cout << "== 1. Measuring " << study.trial_dirs.size() << " trial(s) of " << a.study_dir
            << " on " << jobs << " thread(s)\n";
  const auto trials = pipeline::AnalyzeStudy(study, a.options, jobs, [&](std::size_t done) {
    if (tty) std::cerr << "\r  " << done << "/" << study.trial_dirs.size() << " trials" << std::flush;
  });
  if (tty) std::cerr << "\n";
  std::size_t ok = 0;
  for (const auto& t : trials) {
    ok += t.success ? 1 : 0;
    if (!t.success) std::cout << "  FAILED " << t.spec.id << ": " << t.error << "\n";
  }
  std::cout << "  " << ok << " measured, " << trials.size() - ok << " failed (" << std::fixed
            << std::setprecision(1) << Since(t0) << " s)\n";
  studyfile::StudyInfo info;
  info.name = study.name;
  info.study_dir = std::filesystem::absolute(study.dir);
  info.specimens = study.specimens;
  info.options = a.options;
  info.warnings = study.warnings;
  info.command_line = "hoofimpact run " + a.study_dir + " -o " + a.output_dir;
  studyfile::WriteStudyFile(h5, info, trials);
  studyfile::WriteResultsCsv(out / "results.csv", trials);

  // 2. Simulation against measurement.
  std::cout << "\n== 2. The contact law per surface, and every trial simulated from its measured state\n";
  const compare::StudyComparison cmp = compare::CompareStudy(trials, jobs);
  studyfile::WriteTables(h5, "/comparison", "simulation against measurement (hoofimpact run)",
                         compare::ComparisonTables(trials, cmp), {},
                         compare::ComparisonLinks(trials, cmp));
  std::cout << std::defaultfloat << std::setprecision(4);
  for (const auto& [surface, m] : cmp.surfaces) {
    std::cout << "  " << std::left << std::setw(9) << surface << std::right;
    if (!m.success) {
      std::cout << " no model: " << m.message << "\n";
      continue;
    }
    std::cout << " zeta " << m.zeta_fit.zeta << " (95 % " << m.zeta_fit.zeta_ci_low << " .. "
              << m.zeta_fit.zeta_ci_high << ", " << m.normal_trials << " normal trials), mu "
              << m.mu;
    if (m.mu_only_lower_bound) std::cout << " (a lower bound: contacts stick)";
    else if (std::isfinite(m.mu_se)) std::cout << " +- " << m.mu_se;
    std::cout << " (" << m.oblique_trials << " oblique trials); k not identified\n";
  }
  double worst_z = 0, worst_px = 0;
  std::string worst_z_id;
  int compared = 0;
  for (std::size_t i = 0; i < trials.size(); ++i) {
    const auto& c = cmp.trials[i];
    if (!c.success) continue;
    ++compared;
    const double z = std::max({std::abs(c.v_SC_after_z.x()), std::abs(c.v_SC_after_z.y()), std::abs(c.w_after_z)});
    if (z > worst_z) {
      worst_z = z;
      worst_z_id = trials[i].spec.id;
    }
    const int first_after = static_cast<int>(std::ceil(c.t_touch_s * trials[i].spec.fps));
    for (int f = first_after; f < first_after + 20 && f < static_cast<int>(c.frames.size()); ++f)
      for (double r : c.frames[static_cast<std::size_t>(f)].marker_residual_px)
        if (std::isfinite(r)) worst_px = std::max(worst_px, r);
  }
  std::cout << "  " << compared << " trial(s) compared; largest |measured - simulated| / s.e. "
            << "after impact: " << worst_z << (worst_z_id.empty() ? "" : " (" + worst_z_id + ")")
            << "; largest marker residual over the 20 frames after impact: " << worst_px << " px\n";

  // 3. Statistics.
  std::cout << "\n== " << step++ << ". Statistics (as the paper ran them in SAS)\n";
  RunStudyStatistics(h5.string(), a.alpha, (out / "stats.csv").string(), study_h5.string());

  // Discovery: where model and measurement disagree, and which effect explains it.
  bool discovered = true;
  if (a.discover) {
    std::cout << "\n== " << step++ << ". Discovery: where the model and the measurements disagree\n"
              << std::flush;
    discover.shown_as = study_h5.string();
    discovered = RunStudyDiscovery(h5.string(), trials, discover);
  }

  io::CommitTemporary(h5, study_h5);

  // Figures.
  const auto results = studyfile::ReadStudyResults(study_h5);
  auto figures = report::WriteStudyFigures(results, out / "figures");
  for (const auto& f : report::WriteComparisonFigures(study_h5, out / "figures")) figures.push_back(f);
  for (const auto& t : trials)
    for (const auto& f : WriteTrialFigures(t, a.options, (out / "figures").string(),
                                           /*always=*/false, a.trial_figures))
      figures.emplace_back(f);
  std::cout << "\n== " << step++ << ". " << figures.size() << " figure file(s) in " << (out / "figures").string() << "\n";

  // The report.
  const auto page = report::WriteHtmlReport(study_h5, out / "report.html");
  std::cout << "\n== " << step++ << ". Report: " << page.output.string() << " (" << page.bytes / 1024
            << " KiB, " << page.replays << " replay(s); open it in a browser, no network needed)\n";

  std::cout << "\nDone in " << std::fixed << std::setprecision(1) << Since(t0) << " s. Outputs in "
            << std::filesystem::absolute(out).string() << ":\n"
            << "  report.html  the report: summary, model, replay, figures, trials, statistics\n"
            << "  study.h5     everything (docs/hdf5-schema.md)\n"
            << "  results.csv  per-trial results\n"
            << "  stats.csv    the statistics tables\n"
            << "  figures/     the paper's figures 4-8 (3 with --trial-figures), out-of-plane checks"
            << (a.discover ? ", discovery" : "") << "\n";
  state.exit_code = ok == trials.size() ? kExitOk : ok == 0 ? kExitFailure : kExitPartial;
  // Asked for, the discovery must have run (why not is on stderr and in the report).
  if (!discovered) state.exit_code = kExitFailure;
}

}  // namespace

void RegisterRun(CLI::App& app, RunState& state) {
  auto args = std::make_shared<RunArgs>();
  CLI::App* cmd = app.add_subcommand(
      "run", "The whole study: measure every trial, fit and compare the contact model, "
             "statistics and figures");
  cmd->add_option("study_dir", args->study_dir, "Study folder with study.json (docs/format.md)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("-o,--output", args->output_dir, "Output folder")->capture_default_str();
  cmd->add_option("--jobs", args->jobs, "Threads (0 = all cores)")
      ->check(CLI::Range(0, 4096))->capture_default_str();
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
