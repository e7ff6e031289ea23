#pragma once
/// @file
/// Shared by the libFuzzer targets of tests/fuzz: a scratch folder of this process, a file
/// written into it, and the rule every parser error must keep (it names the file it read).

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

namespace hoof::fuzz {

/// A folder of this process under $TMPDIR (or /tmp), made once and reused for every input.
inline const std::filesystem::path& Scratch() {
  static const std::filesystem::path dir = [] {
    const char* tmp = std::getenv("TMPDIR");
    std::filesystem::path d = std::filesystem::path(tmp && *tmp ? tmp : "/tmp") /
                              ("hoofimpact-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

/// Writes `size` bytes at `data` to `path` (replacing it).
inline void WriteFile(const std::filesystem::path& path, const std::uint8_t* data,
                      std::size_t size) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
}

/// The rule of the input boundary (docs/testing.md, "Fuzzing"): a rejected input's message names
/// the file. A message that does not is a finding, so it aborts with the message.
inline void RequireNamed(std::string_view message, const std::string& file) {
  if (message.find(file) == std::string_view::npos) {
    std::fprintf(stderr, "error message does not name %s:\n%.*s\n", file.c_str(),
                 static_cast<int>(message.size()), message.data());
    std::abort();
  }
}

}  // namespace hoof::fuzz
