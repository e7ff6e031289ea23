#pragma once
/// @file
/// A whole synthetic study: the paper's design (3 surfaces x 4 angles x 4 speeds x 3
/// repetitions = 144 trials) or a smaller one, rendered in parallel across trials. Each trial's
/// seed derives from the study seed and the trial's index, so the bytes do not depend on the
/// number of threads.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "synth/options.h"
#include "synth/renderer.h"

namespace hoof::synth {

/// One cell of a hand-picked design.
struct StudyCell {
  dynamics::Surface surface = dynamics::Surface::kSteel;
  double angle_deg = 0.0;  ///< In [0, 60].
  double speed_m_s = 3.0;  ///< In (0, 20].
};

/// The factors of a study and what every trial shares.
struct StudyDesign {
  std::string name = "synthetic-paper-replica";
  std::uint64_t seed = 2024;  ///< Derives every trial's seed and the scene textures.
  std::vector<dynamics::Surface> surfaces = {
      dynamics::Surface::kSteel, dynamics::Surface::kConcrete, dynamics::Surface::kAsphalt};
  std::vector<double> angles_deg = {0.0, 10.0, 20.0, 30.0};  ///< Each in [0, 60].
  std::vector<double> speeds_m_s = {1.5, 2.33, 3.17, 4.0};   ///< Each in (0, 20].
  /// When not empty, these cells replace the full surfaces x angles x speeds product.
  std::vector<StudyCell> cells;
  int trials_per_cell = 3;         ///< Repetitions of each cell; >= 1.
  bool scatter_parameters = true;  ///< Per-trial e and mu draws (TrialSpec).
  double scatter_scale = 1.0;      ///< Multiplies the spreads of those draws; in [0, 4].
  HiddenEffects hidden;            ///< Applied to every trial.
  /// When > 0, each trial draws its own out-of-plane tilt and roll uniformly in +-this (deg)
  /// and rates in +-(this * 100) deg/s, replacing hidden.out_of_plane.
  double out_of_plane_random_deg = 0.0;

  /// Throws std::invalid_argument naming the field.
  void Validate() const;
  /// The trials in order: surface, angle, speed, repetition; ids like steel_20deg_v3.17_r1.
  std::vector<TrialSpec> Trials() const;
};

/// Makes `design` unreplicated: `per_angle` trials of every surface and angle, each at its own
/// speed drawn uniformly in [lo, hi] m/s from a generator seeded by the design's seed, so that
/// no two trials share a cell (36 trials for the paper's surfaces and angles: the scorecard's
/// "unreplicated" design, docs/discovery.md). Trial ids carry the speed to 0.01 m/s; a draw
/// whose id is taken is drawn again, so ids stay unique. Replaces `cells`, sets
/// `trials_per_cell` to 1. Throws std::invalid_argument naming the argument for per_angle < 1,
/// a range outside 0 < lo < hi <= 20 m/s, or one with fewer than 2 x per_angle speeds distinct
/// to 0.01 m/s (where the redraws could take too long or never end).
void DrawUnreplicatedCells(StudyDesign& design, int per_angle = 3, double lo_m_s = 1.5,
                           double hi_m_s = 4.0);

/// One trial of a study: its result, or why it failed.
struct StudyTrial {
  TrialSpec spec;
  bool ok = false;
  std::string error;
  TrialResult result;
};

struct StudyResult {
  std::vector<StudyTrial> trials;
  double seconds = 0.0;
  int failed = 0;
};

/// Renders `design` into the folder `study_dir` (created), one trial folder per trial and
/// study.json last, with `threads` workers (0 = hardware concurrency). A failing trial is
/// recorded, the others go on; study.json lists the trials that were written. `progress`, when
/// set, is called after each trial with (done, total, id) from the worker threads, serialized.
StudyResult RenderStudy(const StudyDesign& design, const SpecimenGeometry& geometry,
                        const RenderOptions& options, const std::filesystem::path& study_dir,
                        int threads = 0, bool overwrite = false,
                        const std::function<void(int, int, const std::string&)>& progress = {});

}  // namespace hoof::synth
