#include "study/discovery_step.h"

#include "discovery/discovery_tables.h"
#include "report/discovery_figures.h"
#include "studyfile/study_file.h"

namespace hoof::study {

DiscoveryStep DiscoverAndStore(const std::filesystem::path& study_h5,
                               const std::vector<pipeline::TrialAnalysis>& trials,
                               discovery::DiscoveryOptions options,
                               const std::filesystem::path& figures_dir,
                               const std::function<void(const std::string&)>& progress) {
  DiscoveryStep step;
  try {
    options.kinematics = studyfile::ReadKinematicsOptions(study_h5);
  } catch (const std::exception& e) {
    // Only a re-measurement with a rotation rate needs them; the defaults are `analyze`'s.
    step.warnings.push_back(
        std::string(e.what()) +
        "; trials re-measured with an out-of-plane rotation use the default kinematics options");
  }
  options.Validate();
  step.options = options;
  step.result = discovery::Discover(
      trials, options, progress ? progress : [](const std::string&) {});
  std::vector<studyfile::Table> tables = discovery::DiscoveryTables(step.result);
  tables.push_back(discovery::DiscoveryOptionsTable(options));
  studyfile::WriteTables(study_h5, discovery::kDiscoveryGroup, "discovery (hoofimpact discover)",
                         tables);
  step.figures_dir = figures_dir.empty() ? study_h5.parent_path() / "figures" : figures_dir;
  step.figures = report::WriteDiscoveryFigures(step.result, step.figures_dir);
  return step;
}

}  // namespace hoof::study
