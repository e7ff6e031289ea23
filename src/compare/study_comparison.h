#pragma once
/// @file
/// A whole study's simulation-against-measurement: the contact law fitted per surface, every
/// measured trial simulated and compared, and the tables that store it all in the study file
/// (group `/comparison`, docs/hdf5-schema.md).

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "compare/trial_comparison.h"
#include "studyfile/study_file.h"

namespace hoof::compare {

/// Every surface's model and every trial's comparison (in the order of the trials).
struct StudyComparison {
  std::map<std::string, SurfaceModel> surfaces;
  std::vector<TrialComparison> trials;  ///< same order as the analysed trials
};

/// Fits each surface's model and compares every successful trial, on `jobs` threads.
StudyComparison CompareStudy(const std::vector<pipeline::TrialAnalysis>& trials, int jobs = 2);

}  // namespace hoof::compare
