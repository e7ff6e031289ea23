// hoofimpact figures: a study file -> the study figures (the paper's Figures 4 and 5: mean e
// and mu_eff per surface against impact angle and nominal speed, error bars = ±1 s.e.), and,
// when `run` has compared the study with the model (/comparison), Figures 6-8 (velocities after
// normal and oblique impacts, kinetic energy through an impact). Each figure is written as
// PNG, SVG, its data (CSV) and the gnuplot script that remakes the images from the data.
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "cli/json_output.h"
#include "compare/comparison_tables.h"
#include "io/atomic_file.h"
#include "report/comparison_figures.h"
#include "report/figures.h"
#include "report/gnuplot.h"
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
      "Draw the study figures from a study file: e_by_angle, e_by_speed, mu_eff_by_angle, "
      "mu_eff_by_speed (mean per surface, error bars = ±1 s.e.), and velocity_normal, "
      "velocity_oblique and energy_<id> when the file holds `run`'s comparison. Each as .png, "
      ".svg, its data .csv and the gnuplot script .gp that remakes it");
  cmd->add_option("study_h5", args->study_file, "HDF5 study file written by `analyze` or `run`")
      ->required();
  cmd->add_option("-o,--output", args->output_dir, "Folder for the figures (created when missing)")
      ->required();
  AddJsonFlag(cmd, args->json);
  cmd->callback([args, &state] {
    // A missing file is bad input (exit 1, naming it), not a bad command line.
    if (!std::filesystem::is_regular_file(args->study_file))
      throw std::runtime_error(args->study_file + ": no such study file");
    const studyfile::StudyResults study = studyfile::ReadStudyResults(args->study_file);
    if (std::filesystem::is_directory(args->output_dir))  // what a killed run left
      io::RemoveStaleTemporaries(args->output_dir, report::IsFigureTemporary);
    auto written = report::WriteStudyFigures(study, args->output_dir);
    if (compare::HasComparison(args->study_file))
      for (auto& f : report::WriteComparisonFigures(args->study_file, args->output_dir))
        written.push_back(std::move(f));
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
