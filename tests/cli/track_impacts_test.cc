// `hoofimpact track` on rendered clips that bounce three times (`synth --bounces 3`): every
// bounce is found, and each e is within 0.01 of truth.json's impacts[i].e, for the marked
// specimen and for a back-lit ball tracked by its silhouette. Small frames at 500 fps keep the
// renders short (about 200 frames of 256 x 192).
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

}  // namespace
