#include "synth/study_config.h"

#include <fstream>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

namespace hoof::synth {

std::vector<dynamics::Surface> ParseSurfaces(const std::vector<std::string>& names,
                                             const std::string& where) {
  std::vector<dynamics::Surface> out;
  for (const std::string& n : names) {
    try {
      out.push_back(dynamics::ParseSurface(n));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(where + ": " + e.what());
    }
  }
  return out;
}

namespace {

void ReadHiddenEffects(const nlohmann::json& value, const std::string& file, HiddenEffects& h) {
  for (const auto& [k, v] : value.items()) {
    const double val = v.get<double>();
    if (const auto* f = dynamics::FindContactExtension(k))
      h.contact.*f->member = val;
    else if (k == "tilt_deg")
      h.out_of_plane.tilt_deg = val;
    else if (k == "roll_deg")
      h.out_of_plane.roll_deg = val;
    else if (k == "tilt_rate_deg_s")
      h.out_of_plane.tilt_rate_deg_s = val;
    else if (k == "roll_rate_deg_s")
      h.out_of_plane.roll_rate_deg_s = val;
    else
      throw std::invalid_argument(file + ": unknown field 'hidden_effects." + k + "'");
  }
}

/// One key of the config onto `c`; false for a key the format does not have.
bool ReadKey(const std::string& key, const nlohmann::json& value, const std::string& file,
             StudyConfig& c) {
  StudyDesign& d = c.design;
  if (key == "name") {
    d.name = value.get<std::string>();
  } else if (key == "seed") {
    d.seed = value.get<std::uint64_t>();
  } else if (key == "surfaces") {
    d.surfaces = ParseSurfaces(value.get<std::vector<std::string>>(), file + ": surfaces");
  } else if (key == "angles_deg") {
    d.angles_deg = value.get<std::vector<double>>();
  } else if (key == "speeds_m_s") {
    d.speeds_m_s = value.get<std::vector<double>>();
  } else if (key == "trials_per_cell") {
    d.trials_per_cell = value.get<int>();
  } else if (key == "cells") {
    for (const auto& cell : value)
      d.cells.push_back(
          {ParseSurfaces({cell.at("surface").get<std::string>()}, file + ": cells").front(),
           cell.at("angle_deg").get<double>(), cell.at("speed_m_s").get<double>()});
  } else if (key == "scatter_parameters") {
    d.scatter_parameters = value.get<bool>();
  } else if (key == "scatter_scale") {
    d.scatter_scale = value.get<double>();
  } else if (key == "out_of_plane_random_deg") {
    d.out_of_plane_random_deg = value.get<double>();
  } else if (key == "markers_B_m") {
    std::vector<Marker> markers;
    for (const auto& [name, xy] : value.items())
      markers.push_back({name, {xy.at(0).get<double>(), xy.at(1).get<double>()}});
    c.markers_B_m = std::move(markers);
  } else if (key == "hidden_effects") {
    ReadHiddenEffects(value, file, d.hidden);
  } else if (key == "body") {
    try {
      c.body = ParseBody(value.get<std::string>());
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(file + ": " + e.what());
    }
  } else if (key == "lighting") {
    try {
      c.lighting = ParseLighting(value.get<std::string>());
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(file + ": " + e.what());
    }
  } else if (key == "frame_format") {
    try {
      c.frame_format = ParseFrameFormat(value.get<std::string>());
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(file + ": " + e.what());
    }
  } else if (key == "ball_diameter_m") {
    c.ball_diameter_m = value.get<double>();
  } else if (key == "ball_mass_kg") {
    c.ball_mass_kg = value.get<double>();
  } else if (key == "flicker_hz") {
    c.flicker_hz = value.get<double>();
  } else if (key == "flicker_depth") {
    c.flicker_depth = value.get<double>();
  } else if (key == "drop_frames") {
    c.drop_frames = value.get<int>();
  } else if (key == "duplicate_frames") {
    c.duplicate_frames = value.get<int>();
  } else {
    return false;
  }
  return true;
}

}  // namespace

StudyConfig ReadStudyConfig(const std::filesystem::path& path, const StudyDesign& base) {
  const std::string file = path.string();
  std::ifstream in(path);
  if (!in) throw std::invalid_argument("'" + file + "' cannot be read");
  StudyConfig c;
  c.design = base;
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    if (!j.is_object())
      throw std::invalid_argument("'" + file + "' must hold a JSON object ({...})");
    for (const auto& [key, value] : j.items())
      if (!ReadKey(key, value, file, c))
        throw std::invalid_argument(file + ": unknown field '" + key + "'");
  } catch (const nlohmann::json::exception& e) {
    throw std::invalid_argument("'" + file + "': " + e.what());
  }
  // The file's values on their own: a bad one names the file and the field.
  try {
    c.design.Validate();
    SpecimenGeometry g;
    ApplyStudyConfig(c, g);
    g.Validate();
    CameraEffects cam;
    ApplyStudyConfig(c, cam);
    cam.Validate();
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(file + ": " + e.what());
  }
  return c;
}

void ApplyStudyConfig(const StudyConfig& c, SpecimenGeometry& g) {
  if (c.markers_B_m) g.markers = *c.markers_B_m;
  if (c.body) g.body = *c.body;
  if (c.ball_diameter_m) g.ball_diameter_m = *c.ball_diameter_m;
  if (c.ball_mass_kg) g.ball_mass_kg = *c.ball_mass_kg;
}

void ApplyStudyConfig(const StudyConfig& c, CameraEffects& cam) {
  if (c.flicker_hz) cam.flicker_hz = *c.flicker_hz;
  if (c.flicker_depth) cam.flicker_depth = *c.flicker_depth;
  if (c.drop_frames) cam.drop_frames = *c.drop_frames;
  if (c.duplicate_frames) cam.duplicate_frames = *c.duplicate_frames;
}

}  // namespace hoof::synth
