#pragma once
/// @file
/// The discovery step of a study (`hoofimpact discover`, and `run --discover`): the workflow
/// of hoof::discovery run on a study's trials, its result stored in the study file under
/// /discovery with the options it ran with, and its figures drawn.

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "discovery/discovery.h"
#include "pipeline/trial_analysis.h"

namespace hoof::study {

struct DiscoveryStep {
  discovery::DiscoveryOptions options;  ///< as run (kinematics options from the study file)
  discovery::DiscoveryResult result;
  std::filesystem::path figures_dir;
  std::vector<std::filesystem::path> figures;  ///< the figure files written
  std::vector<std::string> warnings;  ///< e.g. the study file's kinematics options unreadable
};

/// Runs discovery on `trials` (those of `study_h5`) with `options`, whose kinematics options
/// are replaced by the ones stored in the study file (the defaults, with a warning, when they
/// cannot be read), stores the result under /discovery of `study_h5`, and draws the figures
/// into `figures_dir` (figures/ beside the study file when empty). `progress` gets discovery's
/// progress lines. Throws std::invalid_argument for options out of range or an unknown
/// candidate key; a workflow that could not run is a result with success = false, stored.
DiscoveryStep DiscoverAndStore(const std::filesystem::path& study_h5,
                               const std::vector<pipeline::TrialAnalysis>& trials,
                               discovery::DiscoveryOptions options,
                               const std::filesystem::path& figures_dir,
                               const std::function<void(const std::string&)>& progress = {});

}  // namespace hoof::study
