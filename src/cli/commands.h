#pragma once
/// @file
/// Each `hoofimpact` subcommand lives in its own file and registers itself on the app here.
/// Subcommands only parse arguments, call the libraries and print; they hold no algorithms.

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace hoof::pipeline {
struct TrialAnalysis;
}  // namespace hoof::pipeline
namespace hoof::study {
struct StudyStatistics;
struct DiscoveryStep;
}  // namespace hoof::study
namespace hoof::discovery {
struct DiscoveryOptions;
}  // namespace hoof::discovery

namespace hoof::cli {

/// Exit codes shared by all subcommands.
enum ExitCode : int {
  kExitOk = 0,        ///< Everything succeeded.
  kExitFailure = 1,   ///< Bad input data or a failed computation; the message says which.
  kExitUsage = 2,     ///< Bad command line.
  kExitPartial = 3,   ///< A study ran, but some trials failed (each recorded with a reason).
  kExitNoImpact = 4,  ///< `track`: the clip holds no impact; the motion is still reported.
};

/// Holds the exit code a subcommand's callback sets.
struct RunState {
  int exit_code = kExitOk;
  /// The command as typed (argv, each word shell-quoted where it needs it), for the record a
  /// study file and a report keep of how they were made.
  std::string command_line;
};

void RegisterSimulate(CLI::App& app, RunState& state);
void RegisterFit(CLI::App& app, RunState& state);
void RegisterStats(CLI::App& app, RunState& state);
void RegisterSynth(CLI::App& app, RunState& state);
/// Adds `synth footage` (everyday footage, synth_footage_command.cc) under `synth`; returns it.
CLI::App* RegisterSynthFootage(CLI::App* synth, RunState& state);
void RegisterTrack(CLI::App& app, RunState& state);
void RegisterInit(CLI::App& app, RunState& state);
void RegisterRun(CLI::App& app, RunState& state);
void RegisterAnalyze(CLI::App& app, RunState& state);
void RegisterScore(CLI::App& app, RunState& state);
void RegisterFigures(CLI::App& app, RunState& state);
void RegisterReport(CLI::App& app, RunState& state);
void RegisterOverlay(CLI::App& app, RunState& state);
void RegisterDiscover(CLI::App& app, RunState& state);

/// Prints the study statistics as `stats STUDY_H5` does (`run` prints them too), and where the
/// tables went.
void PrintStudyStatistics(const study::StudyStatistics& statistics, const std::string& out_csv);

/// Settings of the discovery step (`discover`, and `run --discover`).
struct DiscoverSettings {
  double alpha = 0.01;                  ///< family-wise level (discovery::DiscoveryOptions::alpha)
  int folds = 3;                        ///< leave-trials-out folds
  int rounds = 3;                       ///< effects added at most
  int jobs = 0;                         ///< threads (0 = all cores)
  std::vector<std::string> candidates;  ///< library keys to try; empty = all
  /// Let a contact effect take its own value on each surface (`--shared-only` turns it off;
  /// discovery::DiscoveryOptions::per_surface).
  bool per_surface = true;
  /// Lower bound of the measurement's systematic error per velocity component, fraction of the
  /// impact speed (discovery::DiscoveryOptions::measurement_floor); in [0, 0.1).
  double measurement_floor = 1e-3;
  std::string figures_dir;  ///< where the figures go; empty = figures/ beside the study file
  /// The study file's name in messages, when the file discovery writes to is a temporary that
  /// will be renamed to it (`run`); empty = the file's own name.
  std::string shown_as;
  bool json = false;  ///< print one JSON object instead of the text
};

/// Throws CLI::ValidationError naming the option (--alpha, --folds, --rounds, --jobs,
/// --measurement-floor) when a setting is out of range; `run` calls it before it measures anything.
void CheckDiscoverSettings(const DiscoverSettings& settings);

/// The discovery step of `discover STUDY_H5` (and `run --discover`): runs the workflow on
/// `trials` (those of `study_h5`) with progress lines on stderr, stores the result under
/// /discovery in `study_h5`, draws its figures, and prints the verdict and a compact evidence
/// table on stdout (or the whole result as one JSON object with `settings.json`). Returns
/// true when the workflow ran; false, after saying why on stderr (naming the file), when it
/// could not (the result is stored all the same, with its reason).
bool RunStudyDiscovery(const std::string& study_h5,
                       const std::vector<pipeline::TrialAnalysis>& trials,
                       const DiscoverSettings& settings);

/// The discovery options that `settings` stand for.
discovery::DiscoveryOptions DiscoveryOptionsOf(const DiscoverSettings& settings);

/// Prints a discovery step as `discover` does (text, or JSON with `settings.json`), naming the
/// study file `settings.shown_as`, and returns whether the workflow ran (why not on stderr).
bool PrintDiscoveryStep(const study::DiscoveryStep& step, const DiscoverSettings& settings);

}  // namespace hoof::cli
