/// libFuzzer target: the headers of a Phantom CINE file (tracking::ParseCineLayout), read from
/// the input as if it were the file. Any input is either read, with an offsets table whose
/// images lie within the file, or rejected with a std::exception whose message names the file;
/// anything else (a crash, an allocation beyond the input's size) is a finding.
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>

#include "fuzz/fuzz_files.h"
#include "tracking/camera_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string name = "fuzz.cine";
  const auto read = [&](std::uint64_t offset, std::size_t n, void* out) {
    if (offset > size || n > size - offset) return false;
    std::memcpy(out, data + offset, n);
    return true;
  };
  try {
    const hoof::tracking::CineLayout l = hoof::tracking::ParseCineLayout(read, size, name);
    if (l.offsets.size() != static_cast<std::size_t>(l.info.frame_count) || l.stride < 1 ||
        l.info.width < 1 || l.info.height < 1 || !(l.info.fps > 0))
      std::abort();
    for (const std::uint64_t o : l.offsets)
      if (o > size) std::abort();
  } catch (const std::exception& e) {
    hoof::fuzz::RequireNamed(e.what(), name);
  }
  return 0;
}
