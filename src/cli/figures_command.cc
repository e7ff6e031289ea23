// hoofimpact figures: a study file -> the study figures (the paper's Figures 4 and 5: mean e
// and mu_eff per surface against impact angle and nominal speed, error bars = s.d.).
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>

#include "cli/commands.h"
#include "report/figures.h"
#include "studyfile/study_file.h"

namespace hoof::cli {

void RegisterFigures(CLI::App& app, RunState& state) {
  struct Args {
    std::string study_file;
    std::string output_dir;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "figures",
      "Draw the study figures (PNG and SVG) from a study file: e_by_angle, e_by_speed, "
      "mu_eff_by_angle, mu_eff_by_speed (mean per surface, error bars = s.d.)");
  cmd->add_option("study_h5", args->study_file, "HDF5 study file written by `analyze`")->required();
  cmd->add_option("-o,--output", args->output_dir, "Folder for the figures (created when missing)")
      ->required();
  cmd->callback([args, &state] {
    // A missing file is bad input (exit 1, naming it), not a bad command line.
    if (!std::filesystem::is_regular_file(args->study_file))
      throw std::runtime_error(args->study_file + ": no such study file");
    const studyfile::StudyResults study = studyfile::ReadStudyResults(args->study_file);
    const auto written = report::WriteStudyFigures(study, args->output_dir);
    for (const auto& f : written) std::cout << "figure: " << f.string() << "\n";
    if (written.empty()) {
      std::cerr << "hoofimpact: error: " << args->study_file << ": no successful trial to draw\n";
      state.exit_code = kExitFailure;
    }
  });
}

}  // namespace hoof::cli
