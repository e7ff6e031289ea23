#pragma once
/// @file
/// Every impact of a trial's clip (kinematics::MeasureImpacts) and which of them is the trial's
/// main result, the one `TrialAnalysis::impact` holds.

#include <vector>

#include "core/specimen.h"
#include "kinematics/impact_kinematics.h"
#include "pipeline/trial_analysis.h"

namespace hoof::pipeline {

/// Measures the impacts of `samples` (one pose per frame) into out.impacts and the trial's main
/// result into out.impact, by the method options.method names (out.kinematics_method says
/// which ran). kAuto: the windows (kinematics/impact_kinematics.h) when they find an impact and
/// every window of every impact holds options.fit_frames frames; else the joint arcs
/// (kinematics/arc_impacts.h) when they find an impact and measure gravity's direction (its
/// s.e. within options.arcs.max_roll_se_deg); else the windows' result (their no-impact report
/// included). A window that cannot fill means a flight shorter than the window, which the
/// window then holds whole; the joint arcs fit every flight whole with one fitted
/// acceleration, find contact frames by their residuals and take gravity's direction from the
/// arcs, so they gain wherever the windows cannot fill and gravity bends the arcs measurably;
/// where the windows fill they keep the paper's local method and its numbers.
///
/// Windows: a clip with one impact or none gets MeasureImpact's result (its no-impact and
/// second-bounce reports included); out.impacts then holds the impact found, if any. Both
/// methods, with several impacts: the main result is the first impact that was measured (a
/// warning names it when an earlier one was not), and each impact found but not measured is a
/// warning naming it and the reason. The joint arcs also fill out.arcs and out.contact_line.
/// `w_seen` false (a ball: its rotation is not seen) makes w and its s.e. NaN in every impact.
void MeasureTrialImpacts(const std::vector<kinematics::PoseSample>& samples, double fps,
                         double surface_angle_deg, const core::SpecimenParameters& body,
                         const kinematics::KinematicsOptions& options, bool w_seen,
                         TrialAnalysis& out);

}  // namespace hoof::pipeline
