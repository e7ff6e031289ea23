// A video file that no backend reads: one message naming the file, nothing of OpenCV's or
// GStreamer's own on stderr.
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/run_command.h"

namespace {

namespace fs = std::filesystem;

TEST(BadVideoTest, AGarbageVideoIsNamedWithoutBackendNoise) {
  const fs::path study = fs::path(HOOF_BINARY_DIR) / "test-output" / "bad_video";
  fs::remove_all(study);
  fs::copy(fs::path(HOOF_SOURCE_DIR) / "sample_frames", study, fs::copy_options::recursive);
  const fs::path trial = study / "steel_0deg_v3.00_r1";
  std::mt19937 rng(7);
  std::ofstream clip(trial / "clip.avi", std::ios::binary);
  for (int i = 0; i < 5000; ++i) clip.put(static_cast<char>(rng() & 0xff));
  clip.close();
  nlohmann::json j = nlohmann::json::parse(std::ifstream(trial / "trial.json"));
  j["frames"] = {{"video", "clip.avi"}};
  std::ofstream(trial / "trial.json") << j.dump(1);
  const auto r = hoof::testing::RunHoofimpact("track " + trial.string());
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("clip.avi: cannot open video"), std::string::npos) << r.err;
  for (const char* noise : {"WARN", "GStreamer", "OpenCV(", "[ERROR"})
    EXPECT_EQ(r.err.find(noise), std::string::npos) << noise << " in:\n" << r.err;
}

}  // namespace
