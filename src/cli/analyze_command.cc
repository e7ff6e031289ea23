// hoofimpact analyze: a whole study folder -> every trial measured (in parallel) -> one HDF5
// study file, with optional JSON and CSV exports. A bad trial is recorded with its reason and
// never stops the others.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/json_output.h"
#include "cli/trial_output.h"
#include "core/parallel.h"
#include "format/number_format.h"
#include "io/atomic_file.h"
#include "pipeline/study_analysis.h"
#include "pipeline/study_format.h"
#include "pipeline/trial_analysis.h"
#include "report/figures.h"
#include "report/gnuplot.h"
#include "studyfile/study_file.h"

namespace hoof::cli {
namespace {

struct AnalyzeArgs {
  std::string study_dir;
  std::string output;
  std::string csv;
  std::string tracks_csv;
  std::string impacts_csv;
  std::string figures_dir;
  bool figures_all = false;
  bool json = false;
  int jobs = 0;
  pipeline::TrialAnalysisOptions options;
  std::string method = "centroid";
  std::string command_line;
};

std::string Summary(const std::vector<pipeline::TrialAnalysis>& results, const std::string& output,
                    double seconds) {
  std::size_t ok = 0;
  for (const auto& r : results) ok += r.success ? 1 : 0;
  std::ostringstream os;
  os << "Analysed " << results.size() << " trial(s) in " << format::Seconds(seconds) << ": " << ok
     << " ok, " << results.size() - ok << " failed\n";
  for (const auto& r : results)
    if (!r.success) os << "  FAILED " << r.spec.id << ": " << r.error << "\n";
  // Metadata the images contradict: measured, but a user must see it.
  for (const auto& r : results)
    if (r.success && std::find(r.flags.begin(), r.flags.end(), "surface_angle") != r.flags.end())
      for (const auto& w : r.warnings)
        if (w.find("the surface in the image is at") != std::string::npos)
          os << "  WARNING " << r.spec.id << ": " << w << " (results use trial.json's angle)\n";
  os << "Study file: " << output << "\n";
  return os.str();
}

void Run(AnalyzeArgs& a, RunState& state) {
  ApplyMethod(a.method, a.options);
  a.options.kinematics.Validate();
  a.options.tracker.Validate();
  if (a.jobs < 0)
    throw CLI::ValidationError("--jobs", "must be >= 0, got " + std::to_string(a.jobs));
  const int jobs = core::ResolveJobs(a.jobs);
  const pipeline::StudySpec study = pipeline::ReadStudy(a.study_dir);
  if (study.trial_dirs.empty()) throw std::runtime_error(a.study_dir + ": the study has no trials");
  for (const auto& w : study.warnings) std::cerr << "hoofimpact: warning: " << w << "\n";
  // What a killed earlier run left beside the output (its temporaries) goes now.
  {
    // Only the study file's own temporaries and figures' (PNG, SVG and their gnuplot scripts):
    // these folders may hold anyone's files.
    const std::filesystem::path output = std::filesystem::absolute(a.output);
    const std::string study_tmp = output.filename().string() + ".tmp-";
    int stale = io::RemoveStaleTemporaries(output.parent_path(), [&](const std::string& name) {
      return name.rfind(study_tmp, 0) == 0;
    });
    if (!a.figures_dir.empty())
      stale += io::RemoveStaleTemporaries(a.figures_dir, report::IsFigureTemporary);
    if (stale > 0)
      std::cerr << "hoofimpact: removed " << stale << " temporary file(s) a killed run left\n";
  }

  const bool tty = ::isatty(STDERR_FILENO) != 0;
  const std::size_t n = study.trial_dirs.size();
  const auto start = std::chrono::steady_clock::now();
  const auto results = pipeline::AnalyzeStudy(study, a.options, jobs, [&](std::size_t done) {
    if (tty) std::cerr << "\r  analysing: " << done << "/" << n << " trials" << std::flush;
  });
  if (tty) std::cerr << "\n";
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  studyfile::WriteStudyFile(a.output, studyfile::StudyInfo::Of(study, a.options, a.command_line),
                            results);
  if (!a.csv.empty()) studyfile::WriteResultsCsv(a.csv, results);
  if (!a.impacts_csv.empty()) studyfile::WriteImpactsCsv(a.impacts_csv, results);
  if (!a.tracks_csv.empty()) studyfile::WriteTracksCsv(a.tracks_csv, results);
  std::vector<std::string> figures;
  if (!a.figures_dir.empty()) {
    for (const auto& r : results)
      for (auto& f : report::WriteTrialFigures(r, a.options, a.figures_dir, /*always=*/false,
                                               /*displacement=*/a.figures_all))
        figures.push_back(std::move(f));
    // The study figures come from the file just written, as `hoofimpact figures` draws them.
    for (const auto& f :
         report::WriteStudyFigures(studyfile::ReadStudyResults(a.output), a.figures_dir))
      figures.push_back(f.string());
    std::cerr << "Figures: " << figures.size() << " file(s) in " << a.figures_dir << "\n";
  }

  std::size_t ok = 0;
  for (const auto& r : results) ok += r.success ? 1 : 0;
  state.exit_code = ok == results.size() ? kExitOk : ok == 0 ? kExitFailure : kExitPartial;
  if (a.json) {
    nlohmann::json trials = nlohmann::json::array();
    std::vector<JsonError> errors;
    for (const auto& r : results) {
      trials.push_back(TrialJson(r));
      if (!r.success) errors.push_back({r.error, "", r.spec.dir.string(), r.spec.id, ""});
    }
    const nlohmann::json out = {{"study_dir", a.study_dir},
                                {"study_h5", a.output},
                                {"results_csv", a.csv},
                                {"impacts_csv", a.impacts_csv},
                                {"tracks_csv", a.tracks_csv},
                                {"figures", figures},
                                {"trials_total", results.size()},
                                {"measured", ok},
                                {"failed", results.size() - ok},
                                {"jobs", jobs},
                                {"seconds", seconds},
                                {"trials", trials}};
    PrintEnvelope("analyze", state.exit_code, out, errors, study.warnings);
    std::cerr << Summary(results, a.output, seconds);
  } else {
    std::cout << Summary(results, a.output, seconds);
  }
}

}  // namespace

void RegisterAnalyze(CLI::App& app, RunState& state) {
  auto args = std::make_shared<AnalyzeArgs>();
  CLI::App* cmd = app.add_subcommand(
      "analyze",
      "Measure every trial of a study folder in parallel and write one HDF5 study file "
      "(docs/hdf5-schema.md); a failed trial is recorded with its reason");
  cmd->add_option("study_dir", args->study_dir, "Study folder with study.json (docs/format.md)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("-o,--output", args->output,
                  "Output file: the HDF5 study file to write (atomically)")
      ->required();
  AddJsonFlag(cmd, args->json);
  cmd->add_option("--results-csv", args->csv,
                  "Also write the per-trial results as CSV (the columns of /results)");
  // --csv, its earlier name (an output here, an input of `stats`): still works, not shown.
  cmd->add_option("--csv", args->csv, "Deprecated: --results-csv")->group("");
  cmd->add_option("--impacts-csv", args->impacts_csv,
                  "Also write the per-impact results as CSV (the columns of /impacts)");
  cmd->add_option("--tracks-csv", args->tracks_csv,
                  "Also write every trial's marker tracks and poses as one long CSV");
  cmd->add_option("--figures", args->figures_dir,
                  "Write figures here (PNG and SVG): the study figures e_by_angle, e_by_speed, "
                  "mu_eff_by_angle, mu_eff_by_speed, and <id>_out_of_plane for every trial "
                  "flagged for out-of-plane rotation");
  cmd->add_flag("--figures-all", args->figures_all,
                "With --figures, also draw every trial's <id>_displacement (the paper's Figure 3)")
      ->needs("--figures");
  cmd->add_option("--jobs", args->jobs, "Trials analysed in parallel (0 = all cores)")
      ->capture_default_str();
  AddAnalysisOptions(cmd, args->options, args->method);
  cmd->callback([args, &state] {
    args->command_line = "hoofimpact analyze " + args->study_dir + " -o " + args->output +
                         " --method " + args->method + " --fit-frames " +
                         std::to_string(args->options.kinematics.fit_frames) +
                         (args->options.scale_from_markers ? " --scale-from-markers" : "");
    Run(*args, state);
  });
}

}  // namespace hoof::cli
