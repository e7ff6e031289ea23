/// libFuzzer target: study.json (pipeline::ReadStudy). Any input is either read or rejected
/// with a std::exception whose message names the file; anything else is a finding.
#include <exception>

#include "fuzz/fuzz_files.h"
#include "pipeline/study_format.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path dir = hoof::fuzz::Scratch() / "study";
  const std::filesystem::path file = dir / "study.json";
  hoof::fuzz::WriteFile(file, data, size);
  try {
    const hoof::pipeline::StudySpec study = hoof::pipeline::ReadStudy(dir);
    for (const auto& w : study.warnings) hoof::fuzz::RequireNamed(w, file.string());
  } catch (const std::exception& e) {
    hoof::fuzz::RequireNamed(e.what(), file.string());
  }
  return 0;
}
