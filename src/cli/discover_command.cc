// hoofimpact discover: where the model and the measurements of a study file disagree, which
// missing effect explains it, and how much adding it shrinks the gap on held-out trials
// (docs/discovery.md). Only arguments, reading, storing and printing live here; the workflow is
// in hoof::discovery, its tables in discovery/discovery_tables.h, its figures in hoof::report.
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/common_options.h"
#include "discovery/discovery.h"
#include "discovery/discovery_json.h"
#include "discovery/discovery_tables.h"
#include "io/atomic_file.h"
#include "io/interrupt.h"
#include "report/discovery_figures.h"
#include "report/html_report.h"
#include "study/discovery_step.h"
#include "studyfile/study_file.h"

namespace hoof::cli {
namespace {

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

// ---- text ---------------------------------------------------------------------------------

std::string Num(double v, int precision = 4) {
  if (!std::isfinite(v)) return "-";
  std::ostringstream s;
  s << std::setprecision(precision) << v;
  return s.str();
}

std::string Estimate(double estimate, double se, const std::string& parameter,
                     const std::string& unit) {
  std::string out = parameter.empty() ? "" : parameter + " = ";
  out += Num(estimate, 3);
  if (std::isfinite(se)) out += " +- " + Num(se, 2);
  if (!unit.empty() && unit != "1") out += " " + unit;
  return out;
}

std::string Percent(double fraction) {
  return std::isfinite(fraction) ? Num(100.0 * fraction, 3) + " %" : "-";
}

/// Every value ("steel: c = 0.7 +- 0.1 N s/m^2; concrete: ..."; "all surfaces" for a shared
/// one).
std::string ValuesText(const std::vector<discovery::EffectValue>& values,
                       const std::string& parameter, const std::string& unit) {
  std::string out;
  for (const auto& v : values)
    out += (out.empty() ? "" : "; ") + (v.surface.empty() ? "all surfaces" : v.surface) + ": " +
           Estimate(v.value, v.se, parameter, unit);
  return out;
}

/// Width of a column of enum texts: the longest text, and two spaces.
template <typename Values>
int TextWidth(const Values& values) {
  std::size_t width = 0;
  for (auto v : values) width = std::max(width, std::string(discovery::ToString(v)).size());
  return static_cast<int>(width) + 2;
}

/// Whether a candidate gets a line saying why it was or was not added: it is significant, or
/// its likelihood ratio was and something else decided.
bool SaysWhy(const discovery::CandidateResult& c) {
  using discovery::CandidateOutcome;
  return c.significant || c.outcome == CandidateOutcome::kAdded ||
         c.outcome == CandidateOutcome::kIndistinguishable ||
         c.outcome == CandidateOutcome::kWeakerThanAdded ||
         c.outcome == CandidateOutcome::kWorseHeldOut ||
         c.outcome == CandidateOutcome::kBelowResolution ||
         c.outcome == CandidateOutcome::kAtSmallestValue ||
         c.outcome == CandidateOutcome::kRestsOnOneTrial;
}

/// The held-out score the candidate is judged by, and the current model's.
std::string HeldOutColumn(const discovery::CandidateResult& c) {
  const auto [now, current] = discovery::HeldOutScores(c);
  return now + " (" + current + ")";
}

void PrintText(std::ostream& os, const discovery::DiscoveryResult& r, const std::string& h5) {
  if (!r.success) {
    os << "Discovery on " << h5 << ": could not run (" << r.trials_used << " trial(s) used, "
       << r.trials_skipped << " skipped): " << r.message << "\n";
    return;
  }
  os << "Discovery on " << h5 << ": " << r.trials_used << " trial(s) used, " << r.trials_skipped
     << " skipped; " << r.rounds.size() << " round(s), " << r.simulations << " simulations, "
     << Num(r.seconds, 3) << " s\n\nVerdict:\n";
  std::istringstream verdict(r.verdict);
  for (std::string line; std::getline(verdict, line);)
    os << (line.empty() ? "" : "  ") << line << "\n";
  using discovery::CandidateOutcome;
  using discovery::Identifiability;
  const int outcome_width = TextWidth(discovery::AllCandidateOutcomes());
  const int identifiability_width = TextWidth(std::array{
      Identifiability::kIdentified, Identifiability::kNotTested, Identifiability::kConfounded});
  const int form_width =
      TextWidth(std::array{discovery::EffectForm::kShared, discovery::EffectForm::kPerSurface});
  for (std::size_t i = 0; i < r.rounds.size(); ++i) {
    const auto& round = r.rounds[i];
    os << "\nRound " << i + 1 << ": " << round.decision << "\n";
    if (round.candidates.empty())
      os << "  (no candidate)\n";
    else
      os << "  " << std::left << std::setw(5) << "rank" << std::setw(24) << "effect"
         << std::setw(form_width) << "form" << std::setw(30) << "estimate +- se" << std::right
         << std::setw(10) << "LR p" << std::setw(11) << "dAIC" << std::setw(11) << "dBIC"
         << "  " << std::left << std::setw(outcome_width) << "outcome"
         << std::setw(identifiability_width) << "identifiability"
         << "held-out (current)\n"
         << std::right;
    for (const auto& c : round.candidates) {
      os << "  " << std::left << std::setw(5)
         << (std::to_string(c.rank) + (c.key == round.accepted ? "*" : "")) << std::setw(24)
         << c.key;
      if (!c.fitted) {
        os << "not fitted: " << c.message << std::right << "\n";
        continue;
      }
      // A per-surface effect's estimate is the largest of its surface values.
      const std::string parameter =
          c.form == discovery::EffectForm::kPerSurface && !c.parameter.empty()
              ? "max " + c.parameter
              : c.parameter;
      os << std::setw(form_width) << discovery::ToString(c.form) << std::setw(30)
         << Estimate(c.estimate, c.se, parameter, c.unit) << std::right << std::setw(10)
         << (c.p_value > 0 ? Num(c.p_value, 3) : std::string("<1e-300")) << std::setw(11)
         << Num(c.delta_aic, 3) << std::setw(11) << Num(c.delta_bic, 3) << "  " << std::left
         << std::setw(outcome_width) << discovery::ToString(c.outcome)
         << std::setw(identifiability_width) << discovery::ToString(c.identifiability) << std::right
         << HeldOutColumn(c) << "\n";
    }
    if (!round.candidates.empty())
      os << "  held-out: " << discovery::kHeldOutDensityUnit
         << " under each model's own noise model for a contact effect; "
         << discovery::kHeldOutErrorUnit << " for an out-of-plane candidate\n";
    for (const auto& c : round.candidates) {
      if (!SaysWhy(c)) continue;
      os << "  " << c.key << " (" << discovery::ToString(c.outcome)
         << "): " << (c.reason.empty() ? "-" : c.reason);
      if (c.form == discovery::EffectForm::kPerSurface && !c.values.empty())
        os << " [per surface: " << ValuesText(c.values, c.parameter, c.unit) << "]";
      os << "\n";
    }
    int significant = 0;
    for (const auto& t : round.tests)
      if (t.significant) {
        if (significant++ == 0) os << "  significant structure (Holm):\n";
        os << "    " << t.quantity << ", " << t.scope << ", " << t.covariate << ", " << t.test
           << ": " << Num(t.statistic) << ", p " << Num(t.p, 3) << ", Holm p " << Num(t.p_holm, 3)
           << (t.description.empty() ? "" : " (" + t.description + ")") << "\n";
      }
    if (significant == 0)
      os << "  no significant structure in the residuals (" << round.tests.size()
         << (round.tests.size() == 1 ? " test" : " tests") << ")\n";
    if (!round.accepted.empty())
      os << "  held-out gap " << Percent(round.gap_before) << " -> " << Percent(round.gap_after)
         << " (" << discovery::GapChangeText(round.gap_shrink) << ") with " << round.accepted
         << "\n";
  }
  os << "\nFindings:\n";
  if (r.findings.empty()) os << "  none\n";
  for (const auto& f : r.findings) {
    os << "  " << std::left
       << std::setw(TextWidth(std::array{discovery::FindingStatus::kNamed,
                                         discovery::FindingStatus::kTentative,
                                         discovery::FindingStatus::kIndistinguishable}))
       << discovery::ToString(f.status) << std::right << f.key;
    if (f.form == discovery::EffectForm::kPerSurface) {
      std::string on;
      for (const auto& surface : f.surfaces) on += (on.empty() ? "" : ", ") + surface;
      os << " (" << discovery::ToString(f.form) << (on.empty() ? "" : ", found on " + on) << "): "
         << (f.values.empty() ? Estimate(f.estimate, f.se, f.parameter, f.unit)
                              : ValuesText(f.values, f.parameter, f.unit));
    } else {
      os << ": " << Estimate(f.estimate, f.se, f.parameter, f.unit);
    }
    if (std::isfinite(f.gap_shrink))
      os << "; held-out gap " << discovery::GapChangeText(f.gap_shrink);
    if (!f.partner.empty()) os << "; cannot be told from " << f.partner;
    if (!f.separating_measurement.empty()) os << "; to separate: " << f.separating_measurement;
    os << "\n";
  }
  os << "\nRemaining significant disagreement: " << (r.remaining.empty() ? "none" : "") << "\n";
  for (const auto& t : r.remaining)
    os << "  " << t.quantity << ", " << t.scope << ", " << t.covariate << ", " << t.test
       << ": Holm p " << Num(t.p_holm, 3)
       << (t.description.empty() ? "" : " (" + t.description + ")") << "\n";
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
      p = discovery::PlanDetection(
          trials, key, size, options, a.plan_draws,
          [](const std::string& line) { std::cerr << "  plan: " << line << std::endl; });
    } catch (const std::invalid_argument& e) {
      throw CLI::ValidationError("--plan", e.what());
    }
    if (!p.success) throw std::runtime_error(a.study_h5 + ": no plan: " + p.message);
    json conditions = json::array();
    for (const auto& c : p.conditions)
      conditions.push_back({{"surface", c.surface},
                            {"angle_deg", JsonNumber(c.angle_deg)},
                            {"speed_low_m_s", JsonNumber(c.speed_low_m_s)},
                            {"speed_high_m_s", JsonNumber(c.speed_high_m_s)},
                            {"trials", c.trials},
                            {"information_per_trial", JsonNumber(c.information_per_trial)},
                            {"share", JsonNumber(c.share)}});
    all.push_back({{"key", p.key},
                   {"size", JsonNumber(p.size)},
                   {"unit", p.unit},
                   {"trials", p.trials},
                   {"level", JsonNumber(p.level)},
                   {"detection_limit", JsonNumber(p.detection_limit)},
                   {"power", JsonNumber(p.power)},
                   {"trials_needed", JsonNumber(p.trials_needed)},
                   {"bootstrap",
                    {{"draws", p.bootstrap_draws},
                     {"detected", p.bootstrap_detected},
                     {"likelihood_ratio_significant", p.bootstrap_lr_significant},
                     {"power", JsonNumber(p.bootstrap_power)},
                     {"power_low", JsonNumber(p.bootstrap_low)},
                     {"power_high", JsonNumber(p.bootstrap_high)}}},
                   {"conditions", conditions}});
    if (a.settings.json) continue;
    const std::string unit = p.unit == "1" ? "" : " " + p.unit;
    std::cout << "Plan for " << p.name << " at " << p.parameter << " = " << Num(p.size, 3) << unit
              << " (" << a.study_h5 << ", " << p.trials << " trials, naming level "
              << Num(p.level, 2) << "):\n"
              << "  this study detects " << p.parameter << " >= " << Num(p.detection_limit, 2)
              << unit << " with 80 % power; its power at " << Num(p.size, 3) << unit << " is "
              << Percent(p.power) << "\n"
              << "  80 % power at " << Num(p.size, 3) << unit << " needs about "
              << Num(p.trials_needed, 6)
              << " trials of this design (its conditions in the same proportions)\n";
    if (p.bootstrap_draws > 0)
      std::cout << "  parametric bootstrap: detected in " << p.bootstrap_detected << " of "
                << p.bootstrap_draws << " studies simulated from the baseline with " << p.parameter
                << " = " << Num(p.size, 3) << unit << ": power " << Percent(p.bootstrap_power)
                << " (Wilson 95 % " << Percent(p.bootstrap_low) << " to "
                << Percent(p.bootstrap_high) << "); the likelihood ratio alone below the naming "
                << "level in " << p.bootstrap_lr_significant << " of " << p.bootstrap_draws << "\n";
    std::cout << "  information per trial, most informative condition first (zeta and mu profiled "
                 "out):\n";
    for (const auto& c : p.conditions)
      std::cout << "    " << std::left << std::setw(10) << c.surface << std::right << std::setw(5)
                << Num(c.angle_deg, 3) << " deg  " << Num(c.speed_low_m_s, 3) << "-"
                << Num(c.speed_high_m_s, 3) << " m/s  " << std::setw(3) << c.trials << " trials  "
                << std::setw(10) << Num(c.information_per_trial, 3) << " per trial  ("
                << Percent(c.share) << " of the study's)\n";
    std::cout << "  (the limit and the power from the study's expected data: the effect simulated "
                 "without scatter or error, the baseline's zeta and mu refitted to it, under its "
                 "noise model; the information per trial from the tangent plane; "
                 "docs/discovery.md, \"Detection limits and plans\")\n";
  }
  if (a.settings.json) std::cout << all.dump(2) << "\n";
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
    throw CLI::ValidationError("--alpha", "must be in (0, 0.5), got " + Num(s.alpha));
  if (s.folds < 2)
    throw CLI::ValidationError("--folds", "must be at least 2, got " + std::to_string(s.folds));
  if (s.rounds < 1)
    throw CLI::ValidationError("--rounds", "must be at least 1, got " + std::to_string(s.rounds));
  if (s.jobs < 0)
    throw CLI::ValidationError("--jobs",
                               "must be 0 (all cores) or more, got " + std::to_string(s.jobs));
  if (!(s.measurement_floor >= 0.0 && s.measurement_floor < 0.1))
    throw CLI::ValidationError("--measurement-floor",
                               "must be in [0, 0.1), got " + Num(s.measurement_floor));
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
    std::cout << ResultJson(result, shown, s, figures).dump(2) << "\n";
  } else {
    PrintText(std::cout, result, shown);
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
    step = study::DiscoverAndStore(
        study_h5, trials, DiscoveryOptionsOf(s), s.figures_dir,
        [](const std::string& line) { std::cerr << "  discover: " << line << std::endl; });
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
  cmd->add_option(
      "-o,--output", args->output,
      "Study file to write: a copy of STUDY_H5 with the result under /discovery (default: "
      "STUDY-discovery.h5 beside it); the input is never modified");
  cmd->add_option("--figures", s.figures_dir,
                  "Folder for the figures (default: figures/ beside the output file)");
  cmd->add_option("--report", args->report,
                  "Also write the HTML report of the output file to this file (only when the "
                  "workflow ran)");
  cmd->add_flag("--json", s.json, "Print the whole result as one JSON object");
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
      ->check(CLI::Range(0, 100000))
      ->needs(plan);
  cmd->callback([args, &state] { Discover(*args, state); });
}

}  // namespace hoof::cli
