// A study config as synth::ReadStudyConfig reads it: every key of the format lands in its field
// of the design (the rest keep the base's values), and a broken file names the file and the key
// or field: one that is missing, not JSON, not an object, a key the format does not have, a value
// of the wrong type, a value out of range.
#include "synth/study_config.h"

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "synth/test_support.h"

namespace {

namespace fs = std::filesystem;
using hoof::synth::ReadStudyConfig;

fs::path WriteConfig(const std::string& name, const std::string& text) {
  const fs::path p = hoof::synth::testing::FreshDir("study_config") / (name + ".json");
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
  return p;
}

/// Expects ReadStudyConfig(path) to throw with both `path` and `needle` in its message.
void ExpectError(const fs::path& path, const std::string& needle) {
  try {
    ReadStudyConfig(path);
    ADD_FAILURE() << "no error for " << path << " (" << needle << ")";
  } catch (const std::exception& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path.string()), std::string::npos) << what;
    EXPECT_NE(what.find(needle), std::string::npos) << what;
  }
}

TEST(StudyConfigTest, EveryKeyLandsInItsField) {
  const fs::path p = WriteConfig("every_key", R"({
    "name": "tiny", "seed": 77, "surfaces": ["asphalt", "steel"], "angles_deg": [0, 30],
    "speeds_m_s": [2.5], "trials_per_cell": 2, "scatter_parameters": false,
    "scatter_scale": 0.5, "out_of_plane_random_deg": 1.5,
    "cells": [{"surface": "concrete", "angle_deg": 10, "speed_m_s": 3.25}],
    "markers_B_m": {"A": [0.005, 0.001], "B": [0.025, -0.001]},
    "hidden_effects": {"hunt_crossley_N_s_m2": 2e7, "tilt_rate_deg_s": 300, "roll_deg": 2}})");
  hoof::synth::StudyDesign base;
  base.name = "base";
  const auto c = ReadStudyConfig(p, base);
  const auto& d = c.design;
  EXPECT_EQ(d.name, "tiny");
  EXPECT_EQ(d.seed, 77u);
  ASSERT_EQ(d.surfaces.size(), 2u);
  EXPECT_EQ(d.surfaces[0], hoof::dynamics::Surface::kAsphalt);
  EXPECT_EQ(d.surfaces[1], hoof::dynamics::Surface::kSteel);
  EXPECT_EQ(d.angles_deg, (std::vector<double>{0.0, 30.0}));
  EXPECT_EQ(d.speeds_m_s, std::vector<double>{2.5});
  EXPECT_EQ(d.trials_per_cell, 2);
  EXPECT_FALSE(d.scatter_parameters);
  EXPECT_EQ(d.scatter_scale, 0.5);
  EXPECT_EQ(d.out_of_plane_random_deg, 1.5);
  ASSERT_EQ(d.cells.size(), 1u);
  EXPECT_EQ(d.cells[0].surface, hoof::dynamics::Surface::kConcrete);
  EXPECT_EQ(d.cells[0].angle_deg, 10.0);
  EXPECT_EQ(d.cells[0].speed_m_s, 3.25);
  ASSERT_TRUE(c.markers_B_m.has_value());
  ASSERT_EQ(c.markers_B_m->size(), 2u);
  EXPECT_EQ((*c.markers_B_m)[0].name, "A");
  EXPECT_EQ((*c.markers_B_m)[1].p_BM_m.y(), -0.001);
  EXPECT_EQ(d.hidden.contact.hunt_crossley_N_s_m2, 2e7);
  EXPECT_EQ(d.hidden.out_of_plane.tilt_rate_deg_s, 300.0);
  EXPECT_EQ(d.hidden.out_of_plane.roll_deg, 2.0);
  EXPECT_EQ(d.hidden.out_of_plane.tilt_deg, 0.0);

  // A key the file leaves out keeps the base's value; no markers leaves the specimen's own.
  const auto partial = ReadStudyConfig(WriteConfig("partial", R"({"seed": 5})"), base);
  EXPECT_EQ(partial.design.name, "base");
  EXPECT_EQ(partial.design.seed, 5u);
  EXPECT_EQ(partial.design.angles_deg, base.angles_deg);
  EXPECT_FALSE(partial.markers_B_m.has_value());
}

TEST(StudyConfigTest, ABrokenConfigNamesTheFileAndTheKey) {
  ExpectError(fs::path(HOOF_BINARY_DIR) / "synth-test" / "study_config" / "missing.json",
              "cannot be read");
  ExpectError(WriteConfig("not_json", R"({"seed": )"), "parse error");
  ExpectError(WriteConfig("not_object", "[1, 2]"), "must hold a JSON object");
  ExpectError(WriteConfig("unknown_key", R"({"seeds": 3})"), "unknown field 'seeds'");
  ExpectError(WriteConfig("unknown_effect", R"({"hidden_effects": {"magic": 1}})"),
              "unknown field 'hidden_effects.magic'");
  ExpectError(WriteConfig("wrong_type", R"({"trials_per_cell": "three"})"), "type must be number");
  ExpectError(WriteConfig("bad_surface", R"({"surfaces": ["ice"]})"), "surfaces");
  ExpectError(WriteConfig("out_of_range", R"({"scatter_scale": -0.5})"), "scatter_scale");
}

TEST(StudyConfigTest, BodyAndNuisanceKeysLandInTheirFields) {
  const fs::path p = WriteConfig("nuisance", R"({
    "body": "ball", "ball_diameter_m": 0.0025, "ball_mass_kg": 0.0001, "lighting": "backlit",
    "flicker_hz": 120, "flicker_depth": 0.25, "drop_frames": 2, "duplicate_frames": 3,
    "frame_format": "cine"})");
  const auto c = ReadStudyConfig(p);
  hoof::synth::SpecimenGeometry g;
  hoof::synth::CameraEffects cam;
  hoof::synth::ApplyStudyConfig(c, g);
  hoof::synth::ApplyStudyConfig(c, cam);
  EXPECT_EQ(g.body, hoof::synth::Body::kBall);
  EXPECT_EQ(g.ball_diameter_m, 0.0025);
  EXPECT_EQ(g.ball_mass_kg, 0.0001);
  ASSERT_TRUE(c.lighting.has_value());
  EXPECT_EQ(*c.lighting, hoof::synth::Lighting::kBacklit);
  EXPECT_EQ(cam.flicker_hz, 120.0);
  EXPECT_EQ(cam.flicker_depth, 0.25);
  EXPECT_EQ(cam.drop_frames, 2);
  EXPECT_EQ(cam.duplicate_frames, 3);
  ASSERT_TRUE(c.frame_format.has_value());
  EXPECT_EQ(*c.frame_format, hoof::synth::FrameFormat::kCine);
  // Keys left out leave the fields alone.
  hoof::synth::SpecimenGeometry g2;
  hoof::synth::ApplyStudyConfig(ReadStudyConfig(WriteConfig("none", "{}")), g2);
  EXPECT_EQ(g2.body, hoof::synth::Body::kMarkers);

  ExpectError(WriteConfig("bad_body", R"({"body": "cube"})"), "body 'cube'");
  ExpectError(WriteConfig("bad_lighting", R"({"lighting": "side"})"), "lighting 'side'");
  ExpectError(WriteConfig("bad_flicker", R"({"flicker_depth": 1.5})"), "flicker_depth");
  ExpectError(WriteConfig("bad_ball", R"({"ball_diameter_m": 2})"), "ball_diameter_m");
  ExpectError(WriteConfig("bad_format", R"({"frame_format": "tiff"})"), "frame format 'tiff'");
}

}  // namespace
