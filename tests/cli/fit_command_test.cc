// End-to-end tests of `hoofimpact fit` on normal impacts simulated with a known contact law.
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "dynamics/impact_simulator.h"
#include "io/csv.h"
#include "support/run_command.h"

namespace hoof::cli {
namespace {

using hoof::testing::RunHoofimpact;

struct Group {
  std::string surface;
  double k = 0.0, zeta = 0.0;
};

/// Normal impacts at six speeds per group, each simulated with its group's contact law.
std::string WriteGroups(const std::string& name, const std::vector<Group>& groups) {
  const std::string path = std::string(HOOF_BINARY_DIR) + "/" + name;
  const dynamics::SpecimenParameters specimen;
  std::ofstream out(path);
  out << "surface,v_before_m_s,v_after_m_s\n";
  for (const Group& g : groups) {
    const dynamics::ImpactSimulator sim(
        specimen, {g.k, dynamics::DampingForRatio(g.zeta, g.k, specimen.mass_kg), 0.0});
    for (double v : {1.5, 2.0, 2.5, 3.0, 3.5, 4.0}) {
      const double after =
          sim.Simulate(dynamics::ImpactConditions::Paper(v, 0.0)).at_separation.v_SC.y();
      out << g.surface << "," << io::CsvNumber(v) << "," << io::CsvNumber(after) << "\n";
    }
  }
  return path;
}

std::string WriteImpacts(const std::string& name, double k, double zeta) {
  return WriteGroups(name, {{"asphalt", k, zeta}});
}

TEST(FitCommandTest, ReportsZetaAndThatKIsNotIdentified) {
  const std::string csv = WriteImpacts("fit_cli_impacts.csv", 5.86e7, 0.6009);
  const std::string valley = std::string(HOOF_BINARY_DIR) + "/fit_cli_valley.csv";
  std::filesystem::remove(valley);
  const auto r = RunHoofimpact("fit " + csv + " --json --valley-csv " + valley);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out).at("results").at("groups");
  ASSERT_EQ(j.size(), 1u);
  EXPECT_EQ(j[0]["group"], "asphalt");
  EXPECT_NEAR(j[0]["zeta"].get<double>(), 0.6009, 5e-4);
  EXPECT_FALSE(j[0]["k_identified"].get<bool>());
  EXPECT_NE(j[0]["explanation"].get<std::string>().find("NOT identified"), std::string::npos);
  const io::CsvTable grid = io::CsvTable::Read(valley);
  EXPECT_EQ(grid.rows(), 41u * 41u + 9u);
}

TEST(FitCommandTest, TextOutputShowsTheValleyNotASingleKB) {
  const std::string csv = WriteImpacts("fit_cli_impacts2.csv", 7.24e8, 0.1105);
  const auto r = RunHoofimpact("fit " + csv);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("The valley"), std::string::npos);
  EXPECT_NE(r.out.find("95 % interval"), std::string::npos);
  EXPECT_NE(r.out.find("NOT identified"), std::string::npos);
}

// --where COL=TEXT keeps the rows whose COL is that text: two words are not equal because
// strtod reads both as 0 (it fitted every surface before).
TEST(FitCommandTest, WhereKeepsOnlyTheRowsOfThatText) {
  const std::string csv =
      WriteGroups("fit_cli_where.csv", {{"asphalt", 5.86e7, 0.6009}, {"steel", 7.24e8, 0.1105}});
  auto r = RunHoofimpact("fit " + csv + " --json --where surface=steel");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out).at("results").at("groups");
  ASSERT_EQ(j.size(), 1u) << r.out;
  EXPECT_EQ(j[0]["group"], "steel");
  EXPECT_NEAR(j[0]["zeta"].get<double>(), 0.1105, 5e-4);
  // No word matches a number (strtod reads "steel" as 0 too).
  r = RunHoofimpact("fit " + csv + " --json --where surface=0");
  EXPECT_NE(r.exit_code, 0) << r.out;
  EXPECT_NE(r.err.find("no data rows (after --where)"), std::string::npos) << r.err;
}

TEST(FitCommandTest, MissingColumnAndBadValuesAreNamed) {
  const std::string path = std::string(HOOF_BINARY_DIR) + "/fit_cli_bad.csv";
  {
    std::ofstream out(path);
    out << "v_before_m_s,rebound\n3.0,2.5\n";
  }
  auto r = RunHoofimpact("fit " + path);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("v_after_m_s"), std::string::npos) << r.err;
  {
    std::ofstream out(path);
    out << "v_before_m_s,v_after_m_s\n3.0,2.5\n3.0,abc\n";
  }
  r = RunHoofimpact("fit " + path);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(":3:"), std::string::npos) << r.err;
  // A rebound faster than the approach is named by its line, not by an internal parameter.
  {
    std::ofstream out(path);
    out << "v_before_m_s,v_after_m_s\n3.0,2.5\n2.0,2.4\n3.0,1.0\n";
  }
  r = RunHoofimpact("fit " + path);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("e = v_after_m_s / v_before_m_s > 1 in 1 row(s), on line(s) 3"),
            std::string::npos)
      << r.err;
  r = RunHoofimpact("fit /nonexistent.csv");
  EXPECT_EQ(r.exit_code, 2);  // CLI11 checks that the file exists
}

}  // namespace
}  // namespace hoof::cli
