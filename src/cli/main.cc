// hoofimpact: one program for the whole study. See README.md and docs/cli.md.
#include <exception>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>
#include <opencv2/core/utils/logger.hpp>

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/json_output.h"
#include "io/interrupt.h"

int main(int argc, char** argv) {
  // First, before any thread starts: Ctrl-C removes unfinished outputs and ends with 130.
  hoof::io::HandleInterrupts();
  // OpenCV's own log (backend warnings, assertion texts) never reaches the user: every failure
  // is reported by hoofimpact, naming the file and frame.
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
  CLI::App app{
      "hoofimpact: high-speed video of hoof-wall impacts -> restitution, friction and a "
      "two-phase contact model held against the measurements."};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("hoofimpact ") + hoof::cli::kVersion);
  hoof::cli::RunState state;
  for (int i = 0; i < argc; ++i) {  // the command line as typed, for provenance
    std::string word = i == 0 ? std::string("hoofimpact") : std::string(argv[i]);
    if (word.empty() ||
        word.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                               "0123456789_-+=.,/:@%") != std::string::npos) {
      std::string quoted = "'";
      for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
      word = quoted + "'";
    }
    state.command_line += (i ? " " : "") + word;
  }
  hoof::cli::RegisterSimulate(app, state);
  hoof::cli::RegisterFit(app, state);
  hoof::cli::RegisterStats(app, state);
  hoof::cli::RegisterSynth(app, state);
  hoof::cli::RegisterTrack(app, state);
  hoof::cli::RegisterInit(app, state);
  hoof::cli::RegisterRun(app, state);
  hoof::cli::RegisterAnalyze(app, state);
  hoof::cli::RegisterScore(app, state);
  hoof::cli::RegisterFigures(app, state);
  hoof::cli::RegisterReport(app, state);
  hoof::cli::RegisterOverlay(app, state);
  hoof::cli::RegisterDiscover(app, state);
  hoof::cli::RequireFiniteNumbers(app);  // NaN, inf and 1e999 are command-line errors everywhere
  // With --json, a failure is an envelope on stdout too (success false, the error in it), as
  // the command's own failures are; the message still goes to stderr for a person.
  const std::string json_command = hoof::cli::JsonCommandOf(argc, argv, app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    if (code == 0) return 0;  // --help, --version
    if (!json_command.empty())
      hoof::cli::PrintEnvelope(json_command, hoof::cli::kExitUsage, nullptr,
                               {hoof::cli::ErrorFromMessage(e.what())});
    return hoof::cli::kExitUsage;
  } catch (const std::exception& e) {
    hoof::io::YieldToInterrupt();  // a failure Ctrl-C caused ends as the interrupt does
    std::cerr << "hoofimpact: error: " << e.what() << "\n";
    if (!json_command.empty())
      hoof::cli::PrintEnvelope(json_command, hoof::cli::kExitFailure, nullptr,
                               {hoof::cli::ErrorFromMessage(e.what())});
    return hoof::cli::kExitFailure;
  }
  if (state.exit_code != 0) hoof::io::YieldToInterrupt();
  return state.exit_code;
}
