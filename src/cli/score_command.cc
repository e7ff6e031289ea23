// hoofimpact score: measure synthetic trials and score them against their truth.json.
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/json_output.h"
#include "cli/trial_output.h"
#include "format/number_format.h"
#include "pipeline/truth_score.h"

namespace hoof::cli {

namespace {

/// The envelope: one JSON object per trial (its errors, or its score) and the summary.
void PrintScoreJson(const pipeline::StudyScore& score, int exit_code) {
  const pipeline::StudyScoreSummary& sum = score.summary;
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& t : score.trials) {
    nlohmann::json row = {{"dir", t.dir.string()}};
    if (!t.id.empty()) row.update({{"id", t.id}, {"flags", t.flags}});
    if (!t.scored()) {
      row["error"] = t.error;
    } else {
      const auto& s = t.score;
      row.update({{"marker_rms_px", s.marker_rms_px},
                  {"marker_max_px", s.marker_max_px},
                  {"marker_count", s.marker_count},
                  {"centre_rms_px", s.centre_rms_px},
                  {"centre_max_px", s.centre_max_px},
                  {"centre_count", s.centre_count},
                  {"impacts_true", s.impacts_true},
                  {"impacts_found", s.impacts_found},
                  {"impacts_matched", s.impacts_matched},
                  {"impacts_e_max_abs", JsonNumber(s.impacts_e_max_abs)},
                  {"v_before_rel", s.v_before_rel},
                  {"v_after_rel", s.v_after_rel},
                  {"w_before_abs", JsonNumber(s.w_before_abs)},
                  {"w_after_abs", JsonNumber(s.w_after_abs)},
                  {"e_abs", JsonNumber(s.e_abs)},
                  {"mu_eff_abs", JsonNumber(s.mu_eff_abs)},
                  {"impact_time_abs_s", s.impact_time_abs_s},
                  {"truth_out_of_plane", t.truth_out_of_plane}});
    }
    rows.push_back(row);
  }
  const nlohmann::json summary = {{"trials", sum.trials},
                                  {"succeeded", sum.scored},
                                  {"marker_rms_px", sum.marker_rms_px},
                                  {"marker_max_px", sum.marker_max_px},
                                  {"centre_rms_px", sum.centre_rms_px},
                                  {"centre_max_px", sum.centre_max_px},
                                  {"impacts_true", sum.impacts_true},
                                  {"impacts_matched", sum.impacts_matched},
                                  {"v_SC_max_rel", sum.v_SC_max_rel},
                                  {"w_max_abs_rad_s", JsonNumber(sum.w_max_abs_rad_s)},
                                  {"e_max_abs", sum.e_max_abs},
                                  {"mu_eff_max_abs", sum.mu_eff_max_abs}};
  std::vector<JsonError> errors;
  for (const auto& t : score.trials)
    if (!t.scored()) errors.push_back({t.error, "", t.dir.string(), t.id, ""});
  PrintEnvelope("score", exit_code, {{"trials", rows}, {"summary", summary}}, errors);
}

/// One line per trial and the summary.
void PrintScoreText(const pipeline::StudyScore& score) {
  const pipeline::StudyScoreSummary& sum = score.summary;
  for (const auto& t : score.trials) {
    const std::string name = t.id.empty() ? t.dir.string() : t.id;
    if (!t.scored()) {
      std::cout << name << ": FAILED " << t.error << "\n";
      continue;
    }
    const auto& s = t.score;
    using format::Kind;
    std::cout << std::left << std::setw(28) << name << std::right;
    if (s.marker_count > 0)
      std::cout << " marker rms " << format::Number(s.marker_rms_px, Kind::kError) << " px ";
    // A truth.json written before the centre's image was recorded has none.
    if (s.centre_count > 0)
      std::cout << " centre rms " << format::Number(s.centre_rms_px, Kind::kError) << " px ";
    std::cout << " v "
              << format::Number(100 * std::max(s.v_before_rel, s.v_after_rel), Kind::kError)
              << " %  w ";
    // A ball's spin is not seen: no w error.
    if (std::isfinite(s.w_before_abs) && std::isfinite(s.w_after_abs))
      std::cout << format::Number(std::max(s.w_before_abs, s.w_after_abs), Kind::kError)
                << " rad/s";
    else
      std::cout << "n/a (not seen)";
    std::cout << "  e " << format::Number(s.e_abs, Kind::kError) << "  mu_eff "
              << format::Number(s.mu_eff_abs, Kind::kError);
    if (s.impacts_true > 0)
      std::cout << "  impacts " << s.impacts_matched << " of " << s.impacts_true;
    std::cout << "\n";
  }
  using format::Kind;
  std::cout << "summary: " << sum.scored << " of " << sum.trials << " trials scored; ";
  if (sum.marker_rms_px > 0)
    std::cout << "marker rms " << format::Number(sum.marker_rms_px, Kind::kError) << " px (worst "
              << format::Number(sum.marker_max_px, Kind::kError) << "), ";
  if (sum.centre_max_px > 0)
    std::cout << "centre rms " << format::Number(sum.centre_rms_px, Kind::kError) << " px (worst "
              << format::Number(sum.centre_max_px, Kind::kError) << "), ";
  std::cout << "v_SC " << format::Number(100 * sum.v_SC_max_rel, Kind::kError) << " %, w "
            << (std::isfinite(sum.w_max_abs_rad_s)
                    ? format::Number(sum.w_max_abs_rad_s, Kind::kError) + " rad/s"
                    : std::string("n/a (not seen)"))
            << ", e " << format::Number(sum.e_max_abs, Kind::kError) << ", mu_eff "
            << format::Number(sum.mu_eff_max_abs, Kind::kError) << " (worst of each)";
  if (sum.impacts_true > 0)
    std::cout << "; impacts " << sum.impacts_matched << " of " << sum.impacts_true << " found";
  std::cout << "\n";
}

}  // namespace

void RegisterScore(CLI::App& app, RunState& state) {
  struct Args {
    std::string study_dir;
    bool json = false;
    int jobs = 0;
    pipeline::TrialAnalysisOptions options;
    std::string method = "centroid";
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "score", "Measure the trials of a synthetic study and score them against truth.json");
  cmd->add_option("study_dir", args->study_dir, "Study folder with synthetic trials")
      ->required()
      ->check(CLI::ExistingDirectory);
  AddJsonFlag(cmd, args->json);
  cmd->add_option("--jobs", args->jobs, "Worker threads (0 = all cores)")
      ->check(InRange(0, 4096))
      ->capture_default_str();
  AddAnalysisOptions(cmd, args->options, args->method);
  cmd->callback([args, &state] {
    Args& a = *args;
    ApplyMethod(a.method, a.options);
    const pipeline::StudyScore score = pipeline::ScoreStudy(a.study_dir, a.options, a.jobs);
    const pipeline::StudyScoreSummary& sum = score.summary;
    state.exit_code = sum.scored == sum.trials ? kExitOk : kExitPartial;
    if (a.json)
      PrintScoreJson(score, state.exit_code);
    else
      PrintScoreText(score);
  });
}

}  // namespace hoof::cli
