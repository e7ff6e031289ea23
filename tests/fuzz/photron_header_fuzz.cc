/// libFuzzer target: a Photron camera header (tracking::ParsePhotronHeader), XML .cihx or text
/// .cih. Any input is either read, with sizes a reader can trust, or rejected with a
/// std::exception whose message names the file; anything else is a finding.
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <string>
#include <string_view>

#include "fuzz/fuzz_files.h"
#include "tracking/camera_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string name = "fuzz.cihx";
  try {
    const hoof::tracking::PhotronHeader h = hoof::tracking::ParsePhotronHeader(
        std::string_view(reinterpret_cast<const char*>(data), size), name);
    // What the reader relies on before it allocates a frame.
    if (h.width < 1 || h.height < 1 || h.width > 65536 || h.height > 65536 ||
        static_cast<std::int64_t>(h.width) * h.height > (std::int64_t{1} << 30) ||
        h.frame_count < 1 || !(h.fps > 0) ||
        (h.color_bit != 8 && h.color_bit != 12 && h.color_bit != 16))
      std::abort();
  } catch (const std::exception& e) {
    hoof::fuzz::RequireNamed(e.what(), name);
  }
  return 0;
}
