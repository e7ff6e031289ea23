// The commands' text follows the one number policy (src/format/number_format.h, docs/cli.md
// "Numbers"): undefined values print "n/a" (track printed "mu_eff  nan  (s.e. nan, 95 % nan ..
// nan)" for a normal impact, score "mu 0.0000"), and a number prints with the digits of its
// kind (simulate printed e with 6 digits).
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "format/number_format.h"
#include "support/run_command.h"

namespace {

using hoof::testing::RunHoofimpact;
namespace format = hoof::format;

const std::string kSample = std::string(HOOF_SOURCE_DIR) + "/sample_frames";

TEST(NumberTextTest, UndefinedPrintsNaNowhereNan) {
  // mu_eff of a normal impact is not defined.
  auto r = RunHoofimpact("track " + kSample + "/steel_0deg_v3.00_r1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("mu_eff  n/a  (95 % n/a)"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("nan"), std::string::npos) << r.out;
  r = RunHoofimpact("score " + kSample + " --jobs 2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("mu_eff n/a"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("nan"), std::string::npos) << r.out;
}

TEST(NumberTextTest, NumbersPrintWithTheDigitsOfTheirKind) {
  const auto json = RunHoofimpact("simulate --surface concrete --angle-deg 20 --json");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  const auto j = nlohmann::json::parse(json.out).at("results");
  const auto text = RunHoofimpact("simulate --surface concrete --angle-deg 20");
  ASSERT_EQ(text.exit_code, 0) << text.err;
  // A coefficient to 4 significant digits, the same value the JSON holds in full.
  const double e = j.at("e").get<double>();
  EXPECT_NE(
      text.out.find("  e             " + format::Number(e, format::Kind::kCoefficient) + "\n"),
      std::string::npos)
      << text.out;
  const double mu_eff = j.at("mu_eff").get<double>();
  EXPECT_NE(
      text.out.find("  mu_eff        " + format::Number(mu_eff, format::Kind::kCoefficient) + "\n"),
      std::string::npos)
      << text.out;
  // The contact duration in µs, 4 digits.
  EXPECT_NE(text.out.find(format::Number(j.at("contact_duration_s").get<double>() * 1e6) + " µs"),
            std::string::npos)
      << text.out;
}

}  // namespace
