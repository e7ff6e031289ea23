// End-to-end tests of `hoofimpact simulate`, against the independent reference results
// (kReference in tests/dynamics/impact_simulator_test.cc).
#include <cmath>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/csv.h"
#include "support/run_command.h"

namespace hoof::cli {
namespace {

using hoof::testing::RunHoofimpact;

TEST(SimulateCommandTest, JsonMatchesThePapersObliqueReferenceCase) {
  const auto r =
      RunHoofimpact("simulate --surface steel --angle-deg 20 --speed-m-s 3.28 --mu 0.12 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out).at("results");
  // The reference oblique case (kReference in tests/dynamics/impact_simulator_test.cc):
  // v_C = (0.4706, 2.3451), w = 57.56, e 0.8472, dKE 17.630 mJ, 9.86 us.
  EXPECT_NEAR(j["v_SC_after_m_s"][0].get<double>(), 0.4706, 1e-3 * 2.39);
  EXPECT_NEAR(j["v_SC_after_m_s"][1].get<double>(), 2.3451, 1e-3 * 2.39);
  EXPECT_NEAR(j["w_after_rad_s"].get<double>(), 57.56, 0.06);
  EXPECT_NEAR(j["e"].get<double>(), 0.8472, 1e-3);
  EXPECT_NEAR(j["mu_eff"].get<double>(), 0.1200, 1e-3);
  EXPECT_NEAR(j["energy_loss_J"].get<double>(), 17.630e-3, 2e-5);
  EXPECT_NEAR(j["contact_duration_s"].get<double>(), 9.86e-6, 1e-8);
}

TEST(SimulateCommandTest, OverridesReachTheModel) {
  // Frictionless normal impact with a chosen zeta and no gravity: e is the closed form.
  const auto r =
      RunHoofimpact("simulate --k 1e8 --zeta 0.3 --mu 0 --gravity-m-s2 0 --mass-kg 0.01 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out).at("results");
  const double z = 0.3;
  const double e = std::exp(-z / std::sqrt(1 - z * z) * std::atan(std::sqrt(1 - z * z) / z));
  EXPECT_NEAR(j["e"].get<double>(), e, 1e-6);
  EXPECT_NEAR(j["contact"]["b_N_s_m"].get<double>(), 2 * 0.3 * std::sqrt(1e8 * 0.01), 1e-9);
  EXPECT_TRUE(j["mu_eff"].is_number());
}

TEST(SimulateCommandTest, TrajectoryCsvHasFrameTimesAndFreeFlight) {
  const std::string path = std::string(HOOF_BINARY_DIR) + "/traj_test.csv";
  std::filesystem::remove(path);
  const auto r =
      RunHoofimpact("simulate --surface concrete --angle-deg 10 --speed-m-s 2 --trajectory " +
                    path + " --frames-before 5 --frames-after 7 --fps 8000");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const io::CsvTable t = io::CsvTable::Read(path);
  ASSERT_EQ(t.rows(), 12u);
  const auto time = t.Numbers("t_s");
  const auto vy = t.Numbers("v_SC_y_m_s");
  for (std::size_t i = 1; i < time.size(); ++i)
    EXPECT_NEAR(time[i] - time[i - 1], 1.0 / 8000, 1e-15);
  // Free flight before touch: v_SC.y changes by -g cos(phi) per unit time.
  EXPECT_NEAR((vy[1] - vy[0]) / (time[1] - time[0]), -9.81 * std::cos(10 * M_PI / 180), 1e-6);
  EXPECT_EQ(t.Texts("phase").front(), "flight_before");
  EXPECT_EQ(t.Texts("phase").back(), "flight_after");
}

TEST(SimulateCommandTest, BadInputGivesAClearErrorAndNonZeroExit) {
  // Values out of range are command-line errors (exit 2), like unknown flags.
  auto r = RunHoofimpact("simulate --mass-kg -0.008");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--mass-kg"), std::string::npos) << r.err;
  // Every bound of the physical inputs, and no NaN anywhere; the sampling options are checked
  // without --trajectory too.
  for (const char* bad : {"--mass-kg 1e-12", "--speed-m-s 1e300", "--mu nan", "--k inf",
                          "--zeta -1", "--hunt-crossley-n-s-m2 1e300", "--rolling-resistance-m 5",
                          "--fps -1", "--touch-fraction nan", "--angle-deg 1e999"}) {
    r = RunHoofimpact(std::string("simulate ") + bad);
    EXPECT_EQ(r.exit_code, 2) << bad << "\n" << r.err;
    EXPECT_NE(r.err.find(std::string(bad).substr(0, std::string(bad).find(' '))), std::string::npos)
        << r.err;
  }
  r = RunHoofimpact("simulate --surface wood");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("wood"), std::string::npos) << r.err;
  r = RunHoofimpact("simulate --speed-m-s -3");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--speed-m-s"), std::string::npos) << r.err;
  // Work and output are capped: these hung before.
  r = RunHoofimpact("simulate --frames-before 1000000000 --trajectory /dev/null");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--frames-before"), std::string::npos) << r.err;
  r = RunHoofimpact("simulate --contact-samples 2000000000 --trajectory /dev/null");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--contact-samples"), std::string::npos) << r.err;
  r = RunHoofimpact("simulate --no-such-flag");
  EXPECT_EQ(r.exit_code, 2);
  r = RunHoofimpact("simulate --help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("--angle-deg"), std::string::npos);
}

// A negative seed or thread count is a command-line error (exit 2) naming the option, not a
// value wrapped to 2^64 - 1 or taken as "all cores".
TEST(CommandLineLimitsTest, NegativeSeedsAndThreadCountsAreRefused) {
  const std::string sample = std::string(HOOF_SOURCE_DIR) + "/sample_frames";
  for (const auto& [args, option] :
       {std::pair<std::string, std::string>{"synth --seed -1 -o /nonexistent/x", "--seed"},
        {"synth --study --jobs -1 -o /nonexistent/x", "--jobs"},
        {"synth --study --threads -1 -o /nonexistent/x", "--jobs"},  // its earlier name
        {"run " + sample + " --jobs -1 -o /nonexistent/x", "--jobs"},
        {"score " + sample + " --jobs -5", "--jobs"}}) {
    const auto r = RunHoofimpact(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(option), std::string::npos) << args << "\n" << r.err;
  }
}

}  // namespace
}  // namespace hoof::cli
