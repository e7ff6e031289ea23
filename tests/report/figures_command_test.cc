// End-to-end tests of the figure commands: a tiny study is rendered with `hoofimpact synth
// --study`, analysed with `analyze --figures`, and drawn again from the study file alone with
// `hoofimpact figures`, each figure with its data and gnuplot script, which gnuplot runs
// elsewhere to remake it; `track --figures` draws one trial's Figure 3.
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "support/run_command.h"
#include "support/test_studies.h"
#include "support/test_util.h"

namespace hoof::report {
namespace {

namespace fs = std::filesystem;
using hoof::testing::ReadAll;
using hoof::testing::RunHoofimpact;

const char* const kStudyFigures[] = {"e_by_angle", "e_by_speed", "mu_eff_by_angle",
                                     "mu_eff_by_speed"};

fs::path Root() {
  return fs::path(HOOF_BINARY_DIR) / "figures_command_test" / std::to_string(::getpid());
}

/// A readable PNG with content (curves and text give many grey levels).
void ExpectFigure(const fs::path& png) {
  const cv::Mat image = cv::imread(png.string());
  ASSERT_FALSE(image.empty()) << png;
  cv::Scalar mean, sd;
  cv::meanStdDev(image, mean, sd);
  EXPECT_GT(sd[0], 10.0) << png;
}

/// 2 surfaces x 2 angles x 2 speeds x 2 repetitions = 16 short trials, analysed once.
class FiguresCommandTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    fs::remove_all(Root());
    fs::create_directories(Root());
    const auto a = RunHoofimpact("analyze " + hoof::testing::TestStudyDir("figures_16").string() +
                                 " -o " + StudyFile().string() + " --jobs 2 --figures " +
                                 (Root() / "analyze_figures").string());
    ASSERT_EQ(a.exit_code, 0) << a.out << a.err;
  }
  static void TearDownTestSuite() { fs::remove_all(Root()); }
  static fs::path StudyFile() { return Root() / "f.h5"; }
};

TEST_F(FiguresCommandTest, AnalyzeWritesTheStudyFiguresButNoTrialFigureByDefault) {
  const fs::path dir = Root() / "analyze_figures";
  for (const char* name : kStudyFigures) {
    ExpectFigure(dir / (std::string(name) + ".png"));
    EXPECT_TRUE(fs::is_regular_file(dir / (std::string(name) + ".svg"))) << name;
  }
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find("_displacement"), std::string::npos) << e.path();
}

TEST_F(FiguresCommandTest, FiguresDrawsTheStudyFiguresFromTheFileAlone) {
  const fs::path dir = Root() / "figures";
  const auto r = RunHoofimpact("figures " + StudyFile().string() + " -o " + dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::set<std::string> files;
  for (const auto& e : fs::directory_iterator(dir)) files.insert(e.path().filename().string());
  std::set<std::string> want;  // four figures, each PNG, SVG, CSV and script; nothing temporary
  for (const char* name : kStudyFigures)
    for (const char* ext : {".png", ".svg", ".csv", ".gp"}) want.insert(name + std::string(ext));
  EXPECT_EQ(files, want);
  for (const char* name : kStudyFigures) {
    ExpectFigure(dir / (std::string(name) + ".png"));
    EXPECT_NE(r.out.find(name), std::string::npos) << r.out;
  }
  EXPECT_NE(ReadAll(dir / "e_by_speed.svg").find("Coefficient of restitution by nominal speed"),
            std::string::npos);
  EXPECT_NE(ReadAll(dir / "mu_eff_by_angle.svg").find("steel"), std::string::npos);
}

// The check: `gnuplot` remakes a figure from its shipped script and data, in a folder of
// its own (the script names its files relative to where it runs).
TEST_F(FiguresCommandTest, GnuplotRemakesAShippedFigureElsewhere) {
  const fs::path dir = Root() / "shipped";
  ASSERT_EQ(RunHoofimpact("figures " + StudyFile().string() + " -o " + dir.string()).exit_code, 0);
  const fs::path again = Root() / "remade";
  fs::create_directories(again);
  for (const char* ext : {".gp", ".csv"})
    fs::copy_file(dir / ("e_by_angle" + std::string(ext)),
                  again / ("e_by_angle" + std::string(ext)));
  const std::string command = "cd '" + again.string() + "' && gnuplot e_by_angle.gp";
  ASSERT_EQ(std::system(command.c_str()), 0);
  EXPECT_EQ(ReadAll(again / "e_by_angle.svg"), ReadAll(dir / "e_by_angle.svg"));
  ExpectFigure(again / "e_by_angle.png");
  // The bars are ±1 s.e., and the caption says so.
  EXPECT_NE(ReadAll(dir / "e_by_angle.svg").find("mean ± 1 s.e. of the mean"), std::string::npos);
}

TEST_F(FiguresCommandTest, MissingStudyFileFailsNamingIt) {
  const fs::path missing = Root() / "no_such.h5";
  const auto r = RunHoofimpact("figures " + missing.string() + " -o " + (Root() / "x").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(missing.string()), std::string::npos) << r.err;
}

TEST_F(FiguresCommandTest, TrackWritesFigureThree) {
  const fs::path dir = Root() / "track_figures";
  const std::string trial = "steel_20deg_v3.00_r1";
  const auto r =
      RunHoofimpact("track " + (hoof::testing::TestStudyDir("figures_16") / trial).string() +
                    " --figures " + dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ExpectFigure(dir / (trial + "_displacement.png"));
  EXPECT_NE(
      ReadAll(dir / (trial + "_displacement.svg")).find(trial + ": steel, surface angle 20.0°"),
      std::string::npos);
}

}  // namespace
}  // namespace hoof::report
