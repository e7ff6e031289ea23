#pragma once
/// @file
/// The JSON documents of a synthetic trial and study, exactly per docs/format.md
/// (hoofimpact-trial/1, hoofimpact-truth/1, hoofimpact-study/1). Extra knowledge of the
/// renderer goes into truth.json only, so trial.json and study.json stay plain inputs.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "synth/options.h"
#include "synth/renderer.h"

namespace hoof::synth {

/// The specimen entry of study.json (mass, inertia, geometry and markers_B_m); for a ball
/// the ball's (`"shape": "ball"`, diameter_m, mass_kg, `"inertia": "solid"`: the renderer
/// simulates a solid sphere, SpecimenGeometry::Simulated).
nlohmann::json SpecimenJson(const SpecimenGeometry& geometry);

/// The id of the study's specimen: "ball" for a ball, else "A".
std::string SpecimenId(const SpecimenGeometry& geometry);

/// trial.json: format, id, specimen "A", surface, angle, fps, frames, camera (m_per_px,
/// gravity_image, and distortion with camera_matrix when the lens distorts),
/// surface_line_px, nominal_speed_m_s and notes. A ball names the specimen "ball" only
/// `in_study` (alone it is its own specimen, of unknown mass).
nlohmann::json TrialJson(const TrialTruth& truth, const RenderOptions& options,
                         const SpecimenGeometry& geometry = {}, bool in_study = false);

/// truth.json: docs/format.md's fields plus markers_px_undistorted, p_WC_m, out-of-plane angles,
/// model (k, b, mu, zeta, the drawn e, the scatter switch and scale, hidden_effects), camera
/// effects, frame defects.
nlohmann::json TruthJson(const TrialTruth& truth, const SpecimenGeometry& geometry,
                         const RenderOptions& options);

/// study.json with its specimen (SpecimenId) and the trial folders in order.
nlohmann::json StudyJson(const std::string& name, const SpecimenGeometry& geometry,
                         const std::vector<std::string>& trial_ids);

/// The hidden effects as recorded in truth.json's model.hidden_effects.
nlohmann::json HiddenEffectsJson(const HiddenEffects& hidden);
/// The camera effects as recorded in truth.json.
nlohmann::json CameraEffectsJson(const CameraEffects& camera);

}  // namespace hoof::synth
