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

/// Fits each surface's model and compares every successful trial, on `jobs` threads. A trial
/// that cannot be compared (or whose specimen cannot be simulated) keeps its message, naming its
/// trial.json, its id and where its specimen was defined; it never stops the others.
StudyComparison CompareStudy(const std::vector<pipeline::TrialAnalysis>& trials, int jobs = 2);

/// The trials compared without a known mass (a ball without a specimen), and how many of them
/// without a known inertia.
struct MassGaps {
  int without_mass = 0;     ///< compared at kReferenceMass_kg: no energies, no k and b
  int inertia_assumed = 0;  ///< of them, simulated as a solid sphere
  /// What they leave out, in a sentence or two; "" when none.
  std::string Text() const;
};

/// The gaps of `comparison`'s compared trials.
MassGaps MassGapsOf(const StudyComparison& comparison);

}  // namespace hoof::compare
