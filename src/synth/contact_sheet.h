#pragma once
/// @file
/// A contact sheet: a few frames around impact from several trials, side by side, to look at
/// what the renderer draws (docs/contact-sheet.png).

#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace hoof::synth {

/// One row of the sheet: frames `first` .. `first + count - 1` of the trial folder `trial_dir`.
struct ContactSheetRow {
  std::filesystem::path trial_dir;
  int first = 0;
  int count = 5;
  std::string label;
};

/// Reads the frames (8- or 16-bit), scales each by `scale`, tiles them with the label and the
/// frame index, and returns an 8-bit grey image. Throws std::runtime_error naming a frame that
/// cannot be read.
cv::Mat MakeContactSheet(const std::vector<ContactSheetRow>& rows, double scale = 0.5);

}  // namespace hoof::synth
