// `hoofimpact run` end to end on a small rendered study without per-trial scatter, where the
// fitted model is the truth and every trial must agree with its simulation.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

#include "studyfile/study_file.h"
#include "support/run_command.h"
#include "support/test_studies.h"

namespace hoof::cli {
namespace {

namespace fs = std::filesystem;
using hoof::testing::RunHoofimpact;

TEST(RunCommandTest, TheWholeStudyEndToEnd) {
  const fs::path base =
      fs::path(HOOF_BINARY_DIR) / "test-output" / ("run_" + std::to_string(::getpid()));
  fs::remove_all(base);
  const fs::path study = hoof::testing::TestStudyDir("run_16");
  auto r = RunHoofimpact("run " + study.string() + " -o " + (base / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("16 measured, 0 failed"), std::string::npos) << r.out;
  const fs::path h5 = base / "out" / "study.h5";
  // The comparison: every trial agrees with the simulation of the fitted (true) model within
  // three combined standard errors.
  const auto trials = studyfile::ReadTable(h5, "/comparison/trials");
  for (const char* z : {"z_v_x", "z_v_y", "z_w"})
    for (double v : std::get<std::vector<double>>(trials.Get(z).values))
      EXPECT_LT(std::abs(v), 3.0) << z;
  // Each trial on the scale of its prediction interval (/prediction): 16 trials, none beyond 3
  // where the model is the truth, and the report's Trials table says how many are.
  const auto predicted = studyfile::ReadTable(h5, "/prediction/trials");
  EXPECT_EQ(predicted.Get("id").size(), 16u);
  int prediction_components = 0;
  for (const char* z : {"z_v_x", "z_v_y", "z_w"})
    for (double v : std::get<std::vector<double>>(predicted.Get(z).values))
      if (std::isfinite(v)) {
        ++prediction_components;
        EXPECT_LT(std::abs(v), 3.0) << z;
      }
  EXPECT_EQ(prediction_components, 8 * 1 + 8 * 3);  // v_y of the normal trials; all of the oblique
  {
    std::ifstream in(base / "out" / "report.html");
    const std::string page((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(page.find("<p id=\"prediction-z-count\">0 of " +
                        std::to_string(prediction_components) + " trial components"),
              std::string::npos);
    EXPECT_NE(page.find("precision-only z"), std::string::npos);
  }
  // Statistics stored, CSVs and figures written.
  EXPECT_NO_THROW(studyfile::ReadTable(h5, "/stats/e/by_surface/anova"));
  EXPECT_TRUE(fs::exists(base / "out" / "results.csv"));
  EXPECT_TRUE(fs::exists(base / "out" / "stats.csv"));
  EXPECT_TRUE(fs::exists(base / "out" / "figures" / "e_by_angle.png"));
  EXPECT_TRUE(fs::exists(base / "out" / "figures" / "mu_eff_by_angle.svg"));
  EXPECT_GT(fs::file_size(base / "out" / "report.html"), 10000u);
  // The paper's Figures 6-8: velocities after normal and oblique impacts, and energy.
  EXPECT_TRUE(fs::exists(base / "out" / "figures" / "velocity_normal.png"));
  EXPECT_TRUE(fs::exists(base / "out" / "figures" / "velocity_oblique.svg"));
  int energy = 0;
  for (const auto& e : fs::directory_iterator(base / "out" / "figures"))
    energy +=
        e.path().filename().string().rfind("energy_", 0) == 0 && e.path().extension() == ".png";
  EXPECT_EQ(energy, 2);  // one oblique trial per surface
  // Units written properly: the energy figures' time axis is in µs (the SVG holds the UTF-8 text).
  for (const auto& e : fs::directory_iterator(base / "out" / "figures"))
    if (e.path().filename().string().rfind("energy_", 0) == 0 && e.path().extension() == ".svg") {
      std::ifstream in(e.path());
      const std::string svg((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      EXPECT_NE(svg.find("time since first touch (µs)"), std::string::npos) << e.path();
    }
  EXPECT_NE(r.out.find("report.html"), std::string::npos);
  fs::remove_all(base);
}

TEST(RunCommandTest, AMissingStudyIsAClearError) {
  const auto r = RunHoofimpact("run /nonexistent-study-folder");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("nonexistent-study-folder"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace hoof::cli
