#pragma once
/// @file
/// Figures of a trial's measurement.

#include <filesystem>

#include "pipeline/trial_analysis.h"

namespace hoof::report {

/// The out-of-plane check as a figure: the projected marker distance over the layout distance,
/// per frame, with the fit windows shaded and the flag threshold drawn around the median. The
/// format follows the extension (.png or .svg).
void WriteOutOfPlaneFigure(const pipeline::TrialAnalysis& trial, double threshold,
                           const std::filesystem::path& output);

}  // namespace hoof::report
