#pragma once
/// @file
/// Scoring a trial's analysis against the ground truth of a synthetic trial (truth.json).
/// Only tests and scoring tools read truth; the measuring pipeline never does.

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "pipeline/trial_analysis.h"

namespace hoof::pipeline {

/// One impact of truth.json's `impacts` (every impact of the clip).
struct ImpactTruth {
  double touch_time_s = 0.0;  ///< first touch, since frame 0's capture
  double e = 0.0;
  double mu_eff = 0.0;  ///< NaN on a level surface
};

/// What truth.json says (docs/format.md), the parts scoring uses.
struct TrialTruth {
  /// truth.json's body.kind: "markers", "unmarked" or "ball" ("markers" when absent, as in
  /// files written before other bodies were rendered).
  std::string body = "markers";
  double impact_time_s = 0.0;  ///< first touch, since frame 0
  Eigen::Vector2d v_SC_before{0, 0}, v_SC_after{0, 0};
  double w_before_rad_s = 0.0, w_after_rad_s = 0.0;
  double e = 0.0, mu_eff = 0.0;
  /// markers_px per frame (true, unblurred centres in the recorded image), by marker name;
  /// empty maps for a body without markers.
  std::vector<std::map<std::string, Eigen::Vector2d>> markers_px;
  /// center_px per frame: the image of the centre of mass C (a ball's centre) in the recorded
  /// image; nullopt where the file has none.
  std::vector<std::optional<Eigen::Vector2d>> centre_px;
  std::vector<ImpactTruth> impacts;  ///< empty where the file has no `impacts`
  bool out_of_plane = false;         ///< any out-of-plane tilt or roll was rendered
};

/// Reads `trial_dir/truth.json`. Throws std::runtime_error naming the file and field.
TrialTruth ReadTruth(const std::filesystem::path& trial_dir);

/// Errors of an analysis against truth. A body without markers has no marker errors (count
/// 0); a ball's spin is not seen, so its w errors are NaN.
struct TrialScore {
  double marker_rms_px = 0.0;  ///< over every found marker in every frame
  double marker_max_px = 0.0;
  int marker_count = 0;
  /// The centre path: the measured pose's centre of mass C (E + d x_B) taken into the image
  /// against truth's center_px, over every frame with a pose (px).
  double centre_rms_px = 0.0, centre_max_px = 0.0;
  int centre_count = 0;
  /// The clip's impacts: in truth, found (measured), and matched (a measured impact within two
  /// frame periods of a true touch); the largest e error over the matched ones (NaN: none).
  int impacts_true = 0, impacts_found = 0, impacts_matched = 0;
  double impacts_e_max_abs = 0.0;
  double v_before_rel = 0.0;  ///< |v_SC measured - truth| / |truth|, before
  double v_after_rel = 0.0;   ///< same, after
  double w_before_abs = 0.0;  ///< |w measured - truth| (rad/s)
  double w_after_abs = 0.0;
  double e_abs = 0.0;
  double mu_eff_abs = 0.0;         ///< NaN where the measured or the true mu_eff is NaN
  double impact_time_abs_s = 0.0;  ///< |measured impact time - first touch|
};

/// Scores `analysis` (which must have succeeded) against `truth`.
TrialScore ScoreTrial(const TrialAnalysis& analysis, const TrialTruth& truth);

/// One trial of a synthetic study, measured and scored against its truth.json.
struct StudyTrialScore {
  std::filesystem::path dir;
  std::string id;                   ///< empty when the trial folder could not be read
  std::vector<std::string> flags;   ///< the analysis's flags (TrialAnalysis::flags)
  std::string error;                ///< why the trial was not scored; empty when it was
  TrialScore score;                 ///< valid when error is empty
  bool truth_out_of_plane = false;  ///< the truth says an out-of-plane rotation was rendered
  bool scored() const { return error.empty(); }
};

/// A study's scores pooled: the RMS marker error over every found marker of every scored trial,
/// the centre's likewise, and the worst of each error (each over the trials where it is a
/// number: mu_eff's on oblique trials, w's where the spin is seen).
struct StudyScoreSummary {
  int trials = 0, scored = 0;
  double marker_rms_px = 0.0, marker_max_px = 0.0;
  double centre_rms_px = 0.0, centre_max_px = 0.0;  ///< pooled as the markers' are
  int impacts_true = 0, impacts_matched = 0;        ///< summed over the scored trials
  double v_SC_max_rel = 0.0;  ///< the larger of v_before_rel and v_after_rel, over trials
  /// NaN when no scored trial's spin is seen (a study of balls).
  double w_max_abs_rad_s = 0.0, e_max_abs = 0.0, mu_eff_max_abs = 0.0;
};

struct StudyScore {
  std::vector<StudyTrialScore> trials;  ///< in the order of the study's trial folders
  StudyScoreSummary summary;
};

/// Measures every trial of the study in `study_dir` with `options` and scores it against its
/// truth.json, on `jobs` threads (core::ResolveJobs). A trial that cannot be read, measured or
/// scored keeps its error and the others go on; the result does not depend on `jobs`. Throws
/// only when the study itself cannot be read.
StudyScore ScoreStudy(const std::filesystem::path& study_dir,
                      const TrialAnalysisOptions& options = {}, int jobs = 0);

/// The summary of already scored trials (ScoreStudy's, for trials scored elsewhere).
StudyScoreSummary SummarizeScores(const std::vector<StudyTrialScore>& trials);

}  // namespace hoof::pipeline
