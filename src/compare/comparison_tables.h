#pragma once
/// @file
/// The study file's group `/comparison` (docs/hdf5-schema.md), written and read from one
/// declaration of its columns: `surfaces` (the contact law per surface), `trials` (one row per
/// trial), and per compared trial `frames/<id>` (one row per frame) and `energy/<id>` (kinetic
/// energy through the contact, paper Figure 8). The report and the overlay read it through the
/// typed readers here, not by column names.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "compare/study_comparison.h"
#include "studyfile/study_file.h"

namespace hoof::compare {

/// The comparison as study-file tables. Values a failed fit or trial does not have are NaN.
std::vector<studyfile::Table> ComparisonTables(const std::vector<pipeline::TrialAnalysis>& trials,
                                               const StudyComparison& comparison);

/// Soft links that put each compared trial's tables under its own group too:
/// `/trials/<group>/comparison_frames` -> `/comparison/frames/<id>` and
/// `/trials/<group>/comparison_energy` -> `/comparison/energy/<id>` (for WriteTables).
std::vector<std::pair<std::string, std::string>> ComparisonLinks(
    const std::vector<pipeline::TrialAnalysis>& trials, const StudyComparison& comparison);

/// One row of `/comparison/trials`: a trial's id and its comparison, without the per-frame
/// values and the contact's energy (ReadComparedFrames, ReadContactEnergy).
struct ComparedTrial {
  std::string id;
  TrialComparison comparison;
};

/// Whether `h5` holds a comparison (the table `/comparison/trials`).
bool HasComparison(const std::filesystem::path& h5);
/// The surface models of `/comparison/surfaces`, in the file's order.
std::vector<SurfaceModel> ReadSurfaceModels(const std::filesystem::path& h5);
/// The rows of `/comparison/trials`, in the file's order.
std::vector<ComparedTrial> ReadComparedTrials(const std::filesystem::path& h5);
/// The frames of trial `id` (`/comparison/frames/<id>`), with the markers `marker_names` (the
/// trial's specimen layout, in order).
std::vector<FrameComparison> ReadComparedFrames(const std::filesystem::path& h5,
                                                const std::string& id,
                                                const std::vector<std::string>& marker_names);
/// The frames of trial `id` and the markers its table holds (from its columns "<marker>_sim_x_px",
/// in their order), for a reader that does not know the trial's layout.
struct ComparedFrames {
  std::vector<std::string> markers;
  std::vector<FrameComparison> frames;
};
ComparedFrames ReadComparedFrames(const std::filesystem::path& h5, const std::string& id);
/// The kinetic energy through the contact of trial `id` (`/comparison/energy/<id>`): times
/// since first touch (s) and energies (J), into `contact_t_s` and `contact_kinetic_energy_J`.
void ReadContactEnergy(const std::filesystem::path& h5, const std::string& id,
                       TrialComparison& comparison);

}  // namespace hoof::compare
