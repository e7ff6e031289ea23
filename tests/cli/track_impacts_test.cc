// `hoofimpact track` on rendered clips that bounce three times (`synth --bounces 3`): every
// bounce is found, and each e is within 0.01 of truth.json's impacts[i].e, for the marked
// specimen and for a back-lit ball tracked by its silhouette. Small frames at 500 fps keep the
// renders short (about 200 frames of 256 x 192). And a ball at 30 fps, by the joint arcs.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/run_command.h"

namespace {

namespace fs = std::filesystem;
using hoof::testing::RunHoofimpact;

void ExpectEveryBounce(const std::string& name, const std::string& body_options,
                       const std::string& track_options) {
  const fs::path trial = fs::path(HOOF_BINARY_DIR) / "test-output" / "track_impacts" / name;
  fs::remove_all(trial);
  const auto s = RunHoofimpact("synth -o " + trial.string() + " --bounces 3 " + body_options +
                               " --speed-m-s 1 --fps 500 --m-per-px 4e-4 --exposure-s 1e-4"
                               " --width-px 256 --height-px 192 --frames-before 15 --seed 1");
  ASSERT_EQ(s.exit_code, 0) << s.err;
  const auto truth = nlohmann::json::parse(std::ifstream(trial / "truth.json"));
  ASSERT_EQ(truth["impacts"].size(), 3u);
  const auto r = RunHoofimpact("track " + trial.string() + " --json" + track_options);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto t = nlohmann::json::parse(r.out)["results"];
  const auto& impacts = t["impacts"];
  ASSERT_EQ(impacts.size(), 3u) << impacts.dump(1);
  const double fps = 500;
  for (std::size_t i = 0; i < 3; ++i) {
    SCOPED_TRACE("impact " + std::to_string(i));
    const auto& k = impacts[i];
    const auto& want = truth["impacts"][i];
    ASSERT_TRUE(k["success"].get<bool>()) << k["error"];
    EXPECT_EQ(k["impact_index"], i);
    EXPECT_NEAR(k["e"].get<double>(), want["e"].get<double>(), 0.01);
    // The impact time where the fits meet, within a frame of the touch (the contact lasts
    // about 10 us).
    EXPECT_NEAR(k["impact_time_s"].get<double>(), want["touch_time_s"].get<double>(), 1 / fps);
    EXPECT_TRUE(k["mu_eff"].is_null());  // a level surface
  }
  // The trial's own result is the first impact.
  EXPECT_EQ(t["impact_index"], 0);
  EXPECT_EQ(t["e"], impacts[0]["e"]);
  // The text lists them.
  const auto text = RunHoofimpact("track " + trial.string() + track_options);
  EXPECT_NE(text.out.find("impacts: 3 in the clip"), std::string::npos) << text.out;
}

TEST(TrackImpactsTest, EveryBounceOfTheMarkedSpecimenIsMeasured) {
  ExpectEveryBounce("markers", "",
                    " --study " + std::string(HOOF_SOURCE_DIR) + "/sample_frames/study.json");
}

TEST(TrackImpactsTest, EveryBounceOfABackLitBallIsMeasured) {
  ExpectEveryBounce("ball", "--body ball --lighting backlit", "");
}

// A ball at 30 fps, four bounces, its flights 6 to 15 frames: no window fills, and the joint
// arcs measure every bounce (e within 0.01 of the truth, the impact time within a frame), list
// what limited each, give the contact line and the capture rate gravity implies (30 within 4
// s.e.). 55 frames of 320 x 480.
TEST(TrackImpactsTest, EveryBounceOfABallAtThirtyFpsIsMeasuredByTheJointArcs) {
  const fs::path trial = fs::path(HOOF_BINARY_DIR) / "test-output" / "track_impacts" / "ball30";
  fs::remove_all(trial);
  const auto s = RunHoofimpact("synth -o " + trial.string() +
                               " --body ball --lighting backlit --fps 30 --bounces 4"
                               " --frames-from-flight --speed-m-s 3 --m-per-px 2e-3"
                               " --width-px 320 --height-px 480 --seed 2");
  ASSERT_EQ(s.exit_code, 0) << s.err;
  const auto truth = nlohmann::json::parse(std::ifstream(trial / "truth.json"));
  ASSERT_EQ(truth["impacts"].size(), 4u);
  const auto r = RunHoofimpact("track " + trial.string() + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto t = nlohmann::json::parse(r.out)["results"];
  EXPECT_EQ(t["kinematics_method"], "arcs");
  const auto& impacts = t["impacts"];
  ASSERT_EQ(impacts.size(), 4u) << impacts.dump(1);
  for (std::size_t i = 0; i < 4; ++i) {
    SCOPED_TRACE("impact " + std::to_string(i));
    const auto& k = impacts[i];
    const auto& want = truth["impacts"][i];
    ASSERT_TRUE(k["success"].get<bool>()) << k["error"];
    EXPECT_EQ(k["method"], "arcs");
    EXPECT_NEAR(k["e"].get<double>(), want["e"].get<double>(), 0.01);
    EXPECT_NEAR(k["impact_time_s"].get<double>(), want["touch_time_s"].get<double>(), 1.0 / 30);
    EXPECT_GT(k["impact_time_se_s"].get<double>(), 0.0);
    EXPECT_GE(k["limits"]["samples_before"].get<int>(), 3);
    EXPECT_GE(k["limits"]["samples_after"].get<int>(), 3);
    EXPECT_TRUE(k["mu_eff"].is_null());  // dropped straight down on a level surface
  }
  EXPECT_TRUE(t["contact_line"]["measured"].get<bool>());
  ASSERT_TRUE(t["capture_rate"]["measured"].get<bool>());
  EXPECT_LT(std::abs(t["capture_rate"]["capture_fps"].get<double>() - 30),
            4 * t["capture_rate"]["capture_fps_se"].get<double>());
  EXPECT_LT(std::abs(t["arcs"]["a_norm"].get<double>() - 9.81),
            4 * t["arcs"]["a_norm_se"].get<double>() + 0.01);
  // The text names the method and each impact's limits.
  const auto text = RunHoofimpact("track " + trial.string());
  EXPECT_NE(text.out.find("impacts: 4 in the clip (arcs)"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("contact line"), std::string::npos) << text.out;
}

}  // namespace
