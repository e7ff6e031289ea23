#pragma once
/// @file
/// Scoring a trial's analysis against the ground truth of a synthetic trial (truth.json).
/// Only tests and scoring tools read truth; the measuring pipeline never does.

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "pipeline/trial_analysis.h"

namespace hoof::pipeline {

/// What truth.json says (docs/format.md), the parts scoring uses.
struct TrialTruth {
  double impact_time_s = 0.0;  ///< first touch, since frame 0
  Eigen::Vector2d v_SC_before{0, 0}, v_SC_after{0, 0};
  double w_before_rad_s = 0.0, w_after_rad_s = 0.0;
  double e = 0.0, mu_eff = 0.0;
  /// markers_px per frame (true, unblurred centres in the recorded image), by marker name.
  std::vector<std::map<std::string, Eigen::Vector2d>> markers_px;
  bool out_of_plane = false;  ///< any out-of-plane tilt or roll was rendered
};

/// Reads `trial_dir/truth.json`. Throws std::runtime_error naming the file and field.
TrialTruth ReadTruth(const std::filesystem::path& trial_dir);

/// Errors of an analysis against truth.
struct TrialScore {
  double marker_rms_px = 0.0;  ///< over every found marker in every frame
  double marker_max_px = 0.0;
  int marker_count = 0;
  double v_before_rel = 0.0;  ///< |v_SC measured - truth| / |truth|, before
  double v_after_rel = 0.0;   ///< same, after
  double w_before_abs = 0.0;  ///< |w measured - truth| (rad/s)
  double w_after_abs = 0.0;
  double e_abs = 0.0;
  double mu_eff_abs = 0.0;         ///< NaN for normal impacts without tangential change
  double impact_time_abs_s = 0.0;  ///< |measured impact time - first touch|
};

/// Scores `analysis` (which must have succeeded) against `truth`.
TrialScore ScoreTrial(const TrialAnalysis& analysis, const TrialTruth& truth);

}  // namespace hoof::pipeline
