// hoofimpact report: the study file as one self-contained HTML page (src/report/html_report.h).
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/json_output.h"
#include "report/html_report.h"

namespace hoof::cli {

void RegisterReport(CLI::App& app, RunState& state) {
  struct Args {
    std::string study_file;
    std::string output_dir = "hoofimpact-report";
    std::string study_dir;
    report::HtmlReportOptions options;
    bool json = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "report",
      "One self-contained HTML page (DIR/report.html, no network needed) of a study "
      "file written by `run`: summary and how it was made, contact model, statistics, figures, "
      "trials and a frame-by-frame replay with the simulation and the magnified residuals drawn "
      "over the frames. A replay whose frames cannot be found is named, with the folders looked "
      "at, in the page and on stderr; it does not fail the report (exit 0)");
  cmd->add_option("study_h5", args->study_file, "HDF5 study file written by `run`")->required();
  cmd->add_option("-o,--output", args->output_dir,
                  "Output folder for report.html (created when missing)")
      ->capture_default_str();
  cmd->add_option("--replay-trials", args->options.replay_trials,
                  "Trials with a replay (one per surface first; 0 = none; 0..50)")
      ->check(InRange(0, 50))
      ->capture_default_str();
  cmd->add_option("--replay-frames", args->options.frames_per_replay,
                  "Frames per replay, centred on the impact (2..400)")
      ->check(InRange(2, 400))
      ->capture_default_str();
  cmd->add_option("--residual-scale", args->options.residual_scale,
                  "Magnification F of the replay's residual arrows, drawn from each measured "
                  "marker to measured + F (simulated - measured); a whole number 1..1000, stated "
                  "in the page")
      ->capture_default_str();
  cmd->add_option("--study-dir", args->study_dir,
                  "The study folder's place when it has moved since `run`: a trial folder "
                  "missing at its recorded path is looked for here, at the same place relative "
                  "to the study folder");
  AddJsonFlag(cmd, args->json);
  cmd->callback([cmd, args, &state] {
    args->options.study_dir = args->study_dir;
    args->options.command_line = state.command_line;
    ValidateOptions(cmd, [&] { args->options.Validate(); });
    if (!args->study_dir.empty() && !std::filesystem::is_directory(args->study_dir))
      throw CLI::ValidationError("--study-dir", args->study_dir + ": no such folder");
    const auto summary = report::WriteHtmlReport(
        args->study_file, std::filesystem::path(args->output_dir) / "report.html", args->options);
    state.exit_code = kExitOk;
    if (args->json) {
      PrintEnvelope("report", state.exit_code, ReportJson(summary));
      if (!summary.notes.empty()) std::cerr << summary.notes;
      return;
    }
    std::cout << "report: " << summary.output.string() << " (" << summary.bytes / 1024 << " KiB; "
              << summary.trials << " trials, " << summary.figures << " figures, " << summary.replays
              << " replays)\n";
    // What the page left out, e.g. a replay whose frames were not found: never silent, but not
    // a failure of the report.
    if (!summary.notes.empty()) std::cerr << summary.notes;
    state.exit_code = kExitOk;
  });
}

}  // namespace hoof::cli
