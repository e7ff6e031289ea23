#pragma once
/// @file
/// How a trial's analysis is shown: JSON (for scripts), text (for people), CSV (tracks), and
/// the analysis options shared by `track` and `analyze`.

#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "pipeline/trial_analysis.h"

namespace hoof::cli {

/// Adds --method, --fit-frames, --max-contact-s, --exposure-s, --scale-from-markers.
void AddAnalysisOptions(CLI::App* cmd, pipeline::TrialAnalysisOptions& options,
                        std::string& method);
/// Sets the centre method from "centroid" or "ellipse"; throws naming the value otherwise.
void ApplyMethod(const std::string& method, pipeline::TrialAnalysisOptions& options);

/// One trial's results: id, v_SC_before_m_s, v_SC_after_m_s, w_before_rad_s, w_after_rad_s,
/// e, e_se, mu_eff, mu_eff_se, impact_time_s, flags, and more.
nlohmann::json TrialJson(const pipeline::TrialAnalysis& r);
/// One impact of TrialAnalysis::impacts: impact_index, lowest_frame, success, error (why it was
/// not measured) and, when measured, the keys TrialJson gives the trial's main impact.
nlohmann::json ImpactEntryJson(const kinematics::ImpactKinematics& k);
/// The clip's impacts, one line each (TrialText adds it when there are several).
std::string ImpactsText(const pipeline::TrialAnalysis& r);
/// The frame timing (tracking/frame_timing.h): source ("time_stamps", "motion" or
/// "frame_index"), repeated_frames, dropped_captures, capture_slots (per frame), notes, and the
/// image differences (mean_abs_difference per frame, noise_mean_abs_difference) where taken.
nlohmann::json FrameTimingJson(const tracking::FrameTiming& t);
/// A short readable summary.
std::string TrialText(const pipeline::TrialAnalysis& r);
/// Per frame: marker centres (px), status and quality, pose (m, rad).
std::string TracksCsv(const pipeline::TrialAnalysis& r);

}  // namespace hoof::cli
