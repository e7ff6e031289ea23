#pragma once
/// @file
/// Studies that tests render with `hoofimpact synth --study`, once per build of the program.

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>
#include <system_error>

#include <gtest/gtest.h>

#include "support/run_command.h"

namespace hoof::testing {

/// FNV-1a (64 bit) of `bytes`, continuing from `h`.
inline std::uint64_t Fnv1a(std::string_view bytes, std::uint64_t h = 14695981039346656037ULL) {
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ULL;
  return h;
}

/// A hash of the program's bytes: a rebuilt renderer has another.
inline std::uint64_t ProgramHash() {
  static const std::uint64_t hash = [] {
    std::ifstream in(HOOF_CLI_PATH, std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    return Fnv1a(bytes.str());
  }();
  return hash;
}

/// The folder of a study rendered by `hoofimpact synth --study -o DIR OPTIONS`, made once per
/// build: it is test-output/studies/NAME-OOOOOOOOPPPPPPPP, where O is a hash of the options and P
/// one of the program's bytes, so that changed options or a rebuilt renderer render anew instead
/// of reusing frames an older renderer drew under the same name. Folders of NAME that another
/// build made (another P) are removed; those of this build with other options are kept, as a
/// test running beside this one may be reading them (two tests once gave one NAME options that
/// differed in their spelling, 1000 and 1000.000000, and each removed the other's frames).
/// ctest runs tests as parallel processes: each renders into a folder of its own and renames it
/// into place, and whoever renames second keeps the first one's study.
inline std::filesystem::path RenderedStudy(const std::string& name, const std::string& options) {
  namespace fs = std::filesystem;
  const auto hex8 = [](std::uint64_t h) {
    std::ostringstream os;
    os << std::hex << std::setw(8) << std::setfill('0') << ((h ^ (h >> 32)) & 0xffffffffULL);
    return os.str();
  };
  const std::string program = hex8(ProgramHash());
  const std::string key = hex8(Fnv1a(options)) + program;
  const fs::path root = fs::path(HOOF_BINARY_DIR) / "test-output" / "studies";
  const fs::path dir = root / (name + "-" + key);
  if (fs::exists(dir / "study.json")) return dir;
  std::error_code ec;
  fs::create_directories(root, ec);
  for (const auto& entry : fs::directory_iterator(root, ec)) {
    const std::string other = entry.path().filename().string();
    // NAME-<16 hex digits> whose last 8 are not this build's: a study an older renderer drew.
    if (other.size() == name.size() + 17 && other.rfind(name + "-", 0) == 0 &&
        other.compare(name.size() + 9, 8, program) != 0)
      fs::remove_all(entry.path(), ec);
    // NAME-HASH.tmp-PID of a test process that was killed (a timeout) while rendering.
    const std::size_t at = other.rfind(".tmp-");
    if (other.rfind(name + "-", 0) == 0 && at == name.size() + 17) {
      const long pid = std::strtol(other.c_str() + at + 5, nullptr, 10);
      if (pid > 0 && ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH)
        fs::remove_all(entry.path(), ec);
    }
  }
  const fs::path tmp = dir.string() + ".tmp-" + std::to_string(::getpid());
  fs::remove_all(tmp, ec);
  const auto r = RunHoofimpact("synth --study -o " + tmp.string() + " " + options);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  if (r.exit_code != 0) {  // nothing half made takes the study's place
    fs::remove_all(tmp, ec);
    return dir;
  }
  fs::rename(tmp, dir, ec);
  if (ec) fs::remove_all(tmp, ec);
  return dir;
}

}  // namespace hoof::testing
