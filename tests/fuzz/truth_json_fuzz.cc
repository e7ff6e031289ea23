/// libFuzzer target: a synthetic trial's truth.json (pipeline::ReadTruth). Any input is either
/// read or rejected with a std::exception whose message names the file; anything else is a
/// finding.
#include <exception>

#include "fuzz/fuzz_files.h"
#include "pipeline/truth_score.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path dir = hoof::fuzz::Scratch() / "truth";
  const std::filesystem::path file = dir / "truth.json";
  hoof::fuzz::WriteFile(file, data, size);
  try {
    (void)hoof::pipeline::ReadTruth(dir);
  } catch (const std::exception& e) {
    hoof::fuzz::RequireNamed(e.what(), file.string());
  }
  return 0;
}
