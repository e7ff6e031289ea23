// hoofimpact discover: where the model and the measurements of a study file disagree, which
// missing effect explains it, and how much adding it shrinks the gap on held-out trials
// (docs/discovery.md). Only arguments, reading, storing and printing live here; the workflow is
// in hoof::discovery, its text and JSON in discovery/discovery_text.h and discovery_json.h, its
// tables in discovery/discovery_tables.h, its figures in hoof::report.
#include <unistd.h>

#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/json_output.h"
#include "discovery/discovery.h"
#include "discovery/discovery_json.h"
#include "discovery/discovery_tables.h"
#include "discovery/discovery_text.h"
#include "io/atomic_file.h"
#include "io/interrupt.h"
#include "report/discovery_figures.h"
#include "report/html_report.h"
#include "study/discovery_step.h"
#include "studyfile/study_file.h"

namespace hoof::cli {
namespace {

/// Progress lines ("  discover: round 1: ...") on stderr, only when it is a terminal, as every
/// command shows its progress: a log or a pipe gets the results and the errors, not the progress.
std::function<void(const std::string&)> ProgressLines(const std::string& prefix) {
  if (::isatty(STDERR_FILENO) == 0) return {};
  return [prefix](const std::string& line) {
    std::cerr << "  " << prefix << ": " << line << std::endl;
  };
}

namespace fs = std::filesystem;
using nlohmann::json;

// ---- JSON ---------------------------------------------------------------------------------

json ResultJson(const discovery::DiscoveryResult& r, const std::string& study_h5,
                const DiscoverSettings& s, const std::vector<std::string>& figures) {
  json j = discovery::DiscoveryJson(r);
  j["study_h5"] = study_h5;
  j["options"] = {{"alpha", s.alpha},
                  {"folds", s.folds},
                  {"rounds", s.rounds},
                  {"jobs", s.jobs},
                  {"candidates", s.candidates},
                  {"per_surface", s.per_surface},
                  {"measurement_floor", s.measurement_floor}};
  j["figures"] = figures;
  return j;
}

// ---- the command --------------------------------------------------------------------------

struct DiscoverArgs {
  std::string study_h5;
  std::string output;  ///< the study file written: a copy of study_h5 with /discovery
  DiscoverSettings settings;
  std::string report;
  std::vector<std::string> plans;  ///< --plan KEY=SIZE
  int plan_draws = 0;              ///< --plan-draws: the plans' parametric bootstrap
};

/// `--plan KEY=SIZE` as key and size; a CLI::ValidationError naming the option otherwise.
std::pair<std::string, double> ParsePlan(const std::string& text) {
  const auto eq = text.find('=');
  double size = 0.0;
  std::size_t used = 0;
  try {
    if (eq != std::string::npos) size = std::stod(text.substr(eq + 1), &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (eq == std::string::npos || eq == 0 || used == 0 || used != text.size() - eq - 1)
    throw CLI::ValidationError("--plan",
                               "expected KEY=SIZE (e.g. hunt_crossley=2e7), got '" + text + "'");
  return {text.substr(0, eq), size};
}

/// `--plan KEY=SIZE`: how many trials, and of which conditions, would detect the effect.
void PrintPlans(const DiscoverArgs& a, const std::vector<pipeline::TrialAnalysis>& trials) {
  discovery::DiscoveryOptions options;
  options.alpha = a.settings.alpha;
  options.jobs = a.settings.jobs;
  options.candidates = a.settings.candidates;
  options.measurement_floor = a.settings.measurement_floor;
  json all = json::array();
  for (const auto& text : a.plans) {
    const auto [key, size] = ParsePlan(text);
    discovery::Plan p;
    try {
      p = discovery::PlanDetection(trials, key, size, options, a.plan_draws, ProgressLines("plan"));
    } catch (const std::invalid_argument& e) {
      throw CLI::ValidationError("--plan", e.what());
    }
    if (!p.success) throw std::runtime_error(a.study_h5 + ": no plan: " + p.message);
    all.push_back(discovery::PlanJson(p));
    if (!a.settings.json) discovery::WritePlanText(std::cout, p, a.study_h5);
  }
  if (a.settings.json)
    PrintEnvelope("discover", kExitOk, {{"study_h5", a.study_h5}, {"plans", all}});
}

/// `S.h5` -> `S-discovery.h5` beside it.
fs::path DefaultDiscoveryOutput(const std::string& study_h5) {
  const fs::path in(study_h5);
  return in.parent_path() / (in.stem().string() + "-discovery" +
                             (in.has_extension() ? in.extension().string() : ".h5"));
}

/// The study's trials; errors name the file.
std::vector<pipeline::TrialAnalysis> ReadTrials(const std::string& h5) {
  if (!fs::is_regular_file(h5)) throw std::runtime_error(h5 + ": no such study file");
  try {
    return studyfile::ReadTrialAnalyses(h5);
  } catch (const std::exception& e) {
    const std::string what = e.what();
    if (what.find(h5) != std::string::npos) throw;
    throw std::runtime_error(h5 + ": " + what);
  }
}

void Discover(const DiscoverArgs& a, RunState& state) {
  CheckDiscoverSettings(a.settings);
  for (const auto& text : a.plans) ParsePlan(text);  // a bad one is a command-line error first
  // The input is never modified: the result goes into a copy, written beside the output as a
  // temporary and renamed over it only when the workflow ran.
  const fs::path output =
      a.output.empty() ? DefaultDiscoveryOutput(a.study_h5) : fs::path(a.output);
  std::error_code ec;
  if (fs::exists(output, ec) && fs::equivalent(output, a.study_h5, ec))
    throw CLI::ValidationError("-o", output.string() +
                                         " is the input study file; discover never modifies its "
                                         "input: name another file");
  if (fs::is_directory(output, ec))
    throw CLI::ValidationError("-o",
                               output.string() + " is a folder; name the study file to write");
  const auto trials = ReadTrials(a.study_h5);
  if (!a.plans.empty()) {
    PrintPlans(a, trials);
    state.exit_code = kExitOk;
    return;
  }
  if (!output.parent_path().empty()) fs::create_directories(output.parent_path());
  const std::string own = output.filename().string() + ".tmp-";
  if (const int stale = io::RemoveStaleTemporaries(
          fs::absolute(output).parent_path(),
          [&](const std::string& name) { return name.rfind(own, 0) == 0; });
      stale > 0)
    std::cerr << "hoofimpact: removed " << stale << " temporary file(s) a killed run left\n";
  const fs::path temporary = io::TemporaryPathFor(output);
  bool ok = false;
  try {
    {
      const io::CreatingTemporary creating;
      fs::copy_file(a.study_h5, temporary);
    }
    DiscoverSettings settings = a.settings;
    settings.shown_as = output.string();
    if (settings.figures_dir.empty())
      settings.figures_dir = (output.parent_path() / "figures").string();
    ok = RunStudyDiscovery(temporary.string(), trials, settings);
    if (ok) io::CommitTemporary(temporary, output);
  } catch (...) {
    fs::remove(temporary, ec);
    throw;
  }
  if (!ok) {
    fs::remove(temporary, ec);
    std::cerr << "hoofimpact: " << output.string() << " not written\n";
    state.exit_code = kExitFailure;
    return;
  }
  // The report only when asked for, and only of a complete result.
  if (!a.report.empty()) {
    const auto page = report::WriteHtmlReport(output.string(), a.report);
    (a.settings.json ? std::cerr : std::cout)
        << "report: " << page.output.string() << " (" << page.bytes / 1024 << " KiB, "
        << page.figures << " figures)\n";
    if (!page.notes.empty()) std::cerr << page.notes;
  }
  state.exit_code = kExitOk;
}

}  // namespace

void CheckDiscoverSettings(const DiscoverSettings& s) {
  if (!(s.alpha > 0.0 && s.alpha < 0.5))
    throw CLI::ValidationError("--alpha", "must be in (0, 0.5), got " + discovery::Num(s.alpha));
  if (s.folds < 2)
    throw CLI::ValidationError("--folds", "must be at least 2, got " + std::to_string(s.folds));
  if (s.rounds < 1)
    throw CLI::ValidationError("--rounds", "must be at least 1, got " + std::to_string(s.rounds));
  if (s.jobs < 0)
    throw CLI::ValidationError("--jobs",
                               "must be 0 (all cores) or more, got " + std::to_string(s.jobs));
  if (!(s.measurement_floor >= 0.0 && s.measurement_floor < 0.1))
    throw CLI::ValidationError("--measurement-floor",
                               "must be in [0, 0.1), got " + discovery::Num(s.measurement_floor));
}

discovery::DiscoveryOptions DiscoveryOptionsOf(const DiscoverSettings& s) {
  discovery::DiscoveryOptions options;
  options.alpha = s.alpha;
  options.folds = s.folds;
  options.max_rounds = s.rounds;
  options.jobs = s.jobs;
  options.candidates = s.candidates;
  options.per_surface = s.per_surface;
  options.measurement_floor = s.measurement_floor;
  return options;
}

bool PrintDiscoveryStep(const study::DiscoveryStep& step, const DiscoverSettings& s) {
  for (const auto& w : step.warnings) std::cerr << "hoofimpact: warning: " << w << "\n";
  const discovery::DiscoveryResult& result = step.result;
  std::vector<std::string> figures;
  for (const auto& f : step.figures) figures.push_back(f.string());
  const std::string& shown = s.shown_as;
  if (s.json) {
    std::vector<JsonError> errors;
    if (!result.success)
      errors.push_back(
          {"the discovery workflow could not run: " + result.message, "", shown, "", ""});
    PrintEnvelope("discover", result.success ? kExitOk : kExitFailure,
                  ResultJson(result, shown, s, figures), errors, step.warnings);
  } else {
    discovery::WriteDiscoveryText(std::cout, result, shown);
    std::cout << "\nStored in " << shown << " under /discovery; " << figures.size()
              << " figure file(s)" << (figures.empty() ? "" : " in " + step.figures_dir.string())
              << "\n";
  }
  if (!result.success)
    std::cerr << "hoofimpact: error: " << shown
              << ": the discovery workflow could not run: " << result.message << "\n";
  return result.success;
}

bool RunStudyDiscovery(const std::string& study_h5,
                       const std::vector<pipeline::TrialAnalysis>& trials,
                       const DiscoverSettings& s) {
  study::DiscoveryStep step;
  try {
    step = study::DiscoverAndStore(study_h5, trials, DiscoveryOptionsOf(s), s.figures_dir,
                                   ProgressLines("discover"));
  } catch (const std::invalid_argument& e) {  // options out of range, an unknown candidate key
    throw CLI::ValidationError("discover", e.what());
  }
  DiscoverSettings shown = s;
  if (shown.shown_as.empty()) shown.shown_as = study_h5;
  return PrintDiscoveryStep(step, shown);
}

void RegisterDiscover(CLI::App& app, RunState& state) {
  auto args = std::make_shared<DiscoverArgs>();
  CLI::App* cmd = app.add_subcommand(
      "discover",
      "Find where the model and the measurements of a study file disagree, name the missing "
      "effect with evidence, add it and show the gap shrink on held-out trials "
      "(docs/discovery.md); written to a copy of the study file under /discovery, with figures");
  cmd->add_option("study_h5", args->study_h5, "Study file written by `hoofimpact run` or `analyze`")
      ->required();
  DiscoverSettings& s = args->settings;
  cmd->add_option("--alpha", s.alpha,
                  "Family-wise level: of the structure tests (Holm) and of naming a candidate "
                  "(min-P over the candidates and their forms); in (0, 0.5)")
      ->capture_default_str();
  cmd->add_option("--folds", s.folds, "Leave-trials-out cross-validation folds (>= 2)")
      ->capture_default_str();
  cmd->add_option("--rounds", s.rounds, "Effects added at most (>= 1)")->capture_default_str();
  cmd->add_option("--jobs", s.jobs, "Threads (0 = all cores)")->capture_default_str();
  cmd->add_option("--candidates", s.candidates,
                  "Candidate effects to try, as library keys separated by commas (default: all)")
      ->delimiter(',');
  cmd->add_option("--measurement-floor", s.measurement_floor,
                  "Lower bound of the measurement's systematic error per velocity component, as "
                  "a fraction of the impact speed (the noise model estimates it above this); in "
                  "[0, 0.1)")
      ->capture_default_str();
  cmd->add_flag_callback(
      "--shared-only", [args] { args->settings.per_surface = false; },
      "Give every contact effect one value shared by all surfaces (default: a per-surface "
      "form too, chosen by a likelihood-ratio test)");
  cmd->add_option("-o,--output", args->output,
                  "Output file: the study file to write, a copy of STUDY_H5 with the result under "
                  "/discovery (default: "
                  "STUDY-discovery.h5 beside it); the input is never modified");
  cmd->add_option("--figures", s.figures_dir,
                  "Folder for the figures (default: figures/ beside the output file)");
  cmd->add_option("--report", args->report,
                  "Also write the HTML report of the output file to this file (only when the "
                  "workflow ran)");
  AddJsonFlag(cmd, s.json);
  auto* plan = cmd->add_option(
      "--plan", args->plans,
      "KEY=SIZE: instead of the workflow, how many trials of this design would detect the "
      "effect at that size (library unit) with 80 % power, and which conditions tell most "
      "(repeatable)");
  cmd->add_option("--plan-draws", args->plan_draws,
                  "With --plan: also simulate this many studies of these trials from the fitted "
                  "baseline with the effect at SIZE (each trial's e and mu drawn from the noise "
                  "model's scatter) and count how often the candidate is detected: the power by "
                  "parametric bootstrap (slow: a baseline and a candidate fit per study)")
      ->check(InRange(0, 100000))
      ->needs(plan);
  cmd->callback([args, &state] { Discover(*args, state); });
}

}  // namespace hoof::cli
