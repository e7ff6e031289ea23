// `hoofimpact score`: the sample trials measured against their truth.json on one and on two
// threads. The accuracy is the tracker's own target (e within 0.001, velocities within 0.1 %),
// and the result does not depend on the number of threads.
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/run_command.h"

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

}  // namespace
