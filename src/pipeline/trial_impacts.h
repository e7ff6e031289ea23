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
/// result into out.impact. A clip with one impact or none gets MeasureImpact's result (today's
/// single-impact measurement, its no-impact and second-bounce reports included); out.impacts
/// then holds the impact found, if any. With several, the main result is the first impact that
/// was measured (a warning names it when an earlier one was not), and each impact found but not
/// measured is a warning naming it and the reason. `w_seen` false (a ball: its rotation is not
/// seen) makes w and its s.e. NaN in every impact.
void MeasureTrialImpacts(const std::vector<kinematics::PoseSample>& samples, double fps,
                         double surface_angle_deg, const core::SpecimenParameters& body,
                         const kinematics::KinematicsOptions& options, bool w_seen,
                         TrialAnalysis& out);

}  // namespace hoof::pipeline
