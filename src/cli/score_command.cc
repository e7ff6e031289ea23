// hoofimpact score: measure synthetic trials and score them against their truth.json.
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/trial_output.h"
#include "core/parallel.h"
#include "pipeline/truth_score.h"

namespace hoof::cli {

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
  cmd->add_flag("--json", args->json, "Print one JSON object per trial and a summary");
  cmd->add_option("--jobs", args->jobs, "Worker threads (0 = all cores)")
      ->check(CLI::Range(0, 4096));
  AddAnalysisOptions(cmd, args->options, args->method);
  cmd->callback([args, &state] {
    Args& a = *args;
    ApplyMethod(a.method, a.options);
    const pipeline::StudySpec study = pipeline::ReadStudy(a.study_dir);
    const std::size_t n = study.trial_dirs.size();
    std::vector<nlohmann::json> rows(n);
    std::vector<pipeline::TrialScore> scores(n);
    std::vector<char> ok(
        n, 0);  // not vector<bool>: its packed bits would be a data race between workers
    core::ParallelFor(n, a.jobs, [&](std::size_t i) {
      nlohmann::json row = {{"dir", study.trial_dirs[i].string()}};
      try {
        const auto spec = pipeline::ReadTrial(study.trial_dirs[i], study);
        const auto r = pipeline::AnalyzeTrial(spec, a.options);
        row["id"] = spec.id;
        row["flags"] = r.flags;
        if (!r.success) {
          row["error"] = r.error;
        } else {
          const auto truth = pipeline::ReadTruth(study.trial_dirs[i]);
          const auto s = pipeline::ScoreTrial(r, truth);
          scores[i] = s;
          ok[i] = 1;
          row.update({{"marker_rms_px", s.marker_rms_px},
                      {"marker_max_px", s.marker_max_px},
                      {"v_before_rel", s.v_before_rel},
                      {"v_after_rel", s.v_after_rel},
                      {"w_before_abs", s.w_before_abs},
                      {"w_after_abs", s.w_after_abs},
                      {"e_abs", s.e_abs},
                      {"mu_eff_abs", JsonNumber(s.mu_eff_abs)},
                      {"impact_time_abs_s", s.impact_time_abs_s},
                      {"truth_out_of_plane", truth.out_of_plane}});
        }
      } catch (const std::exception& e) {
        row["error"] = e.what();
      }
      rows[i] = row;
    });

    // Summary: pooled marker RMS and the worst of every error.
    double ss = 0, worst_v = 0, worst_w = 0, worst_e = 0, worst_mu = 0, worst_marker = 0;
    long count = 0;
    int n_ok = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (!ok[i]) continue;
      ++n_ok;
      const auto& s = scores[i];
      ss += s.marker_rms_px * s.marker_rms_px * s.marker_count;
      count += s.marker_count;
      worst_marker = std::max(worst_marker, s.marker_max_px);
      worst_v = std::max({worst_v, s.v_before_rel, s.v_after_rel});
      worst_w = std::max({worst_w, s.w_before_abs, s.w_after_abs});
      worst_e = std::max(worst_e, s.e_abs);
      if (std::isfinite(s.mu_eff_abs)) worst_mu = std::max(worst_mu, s.mu_eff_abs);
    }
    nlohmann::json summary = {
        {"trials", n},
        {"succeeded", n_ok},
        {"marker_rms_px", count ? std::sqrt(ss / static_cast<double>(count)) : 0.0},
        {"marker_max_px", worst_marker},
        {"v_SC_max_rel", worst_v},
        {"w_max_abs_rad_s", worst_w},
        {"e_max_abs", worst_e},
        {"mu_eff_max_abs", worst_mu}};
    if (a.json) {
      std::cout << nlohmann::json({{"trials", rows}, {"summary", summary}}).dump(2) << "\n";
    } else {
      for (const auto& r : rows) {
        if (r.contains("error")) {
          std::cout << r.value("id", r["dir"].get<std::string>()) << ": FAILED "
                    << r["error"].get<std::string>() << "\n";
          continue;
        }
        std::cout << std::left << std::setw(28) << r["id"].get<std::string>() << std::right
                  << std::fixed << std::setprecision(4) << " marker rms "
                  << r["marker_rms_px"].get<double>() << " px  v "
                  << 100 * std::max(r["v_before_rel"].get<double>(), r["v_after_rel"].get<double>())
                  << " %  w "
                  << std::max(r["w_before_abs"].get<double>(), r["w_after_abs"].get<double>())
                  << "  e " << r["e_abs"].get<double>() << "  mu "
                  << (r["mu_eff_abs"].is_number() ? r["mu_eff_abs"].get<double>() : 0.0) << "\n";
      }
      std::cout << "summary: " << summary.dump() << "\n";
    }
    state.exit_code = n_ok == static_cast<int>(n) ? kExitOk : kExitPartial;
  });
}

}  // namespace hoof::cli
