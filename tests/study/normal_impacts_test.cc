// The input and output of `hoofimpact fit` as a library (study/normal_impacts.h), read without
// spawning the program.
#include "study/normal_impacts.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "support/test_util.h"

namespace {

using hoof::study::NormalImpactColumns;
using hoof::study::ReadNormalImpacts;

std::string WriteCsv(const std::string& name, const std::string& text) {
  const auto path = hoof::testing::FreshDir("normal_impacts") / name;
  std::ofstream(path) << text;
  return path.string();
}

const char* kTable =
    "surface,surface_angle_deg,v_before_m_s,v_after_m_s\n"
    "steel,0,-3.0,1.5\n"
    "steel,0.0,-2.0,1.0\n"
    "concrete,0,-3.0,1.2\n"
    "steel,20,-3.0,nan\n";

TEST(NormalImpactsTest, RowsAreKeptByTheirTextOrTheirNumberAndGrouped) {
  const std::string csv = WriteCsv("t.csv", kTable);
  // "0" keeps "0.0" too (equal as numbers); the 20 deg row, whose rebound is "nan", is dropped
  // before it is parsed.
  const auto groups = ReadNormalImpacts(csv, {.where = {"surface_angle_deg=0"}});
  ASSERT_EQ(groups.size(), 2u);
  ASSERT_EQ(groups.at("steel").size(), 2u);
  EXPECT_EQ(groups.at("steel")[1].v_before_m_s, 2.0);  // the sign is ignored
  EXPECT_EQ(groups.at("concrete")[0].v_after_m_s, 1.2);
  // Two words are not equal because strtod reads both as 0.
  const auto steel = ReadNormalImpacts(csv, {.where = {"surface=steel", "surface_angle_deg=0"}});
  EXPECT_EQ(steel.size(), 1u);
  EXPECT_FALSE(hoof::study::SameValue("steel", "concrete"));
  EXPECT_TRUE(hoof::study::SameValue("0", "0.0"));
}

TEST(NormalImpactsTest, BadInputIsNamedWithTheFileAndTheLine) {
  const std::string csv = WriteCsv("t.csv", kTable);
  // The 20 deg row's rebound is not a number: line 5.
  hoof::testing::ExpectErrorContaining([&] { ReadNormalImpacts(csv, {}); }, csv + ":5");
  EXPECT_THROW(ReadNormalImpacts(csv, {.where = {"surface"}}), std::invalid_argument);
  hoof::testing::ExpectErrorContaining(
      [&] { ReadNormalImpacts(csv, {.where = {"surface=asphalt"}}); },
      "no data rows (after --where)");
  const std::string swapped =
      WriteCsv("swapped.csv", "v_before_m_s,v_after_m_s\n1.5,3.0\n2.0,1.0\n1.0,2.5\n");
  hoof::testing::ExpectErrorContaining([&] { ReadNormalImpacts(swapped, {}); },
                                       "> 1 in 2 row(s), on line(s) 2, 4");
}

TEST(NormalImpactsTest, TheValleyCsvHasTheGridAndTheValleyWithTheirDampingRatio) {
  hoof::dynamics::ContactFitSummary s;
  s.map_k_N_m = {1e7, 1e8};
  s.map_b_N_s_m = {100.0};
  s.map_mpe_percent = Eigen::MatrixXd::Constant(2, 1, 3.0);
  s.valley.push_back({});
  s.valley.back().k_N_m = 1e8;
  s.valley.back().b_N_s_m = 100.0;
  s.valley.back().zeta = 0.25;
  s.valley.back().mpe_percent = 1.0;
  const double mass = 0.25;
  const std::string csv = hoof::study::ValleyCsv({{"steel", s}}, mass);
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "group,k_N_m,b_N_s_m,zeta,mpe_percent,on_valley");
  std::getline(in, line);  // k = 1e7, b = 100: zeta = b / (2 sqrt(k m))
  const double zeta = 100.0 / (2 * std::sqrt(1e7 * mass));
  std::istringstream row(line);
  std::string group, k, b, z;
  std::getline(row, group, ',');
  std::getline(row, k, ',');
  std::getline(row, b, ',');
  std::getline(row, z, ',');
  EXPECT_EQ(group, "steel");
  EXPECT_NEAR(std::stod(z), zeta, 1e-12 * zeta);
  std::getline(in, line);
  std::getline(in, line);  // the valley point
  EXPECT_EQ(line.substr(line.size() - 2), ",1");
  EXPECT_FALSE(std::getline(in, line));
}

}  // namespace
