// `hoofimpact track` on a body without markers: the real Photron ball clip (a back-lit 2.5 mm
// sphere that does not reach the surface in its 15 frames; tests/data/real-ball/trial.json) and
// bad input (a clip with no moving body, frames with no body).
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "support/run_command.h"
#include "tracking/silhouette_test_images.h"

namespace {

namespace fs = std::filesystem;
using hoof::testing::RunHoofimpact;

const fs::path kBall = fs::path(HOOF_SOURCE_DIR) / "tests" / "data" / "real-ball";

// The figures the issue (and the recording's README) give: the sphere moves about 2.64 px per
// frame, 1.56 m/s at the authors' 19.7 um/px (127 px x 19.7 um = 2.5 mm), in a straight line.
TEST(TrackSilhouetteTest, TheRealBallClipHoldsNoImpactAndItsApproachIsMeasured) {
  const auto r = RunHoofimpact("track " + kBall.string() + " --json");
  EXPECT_EQ(r.exit_code, 4) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["exit_code"], 4);
  EXPECT_FALSE(j["success"]);
  const auto& t = j["results"];
  EXPECT_TRUE(t["no_impact"]);
  EXPECT_FALSE(t.contains("e")) << "an e was invented";
  EXPECT_EQ(t["body_model"], "silhouette");
  EXPECT_EQ(t["polarity"], "dark_on_bright");
  EXPECT_EQ(t["scale_source"], "body.diameter_m");
  EXPECT_NEAR(t["m_per_px_used"].get<double>(), 19.7e-6, 0.01 * 19.7e-6);
  EXPECT_NEAR(t["body_diameter_px"].get<double>(), 127.0, 1.0);
  const auto& m = t["motion"];
  EXPECT_EQ(m["frames_tracked"], 15);
  EXPECT_LT(m["rms_residual_px"].get<double>(), 0.05);
  EXPECT_NEAR(m["speed_px_per_frame"].get<double>(), 2.64, 0.02);
  EXPECT_NEAR(m["speed_m_s"].get<double>(), 1.56, 0.01);
  EXPECT_GT(m["speed_se_m_s"].get<double>(), 0.0);
  EXPECT_LT(m["speed_se_m_s"].get<double>(), 0.01);
  // Straight down the image: the sideways drift is under 0.02 px per frame.
  EXPECT_LT(std::abs(m["v_px_per_frame"][0].get<double>()), 0.02);
}

TEST(TrackSilhouetteTest, TheTextSaysThereIsNoImpactAndPrintsNoE) {
  const fs::path trial = fs::path(HOOF_BINARY_DIR) / "test-output" / "track_silhouette" / "ball";
  fs::remove_all(trial);
  fs::create_directories(trial);
  // The stated scale of the authors' set-up instead of the ball's diameter.
  nlohmann::json j = nlohmann::json::parse(std::ifstream(kBall / "trial.json"));
  j["frames"]["camera_file"] =
      (fs::absolute(kBall) / j["frames"]["camera_file"].get<std::string>()).string();
  j["camera"]["m_per_px"] = 19.7e-6;
  std::ofstream(trial / "trial.json") << j.dump(1);
  const auto r =
      RunHoofimpact("track " + trial.string() + " --tracks-csv " + (trial / "tracks.csv").string());
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_NE(r.out.find("no impact in the clip"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("15 frames tracked"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("from camera.m_per_px"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("\n  e "), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("no impact in the clip"), std::string::npos) << r.err;
  std::ifstream csv(trial / "tracks.csv");
  std::string line;
  int rows = 0;
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, 16);  // a header and 15 frames
}

/// A trial folder of 8-bit frames drawn here: a bright disc that stays put, or nothing.
fs::path StillTrial(const std::string& name, bool with_body) {
  const fs::path dir = fs::path(HOOF_BINARY_DIR) / "test-output" / "track_silhouette" / name;
  fs::remove_all(dir);
  fs::create_directories(dir / "frames");
  for (int i = 0; i < 16; ++i) {
    cv::Mat img(120, 120, CV_64F, cv::Scalar(30.0));
    if (with_body) hoof::testing::PaintDisc(img, {60.3, 58.9}, 20.0, 200.0, 30.0);
    char file[32];
    std::snprintf(file, sizeof file, "frames/%06d.png", i);
    cv::imwrite((dir / file).string(),
                hoof::testing::Quantize(img, CV_8U, 2.0, static_cast<unsigned>(7 + i)));
  }
  std::ofstream(dir / "trial.json")
      << R"({"format": "hoofimpact-trial/1", "id": ")" << name
      << R"(", "surface": "steel", "surface_angle_deg": 0, "fps": 1000,
  "frames": {"pattern": "frames/%06d.png", "first": 0, "count": 16},
  "body": {"model": "silhouette", "shape": "ball"}, "camera": {"m_per_px": 1e-4}})";
  return dir;
}

TEST(TrackSilhouetteTest, AClipWithNoMovingBodyIsAClearError) {
  const auto r = RunHoofimpact("track " + StillTrial("still", true).string() + " --json");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("no moving body"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("frames/000000.png"), std::string::npos) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["exit_code"], 1);
}

TEST(TrackSilhouetteTest, FramesWithoutABodyAreAClearError) {
  const auto r = RunHoofimpact("track " + StillTrial("empty", false).string());
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("no body found"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("frames/000000.png"), std::string::npos) << r.err;
}

// A ball rendered with known truth (hoofimpact synth: back-lit, 12-bit Photron clip, 8000 fps,
// onto 20 deg steel) and tracked by its silhouette alone: e and mu_eff within 0.01 of the truth
// (issue 16: marker-free e within 0.01 at 8000 fps), fps from the clip's header.
TEST(TrackSilhouetteTest, ARenderedBallClipGivesTheTruthsRestitutionAndFriction) {
  const fs::path trial =
      fs::path(HOOF_BINARY_DIR) / "test-output" / "track_silhouette" / "rendered_ball";
  fs::remove_all(trial);
  const auto s = RunHoofimpact("synth -o " + trial.string() +
                               " --body ball --lighting backlit --frame-format mraw --bit-depth 12"
                               " --seed 3 --angle-deg 20");
  ASSERT_EQ(s.exit_code, 0) << s.err;
  const auto truth = nlohmann::json::parse(std::ifstream(trial / "truth.json"));
  const auto r = RunHoofimpact("track " + trial.string() + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto t = nlohmann::json::parse(r.out)["results"];
  EXPECT_EQ(t["body_model"], "silhouette");
  EXPECT_NEAR(t["e"].get<double>(), truth["e"].get<double>(), 0.01);
  EXPECT_NEAR(t["mu_eff"].get<double>(), truth["mu_eff"].get<double>(), 0.01);
}

}  // namespace
