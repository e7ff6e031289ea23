/// libFuzzer target: trial.json (pipeline::ReadTrial) beside a fixed, valid study.json with
/// one specimen "S1". Any input is either read or rejected with a std::exception whose message
/// names the file; anything else is a finding.
#include <exception>
#include <string>

#include "fuzz/fuzz_files.h"
#include "pipeline/study_format.h"

namespace {

const hoof::pipeline::StudySpec& Study() {
  static const hoof::pipeline::StudySpec study = [] {
    const std::filesystem::path dir = hoof::fuzz::Scratch() / "study";
    const std::string text = R"({"format": "hoofimpact-study/1", "name": "fuzz",
      "specimens": {"S1": {"mass_kg": 0.2, "inertia_kg_m2": 3e-4, "end_radius_m": 0.02,
        "d_EC_m": 0.06, "markers_B_m": {"m1": [0.02, 0.0], "m2": [0.08, 0.0]}}}})";
    hoof::fuzz::WriteFile(dir / "study.json", reinterpret_cast<const std::uint8_t*>(text.data()),
                          text.size());
    return hoof::pipeline::ReadStudy(dir);
  }();
  return study;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const hoof::pipeline::StudySpec& study = Study();
  const std::filesystem::path trial = study.dir / "t";
  const std::filesystem::path file = trial / "trial.json";
  hoof::fuzz::WriteFile(file, data, size);
  try {
    const hoof::pipeline::TrialSpec spec = hoof::pipeline::ReadTrial(trial, study);
    for (const auto& w : spec.warnings) hoof::fuzz::RequireNamed(w, file.string());
  } catch (const std::exception& e) {
    hoof::fuzz::RequireNamed(e.what(), file.string());
  }
  return 0;
}
