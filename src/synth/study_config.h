#pragma once
/// @file
/// A study config file (`synth --study --study-config FILE`, docs/synthetic-trials.md): the
/// design of a synthetic study, its hidden effects and, optionally, the specimen's markers, as
/// one JSON object.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "synth/options.h"
#include "synth/study.h"

namespace hoof::synth {

struct StudyConfig {
  StudyDesign design;
  /// The config's `markers_B_m`, when it has one: replaces the specimen's markers.
  std::optional<std::vector<Marker>> markers_B_m;
  /// Bodies and nuisances (docs/synthetic-trials.md, "Bodies, lighting and clip faults"), each
  /// when the file has its key: `body`, `ball_diameter_m`, `ball_mass_kg`, `lighting`,
  /// `flicker_hz`, `flicker_depth`, `drop_frames`, `duplicate_frames`.
  std::optional<Body> body;
  std::optional<double> ball_diameter_m, ball_mass_kg;
  std::optional<Lighting> lighting;
  std::optional<double> flicker_hz, flicker_depth;
  std::optional<int> drop_frames, duplicate_frames;
  /// `frame_format`: "png", "mraw" or "cine" (RenderOptions::frame_format).
  std::optional<FrameFormat> frame_format;
};

/// The surfaces named in `names`; std::invalid_argument "WHERE: ..." for a name that is not one
/// (`where` says where the names came from: an option or a file's key).
std::vector<dynamics::Surface> ParseSurfaces(const std::vector<std::string>& names,
                                             const std::string& where);

/// Reads the config in `path` over `base`: each key the file holds replaces that field of the
/// design (`name`, `seed`, `surfaces`, `angles_deg`, `speeds_m_s`, `trials_per_cell`, `cells`,
/// `scatter_parameters`, `scatter_scale`, `out_of_plane_random_deg`, `markers_B_m`, and
/// `hidden_effects` with a key of every contact extension and `tilt_deg`, `roll_deg`,
/// `tilt_rate_deg_s`, `roll_rate_deg_s`), and the body, nuisance and frame_format keys of
/// StudyConfig. The
/// design and those values are validated. Every error names the file:
/// one that cannot be read, JSON that does not parse or is not an object, an unknown key, a value
/// of the wrong type (std::invalid_argument), or a value out of range (std::runtime_error, from
/// StudyDesign::Validate, naming the field).
StudyConfig ReadStudyConfig(const std::filesystem::path& path, const StudyDesign& base = {});

/// The config's specimen keys (markers_B_m, body, ball_*) onto `geometry`, and its camera keys
/// (flicker_*, drop_frames, duplicate_frames) onto `camera`; keys the file left out leave
/// their fields alone.
void ApplyStudyConfig(const StudyConfig& config, SpecimenGeometry& geometry);
void ApplyStudyConfig(const StudyConfig& config, CameraEffects& camera);

}  // namespace hoof::synth
