#pragma once
/// @file
/// Each `hoofimpact` subcommand lives in its own file and registers itself on the app here.
/// Subcommands only parse arguments, call the libraries and print; they hold no algorithms.

#include <string>

#include <CLI/CLI.hpp>

namespace hoof::cli {

/// Exit codes shared by all subcommands.
enum ExitCode : int {
  kExitOk = 0,           ///< Everything succeeded.
  kExitFailure = 1,      ///< Bad input data or a failed computation; the message says which.
  kExitUsage = 2,        ///< Bad command line.
  kExitPartial = 3,      ///< A study ran, but some trials failed (each recorded with a reason).
};

/// Holds the exit code a subcommand's callback sets.
struct RunState {
  int exit_code = kExitOk;
};

void RegisterSimulate(CLI::App& app, RunState& state);
void RegisterFit(CLI::App& app, RunState& state);
void RegisterStats(CLI::App& app, RunState& state);
void RegisterSynth(CLI::App& app, RunState& state);
void RegisterTrack(CLI::App& app, RunState& state);
void RegisterRun(CLI::App& app, RunState& state);
void RegisterAnalyze(CLI::App& app, RunState& state);
void RegisterScore(CLI::App& app, RunState& state);
void RegisterFigures(CLI::App& app, RunState& state);
void RegisterReport(CLI::App& app, RunState& state);
void RegisterOverlay(CLI::App& app, RunState& state);

/// The study statistics of `stats STUDY_H5` (stored under /stats, printed, and written to
/// `out_csv` when not empty); `run` uses it too.
void RunStudyStatistics(const std::string& study_h5, double alpha, const std::string& out_csv);

}  // namespace hoof::cli
