#pragma once
/// @file
/// The everyday-footage renderer's entry point (docs/synthetic-trials.md, "Everyday footage"):
/// renders a clip of a coloured ball bouncing in an ordinary room, as a phone or a slow-motion
/// camera records it, with its exact truth. Writes DIR/clip.mp4 (H.264, yuv420p, through
/// OpenCV's FFmpeg writer, frames stored turned by the rotation tag) or DIR/frames/%06d.png
/// (lossless, upright), and DIR/truth.json; never a trial.json. It draws; it never detects.

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "synth/footage_options.h"
#include "synth/footage_plan.h"
#include "synth/footage_truth.h"

namespace hoof::synth {

/// A rendered clip.
struct FootageResult {
  FootageTruth truth;
  std::filesystem::path path;   ///< The clip's folder.
  std::filesystem::path clip;   ///< clip.mp4, or the frames/ folder.
  double render_seconds = 0.0;  ///< Wall time of planning, drawing and writing.
};

/// Plans, draws and writes the clip of `spec` into the folder `out_dir`, under a temporary name
/// beside it renamed when complete. An existing folder is replaced only with `overwrite`.
/// Throws std::invalid_argument for a bad spec (naming the field) and std::runtime_error when
/// writing fails (naming the file). `jobs` threads draw frames (0 = all cores); the bytes do
/// not depend on it.
FootageResult RenderFootage(const FootageSpec& spec, const std::filesystem::path& out_dir,
                            bool overwrite = false, int jobs = 1);

/// The delivered frames [first, first + count) of a planned clip, upright as a reader delivers
/// them (CV_8UC3, BGR), before any compression: the PNG variant's pixels.
std::vector<cv::Mat> RenderFootageFrames(const FootagePlan& plan, int first = 0, int count = -1);

/// The frame as the file stores it: `upright` turned counter-clockwise by `rotation_tag_deg`.
cv::Mat StoredFrame(const cv::Mat& upright, int rotation_tag_deg);

/// truth.json of a clip (format kFootageTruthFormat; every field in docs/synthetic-trials.md).
nlohmann::json FootageTruthJson(const FootageTruth& truth);

/// The name of the clip file in its folder: "clip.mp4", or "frames/%06d.png".
std::string FootageClipName(FootageCodec codec);

}  // namespace hoof::synth
