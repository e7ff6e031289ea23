#include "io/atomic_file.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "support/test_util.h"

namespace hoof::io {
namespace {

namespace fs = std::filesystem;

using hoof::testing::FreshDir;
using hoof::testing::ReadAll;

TEST(AtomicFileTest, WritesCompleteFileAndLeavesNoTemporary) {
  const fs::path dir = FreshDir("atomic_ok");
  const fs::path target = dir / "sub" / "out.txt";
  WriteTextAtomically(target, "hello\n");
  EXPECT_EQ(ReadAll(target), "hello\n");
  int files = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir)) files += e.is_regular_file();
  EXPECT_EQ(files, 1);
}

TEST(AtomicFileTest, FailureInTheMiddleKeepsTheOldFile) {
  const fs::path dir = FreshDir("atomic_fail");
  const fs::path target = dir / "out.txt";
  WriteTextAtomically(target, "old\n");
  EXPECT_THROW(WriteFileAtomically(target,
                                   [](std::ostream& out) {
                                     out << "half of the new";
                                     throw std::runtime_error("crash while writing");
                                   }),
               std::runtime_error);
  EXPECT_EQ(ReadAll(target), "old\n");
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
  EXPECT_EQ(files, 1);  // the temporary is gone
}

TEST(AtomicFileTest, AFolderInPlaceOfTheFileIsNamedAndKept) {
  const fs::path dir = FreshDir("atomic_folder");
  fs::create_directories(dir / "out" / "inside");
  hoof::testing::ExpectErrorContaining([&] { WriteTextAtomically(dir / "out", "x"); },
                                       (dir / "out").string() + ": it is a folder");
  EXPECT_TRUE(fs::is_directory(dir / "out" / "inside"));
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
  EXPECT_EQ(files, 0);  // no temporary left
}

// What a killed process left goes; a live process's temporaries and every other name stay.
TEST(AtomicFileTest, StaleTemporariesOfDeadProcessesAreRemoved) {
  const fs::path dir = FreshDir("atomic_stale");
  // A process id that no longer runs: a child that has exited and been reaped.
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ASSERT_GT(child, 0);
  ::waitpid(child, nullptr, 0);
  const std::string dead = std::to_string(child), live = std::to_string(::getppid());
  for (const std::string& name :
       {"study.h5.tmp-" + dead + "-0", "plot.png.tmp-" + dead + "-3.gp", ".t1.tmp-" + dead + "-2",
        "study.h5.tmp-" + live + "-0", std::string("notes.tmp-x"), std::string("data.tmp-12"),
        std::string("study.h5")})
    std::ofstream(dir / name) << "x";
  fs::create_directories(dir / (".frames.tmp-" + dead + "-1") / "inner");
  EXPECT_EQ(RemoveStaleTemporaries(dir), 4);
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(dir)) left.push_back(e.path().filename().string());
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{"data.tmp-12", "notes.tmp-x", "study.h5",
                                            "study.h5.tmp-" + live + "-0"}));
  EXPECT_EQ(RemoveStaleTemporaries(dir / "no-such-folder"), 0);
  // With a filter, only the temporaries it accepts.
  for (const std::string& name : {"study.h5.tmp-" + dead + "-1", "other.h5.tmp-" + dead + "-1"})
    std::ofstream(dir / name) << "x";
  EXPECT_EQ(RemoveStaleTemporaries(
                dir, [](const std::string& name) { return name.rfind("study.h5.tmp-", 0) == 0; }),
            1);
  EXPECT_TRUE(fs::exists(dir / ("other.h5.tmp-" + dead + "-1")));
}

TEST(AtomicFileTest, UnwritableDirectoryNamesThePath) {
  try {
    WriteTextAtomically("/proc/hoofimpact-cannot-write/out.txt", "x");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/proc/hoofimpact-cannot-write"), std::string::npos);
  }
}

}  // namespace
}  // namespace hoof::io
