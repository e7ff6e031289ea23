#pragma once
/// @file
/// Studies that tests render with `hoofimpact synth --study`, once per version of the renderer.

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>

#include <algorithm>
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

/// The renderer's version: a hash of what `hoofimpact synth` is built from (HOOF_RENDERER_FILES:
/// the libraries it renders with, as deterministic archives, and the command's own sources) and
/// of the OpenCV that writes its frames. A change elsewhere in the program (discovery, say)
/// leaves it, so the tests' studies are not rendered again; a changed renderer has another.
inline std::uint64_t RendererHash() {
  static const std::uint64_t hash = [] {
    std::uint64_t h = Fnv1a(std::string("opencv ") + HOOF_RENDERER_OPENCV);
    const std::string files = HOOF_RENDERER_FILES;
    for (std::size_t start = 0; start <= files.size();) {
      const std::size_t bar = std::min(files.find('|', start), files.size());
      const std::string path = files.substr(start, bar - start);
      std::ifstream in(path, std::ios::binary);
      std::ostringstream bytes;
      bytes << in.rdbuf();
      h = Fnv1a(bytes.str(), Fnv1a(path + (in ? "" : " (missing)"), h));
      start = bar + 1;
    }
    return h;
  }();
  return hash;
}

/// A study the tests render: its name, the options of `hoofimpact synth --study` and, where the
/// design is a list of cells, the study config (JSON) it is rendered from with --study-config.
/// Each test folder lists its studies in one catalog (tests/support/test_studies.h,
/// tests/discovery/discovery_studies.h), which a CTest fixture renders before the tests that read
/// them run (tests/support/render_studies.h).
struct TestStudy {
  std::string name;
  std::string options;
  std::string config;  // JSON, or empty

  bool operator==(const TestStudy&) const = default;
};

/// ctest's and gtest's name of a study: its name.
inline void PrintTo(const TestStudy& s, std::ostream* os) { *os << s.name; }

/// The folder of `study`, rendered by `hoofimpact synth --study -o DIR OPTIONS` (with
/// `--study-config` of its config, written beside the folder while it renders) once per renderer:
/// it is test-output/studies/NAME-OOOOOOOOPPPPPPPP, where O is a hash of the options (and of the
/// config, where there is one) and P the renderer's version (RendererHash), so that changed options
/// or a changed renderer render anew instead of reusing frames an older renderer drew under the
/// same name. Folders of NAME that another build made (another P) are removed; those of this build
/// with other options are kept, as a test running beside this one may be reading them (two tests
/// once gave one NAME options that differed in their spelling, 1000 and 1000.000000, and each
/// removed the other's frames). ctest runs tests as parallel processes: each renders into a folder
/// of its own and renames it into place, and whoever renames second keeps the first one's study.
inline std::filesystem::path RenderedStudy(const TestStudy& study) {
  namespace fs = std::filesystem;
  const auto hex8 = [](std::uint64_t h) {
    std::ostringstream os;
    os << std::hex << std::setw(8) << std::setfill('0') << ((h ^ (h >> 32)) & 0xffffffffULL);
    return os.str();
  };
  const std::string renderer = hex8(RendererHash());
  const std::string& name = study.name;
  const std::uint64_t options = Fnv1a(study.options);
  const std::string key =
      hex8(study.config.empty() ? options : Fnv1a(study.config, options)) + renderer;
  const fs::path root = fs::path(HOOF_BINARY_DIR) / "test-output" / "studies";
  const fs::path dir = root / (name + "-" + key);
  if (fs::exists(dir / "study.json")) return dir;
  std::error_code ec;
  fs::create_directories(root, ec);
  for (const auto& entry : fs::directory_iterator(root, ec)) {
    const std::string other = entry.path().filename().string();
    // NAME-<16 hex digits> whose last 8 are not this renderer's: a study an older one drew.
    if (other.size() == name.size() + 17 && other.rfind(name + "-", 0) == 0 &&
        other.compare(name.size() + 9, 8, renderer) != 0)
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
  std::string config_option;
  const fs::path config = tmp.string() + ".json";
  if (!study.config.empty()) {
    std::ofstream(config) << study.config;
    config_option = " --study-config " + config.string();
  }
  const auto r =
      RunHoofimpact("synth --study -o " + tmp.string() + config_option + " " + study.options);
  fs::remove(config, ec);
  EXPECT_EQ(r.exit_code, 0) << name << ": " << r.err;
  if (r.exit_code != 0) {  // nothing half made takes the study's place
    fs::remove_all(tmp, ec);
    return dir;
  }
  fs::rename(tmp, dir, ec);
  if (ec) fs::remove_all(tmp, ec);
  return dir;
}

/// The study of `name` rendered with `options` (no study config).
inline std::filesystem::path RenderedStudy(const std::string& name, const std::string& options) {
  return RenderedStudy(TestStudy{name, options, ""});
}

}  // namespace hoof::testing
