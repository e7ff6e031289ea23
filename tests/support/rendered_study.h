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
/// build: it is test-output/studies/NAME-HASH, where HASH is of the options and of the program's
/// bytes, so that changed options or a rebuilt renderer render anew instead of reusing frames an
/// older renderer drew under the same name. Folders of NAME made by other builds are removed.
/// ctest runs tests as parallel processes: each renders into a folder of its own and renames it
/// into place, and whoever renames second keeps the first one's study.
inline std::filesystem::path RenderedStudy(const std::string& name, const std::string& options) {
  namespace fs = std::filesystem;
  std::ostringstream key;
  key << std::hex << std::setw(16) << std::setfill('0') << Fnv1a(options, ProgramHash());
  const fs::path root = fs::path(HOOF_BINARY_DIR) / "test-output" / "studies";
  const fs::path dir = root / (name + "-" + key.str());
  if (fs::exists(dir / "study.json")) return dir;
  std::error_code ec;
  fs::create_directories(root, ec);
  for (const auto& entry : fs::directory_iterator(root, ec)) {
    const std::string other = entry.path().filename().string();
    // NAME-<16 hex digits>, and not this build's: a study an older renderer drew.
    if (other.size() == name.size() + 17 && other.rfind(name + "-", 0) == 0 && entry.path() != dir)
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
