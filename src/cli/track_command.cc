// hoofimpact track: one trial folder -> marker tracks, poses and the impact measurement.
#include <cmath>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>

#include <unistd.h>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/json_output.h"
#include "cli/trial_output.h"
#include "io/atomic_file.h"
#include "pipeline/trial_analysis.h"
#include "report/figures.h"

namespace hoof::cli {

void RegisterTrack(CLI::App& app, RunState& state) {
  struct Args {
    std::string trial_dir;
    std::string study_json;
    std::string tracks_csv;
    std::string figures_dir;
    bool json = false;
    pipeline::TrialAnalysisOptions options;
    std::string method = "centroid";
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "track", "Track one trial's markers and measure its impact (velocities, w, e, mu_eff)");
  cmd->add_option("trial_dir", args->trial_dir, "Trial folder (docs/format.md)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--study", args->study_json,
                  "study.json that defines the specimen (default: the one beside the trial)");
  cmd->add_option("--tracks-csv", args->tracks_csv, "Write the marker tracks and poses as CSV");
  AddJsonFlag(cmd, args->json);
  cmd->add_option(
      "--figures", args->figures_dir,
      "Write the trial's figures into this folder (PNG and SVG): <id>_displacement (the "
      "paper's Figure 3), <id>_out_of_plane, and <id>_height (height against time with the "
      "flight arcs, each impact and its e) for a trial measured by its arcs");
  AddAnalysisOptions(cmd, args->options, args->method);

  cmd->callback([args, &state] {
    Args& a = *args;
    ApplyMethod(a.method, a.options);
    const pipeline::TrialSpec spec =
        a.study_json.empty()
            ? pipeline::ReadTrial(a.trial_dir)
            : pipeline::ReadTrial(a.trial_dir, std::filesystem::path(a.study_json));
    const bool tty = ::isatty(STDERR_FILENO) != 0;
    const pipeline::TrialAnalysis r = pipeline::AnalyzeTrial(spec, a.options, [&](int f) {
      if (tty && (f % 10 == 0 || f + 1 == spec.frames.count))
        std::cerr << "\r  tracking " << spec.id << ": frame " << f + 1 << "/" << spec.frames.count
                  << std::flush;
    });
    if (tty) std::cerr << "\n";
    if (!a.tracks_csv.empty()) io::WriteTextAtomically(a.tracks_csv, TracksCsv(r));
    const auto figures = report::WriteTrialFigures(r, a.options, a.figures_dir, /*always=*/true,
                                                   /*displacement=*/true);
    state.exit_code = r.success ? kExitOk : r.no_impact ? kExitNoImpact : kExitFailure;
    if (a.json) {
      nlohmann::json results = TrialJson(r);
      results["figures"] = figures;
      std::vector<JsonError> errors;
      if (!r.success) errors.push_back({r.error, "", spec.dir.string(), spec.id, ""});
      PrintEnvelope("track", state.exit_code, std::move(results), errors);
    } else {
      std::cout << TrialText(r);
      for (const auto& f : figures) std::cout << "  figure: " << f << "\n";
    }
    if (r.no_impact)
      std::cerr << "hoofimpact: no impact in the clip: " << r.error << "\n";
    else if (!r.success)
      std::cerr << "hoofimpact: error: " << r.error << "\n";
  });
}

}  // namespace hoof::cli
