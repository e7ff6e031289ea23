// `hoofimpact discover` at its edges: help, bad settings and files that are not study files.
// (The workflow on rendered studies is tested in tests/discovery.)
#include <hdf5.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "support/run_command.h"
#include "support/test_util.h"

namespace hoof::cli {
namespace {

namespace fs = std::filesystem;
using hoof::testing::FreshDir;
using hoof::testing::RunHoofimpact;

/// An HDF5 file with nothing in it (not a study file).
fs::path EmptyHdf5(const fs::path& path) {
  const hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (f >= 0) H5Fclose(f);
  return path;
}

TEST(DiscoverCommandTest, HelpListsTheOptions) {
  const auto r = RunHoofimpact("discover --help");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  for (const char* option :
       {"--alpha", "--folds", "--rounds", "--jobs", "--candidates", "--measurement-floor",
        "--shared-only", "--figures", "--report", "--json"})
    EXPECT_NE(r.out.find(option), std::string::npos) << option << "\n" << r.out;
  // And `run` offers the step.
  const auto run = RunHoofimpact("run --help");
  EXPECT_NE(run.out.find("--discover"), std::string::npos) << run.out;
}

TEST(DiscoverCommandTest, AMissingFileIsNamed) {
  const auto r = RunHoofimpact("discover /nonexistent-folder/study.h5");
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_NE(r.err.find("/nonexistent-folder/study.h5"), std::string::npos) << r.err;
}

TEST(DiscoverCommandTest, AFileThatIsNotHdf5IsNamed) {
  const fs::path dir = FreshDir("discover_command_test/text");
  const fs::path bogus = dir / "notes.h5";
  std::ofstream(bogus) << "this is not an HDF5 file\n";
  const auto r = RunHoofimpact("discover " + bogus.string());
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_NE(r.err.find(bogus.string() + " is not an HDF5 file"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "figures"));
}

TEST(DiscoverCommandTest, AnHdf5FileThatIsNotAStudyFileIsNamed) {
  const fs::path dir = FreshDir("discover_command_test/empty_h5");
  const fs::path h5 = EmptyHdf5(dir / "empty.h5");
  ASSERT_TRUE(fs::exists(h5));
  const auto r = RunHoofimpact("discover " + h5.string());
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_NE(r.err.find(h5.string()), std::string::npos) << r.err;
}

TEST(DiscoverCommandTest, TheInputIsNeverTheOutput) {
  const fs::path dir = FreshDir("discover_command_test/same");
  const fs::path h5 = EmptyHdf5(dir / "study.h5");
  ASSERT_TRUE(fs::exists(h5));
  const auto bytes = fs::file_size(h5);
  for (const std::string& same : {h5.string(), (dir / "." / "study.h5").string()}) {
    const auto r = RunHoofimpact("discover " + h5.string() + " -o " + same);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("is the input study file"), std::string::npos) << r.err;
  }
  const auto r = RunHoofimpact("discover " + h5.string() + " -o " + dir.string());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("is a folder"), std::string::npos) << r.err;
  EXPECT_EQ(fs::file_size(h5), bytes);
  // A study file discovery cannot run on writes nothing: no copy, no figures.
  const auto bad = RunHoofimpact("discover " + h5.string());
  EXPECT_EQ(bad.exit_code, 1) << bad.err;
  EXPECT_FALSE(fs::exists(dir / "study-discovery.h5"));
  EXPECT_FALSE(fs::exists(dir / "figures"));
}

TEST(DiscoverCommandTest, BadSettingsAreACommandLineError) {
  auto r = RunHoofimpact("discover /nonexistent-folder/study.h5 --folds 1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--folds"), std::string::npos) << r.err;
  r = RunHoofimpact("discover /nonexistent-folder/study.h5 --alpha 0.7");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--alpha"), std::string::npos) << r.err;
  r = RunHoofimpact("discover /nonexistent-folder/study.h5 --plan hunt_crossley");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--plan"), std::string::npos) << r.err;
  r = RunHoofimpact("discover /nonexistent-folder/study.h5 --plan hunt_crossley=2e7x");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--plan"), std::string::npos) << r.err;
  r = RunHoofimpact("discover /nonexistent-folder/study.h5 --measurement-floor 0.2");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--measurement-floor"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace hoof::cli
