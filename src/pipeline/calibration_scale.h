#pragma once
/// @file
/// The scale from a calibration image named in trial.json (docs/format.md, "The scale"):
/// `camera.scale_from` "checkerboard" or "ruler", the image a file beside the trial or a frame
/// of its clip, measured by tracking/calibration_target.h. Also `init`'s side of it: a
/// calibration image given on its command line, measured and written into the trial.json.

#include <filesystem>
#include <string>

#include <Eigen/Core>

#include "pipeline/study_format.h"
#include "pipeline/trial_setup.h"
#include "tracking/calibration_target.h"

namespace hoof::pipeline {

/// True when the trial's scale comes from a calibration image.
bool UsesCalibrationImage(const TrialSpec& spec);

/// Measures the trial's calibration image (camera.checkerboard or camera.ruler, as
/// camera.scale_from says) with the trial's lens model. Throws std::runtime_error naming the
/// image (file, or clip and frame) and the trial.json field: a missing or unreadable image, a
/// frame beyond the clip, no board or another corner count, a ruler segment off the image.
tracking::CalibrationScale MeasureCalibrationScale(const TrialSpec& spec);

/// A calibration image for `init` (docs/init.md): `kind` "checkerboard" or "ruler" (empty:
/// none), the image's path as given, and the target's geometry.
struct InitCalibration {
  std::string kind;
  std::filesystem::path image;
  int cols = 0, rows = 0;
  double square_m = 0.0;
  Eigen::Vector2d from_px{0.0, 0.0}, to_px{0.0, 0.0};
  double tick_m = 0.0;
};

/// Measures `c` and makes it the setup's scale: scale_from, m_per_px and its s.e., and the
/// trial.json text (camera.scale_from and camera.checkerboard or camera.ruler, the image named
/// relative to `trial_dir`). Throws std::runtime_error naming the image or the option.
void UseCalibrationScale(const InitCalibration& c, const std::filesystem::path& trial_dir,
                         TrialSetup& setup);

}  // namespace hoof::pipeline
