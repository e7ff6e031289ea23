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
    report::HtmlReportOptions options;
    bool json = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "report",
      "One self-contained HTML page (DIR/report.html, no network needed) of a study "
      "file written by `run`: summary, contact model, statistics, figures, trials "
      "and a frame-by-frame replay with the simulation drawn over the frames");
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
  AddJsonFlag(cmd, args->json);
  cmd->callback([args, &state] {
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
    if (!summary.notes.empty()) std::cerr << summary.notes;
    state.exit_code = kExitOk;
  });
}

}  // namespace hoof::cli
