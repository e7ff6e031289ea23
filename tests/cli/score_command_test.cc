// `hoofimpact score`: the sample trials measured against their truth.json on one and on two
// threads. The accuracy is the tracker's own target (e within 0.001, velocities within 0.1 %),
// and the result does not depend on the number of threads.
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/run_command.h"
#include "support/test_studies.h"

namespace {

using hoof::testing::RunHoofimpact;

TEST(ScoreCommandTest, SampleTrialsMeetTheirTruthOnAnyNumberOfThreads) {
  const std::string sample = std::string(HOOF_SOURCE_DIR) + "/sample_frames";
  const auto one = RunHoofimpact("score " + sample + " --json --jobs 1");
  const auto two = RunHoofimpact("score " + sample + " --json --jobs 2");
  ASSERT_EQ(one.exit_code, 0) << one.err;
  ASSERT_EQ(two.exit_code, 0) << two.err;
  EXPECT_EQ(one.out, two.out);
  const auto j = nlohmann::json::parse(two.out).at("results");
  const auto& s = j.at("summary");
  EXPECT_EQ(s.at("succeeded").get<int>(), 4);
  EXPECT_LT(s.at("e_max_abs").get<double>(), 1e-3);
  EXPECT_LT(s.at("mu_eff_max_abs").get<double>(), 1e-3);
  EXPECT_LT(s.at("v_SC_max_rel").get<double>(), 1e-3);
  EXPECT_LT(s.at("marker_rms_px").get<double>(), 0.05);
  ASSERT_EQ(j.at("trials").size(), 4u);
}

TEST(ScoreCommandTest, BallsAndOutlinesAreScoredOnTheirCentreAndImpacts) {
  // A ball's and an outline's truth has no markers; score reads their centre path and impacts
  // (bounds as in tests/pipeline/truth_score_test.cc) and says that a ball's spin is not seen.
  for (const std::string name : {"ball_8", "unmarked_8"}) {
    const std::string study = hoof::testing::TestStudyDir(name).string();
    const auto text = RunHoofimpact("score " + study);
    ASSERT_EQ(text.exit_code, 0) << text.err << text.out;
    EXPECT_NE(text.out.find("summary: 8 of 8 trials scored; centre rms"), std::string::npos)
        << text.out;
    EXPECT_NE(text.out.find("impacts 8 of 8 found"), std::string::npos) << text.out;
    EXPECT_EQ(text.out.find("w n/a (not seen)") != std::string::npos, name == "ball_8") << text.out;
    const auto json = RunHoofimpact("score " + study + " --json");
    ASSERT_EQ(json.exit_code, 0) << json.err;
    const nlohmann::json parsed = nlohmann::json::parse(json.out);
    const auto& s = parsed.at("results").at("summary");
    EXPECT_EQ(s.at("succeeded").get<int>(), 8);
    EXPECT_LT(s.at("e_max_abs").get<double>(), 0.003) << name;
    EXPECT_LT(s.at("mu_eff_max_abs").get<double>(), 0.003) << name;
    EXPECT_LT(s.at("centre_rms_px").get<double>(), 0.6) << name;
    EXPECT_EQ(s.at("w_max_abs_rad_s").is_null(), name == "ball_8") << name;
  }
}

}  // namespace
