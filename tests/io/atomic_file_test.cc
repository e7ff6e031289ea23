#include "io/atomic_file.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

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
