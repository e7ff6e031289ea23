// A synthetic trial's truth.json as ReadTruth reads it: a sample trial's file reads with its
// numbers, and a broken one names the file and the field (the cases the fuzzer found first:
// a frame without markers, a marker that is not [x, y], a tilt that is not a number).
#include "pipeline/truth_score.h"

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/test_util.h"

namespace {

namespace fs = std::filesystem;
using hoof::pipeline::ReadTruth;

fs::path WriteTruth(const std::string& name, const nlohmann::json& j) {
  const fs::path dir = fs::path(HOOF_BINARY_DIR) / "test-output" / "truth_score_test" / name;
  fs::create_directories(dir);
  std::ofstream(dir / "truth.json") << j.dump();
  return dir;
}

nlohmann::json SampleTruth() {
  std::ifstream in(std::string(HOOF_SOURCE_DIR) + "/sample_frames/steel_20deg_v3.28_r1/truth.json");
  return nlohmann::json::parse(in);
}

TEST(TruthScoreTest, ASampleTruthReadsWithItsNumbers) {
  const nlohmann::json j = SampleTruth();
  const auto t = ReadTruth(WriteTruth("sample", j));
  EXPECT_EQ(t.e, j.at("e").get<double>());
  EXPECT_EQ(t.v_SC_before.x(), j.at("v_SC_before_m_s")[0].get<double>());
  ASSERT_EQ(t.markers_px.size(), j.at("frames").size());
  EXPECT_FALSE(t.markers_px.front().empty());
}

TEST(TruthScoreTest, ABrokenTruthNamesTheFileAndTheField) {
  const auto expect = [](const std::string& name, const nlohmann::json& j,
                         const std::string& needle) {
    const fs::path dir = WriteTruth(name, j);
    hoof::testing::ExpectErrorContaining([&] { ReadTruth(dir); },
                                         (dir / "truth.json").string() + ": " + needle);
  };
  nlohmann::json j = SampleTruth();
  j["frames"][3].erase("markers_px");
  expect("no_markers", j, "field \"frames[3].markers_px\" is missing or not an object");
  j = SampleTruth();
  j["frames"][0]["markers_px"].begin().value() = {1.0, "x"};
  expect("bad_marker", j, "field \"frames[0].markers_px.");
  j = SampleTruth();
  j["frames"][1]["out_of_plane_tilt_rad"] = "tilted";
  expect("bad_tilt", j, "field \"frames[1].out_of_plane_tilt_rad\" must be a number");
  j = SampleTruth();
  j["frames"][2] = 7;
  expect("frame_not_object", j, "field \"frames[2].markers_px\" is missing or not an object");
  j = SampleTruth();
  j["v_SC_after_m_s"] = {1.0};
  expect("short_velocity", j, "field \"v_SC_after_m_s\" must be [x, y]");
}

}  // namespace
