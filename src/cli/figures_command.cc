// hoofimpact figures: a study file -> the study figures (the paper's Figures 4 and 5: mean e
// and mu_eff per surface against impact angle and nominal speed, error bars = s.d.).
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "cli/json_output.h"
#include "report/figures.h"
#include "studyfile/study_file.h"

namespace hoof::cli {

void RegisterFigures(CLI::App& app, RunState& state) {
  struct Args {
    std::string study_file;
    std::string output_dir;
    bool json = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "figures",
      "Draw the study figures (PNG and SVG) from a study file: e_by_angle, e_by_speed, "
      "mu_eff_by_angle, mu_eff_by_speed (mean per surface, error bars = s.d.)");
  cmd->add_option("study_h5", args->study_file, "HDF5 study file written by `analyze`")->required();
  cmd->add_option("-o,--output", args->output_dir,
                  "Output folder for the figures (created when missing)")
      ->required();
  AddJsonFlag(cmd, args->json);
  cmd->callback([args, &state] {
    // A missing file is bad input (exit 1, naming it), not a bad command line.
    if (!std::filesystem::is_regular_file(args->study_file))
      throw std::runtime_error(args->study_file + ": no such study file");
    const studyfile::StudyResults study = studyfile::ReadStudyResults(args->study_file);
    const auto written = report::WriteStudyFigures(study, args->output_dir);
    const std::string error = args->study_file + ": no successful trial to draw";
    state.exit_code = written.empty() ? kExitFailure : kExitOk;
    if (args->json) {
      std::vector<std::string> figures;
      for (const auto& f : written) figures.push_back(f.string());
      std::vector<JsonError> errors;
      if (written.empty()) errors.push_back(ErrorFromMessage(error));
      PrintEnvelope(
          "figures", state.exit_code,
          {{"study_h5", args->study_file}, {"output_dir", args->output_dir}, {"figures", figures}},
          errors);
    } else {
      for (const auto& f : written) std::cout << "figure: " << f.string() << "\n";
    }
    if (written.empty()) std::cerr << "hoofimpact: error: " << error << "\n";
  });
}

}  // namespace hoof::cli
