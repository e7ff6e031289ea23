// `hoofimpact run` on sample_frames/ writes the same study file as the program did before the
// study job moved into its library (hoof::study): every dataset and attribute is compared with
// tests/data/run_sample_frames.digest, which that earlier program wrote. It was written anew
// five times since, each for one deliberate change: mu_eff of the normal trial (and its s.e.
// and interval) became NaN, as it is not defined there (docs/tracking.md); the table /impacts
// (one row per impact, docs/hdf5-schema.md) was added, with nothing outside it changed;
// /impacts gained the columns of how each impact was measured and what limited it (method,
// impact_time_se_s to meeting_gap_se_m), with nothing else changed; and each trial's own
// specimen and body model, the specimen's shape and inertia rule, the centre of mass's columns
// of /comparison/frames, mass_known and inertia_assumed were added, with three descriptions
// that now say NaN means an unknown mass, and no number changed; and /impacts gained
// e_perspective_shift, the change of e by the rectification of a slanted view, with nothing
// else changed. Numbers
// agree to 1e-9 relative (the same computation; the last bits may differ between CPUs), texts
// exactly. Only what names the moment and the place of the run is left out (see Varies), and the
// source folder in a text is written as <source>, so that a checkout anywhere compares.
//
// To write the digest anew after a deliberate change of the study file:
//   HOOF_WRITE_GOLDEN=1 build/tests/cli/run_golden_test
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/h5_digest.h"
#include "support/run_command.h"
#include "support/test_util.h"

namespace {

namespace fs = std::filesystem;

const fs::path kGolden = fs::path(HOOF_SOURCE_DIR) / "tests/data/run_sample_frames.digest";

/// Keys that differ from run to run by design: the time, the program's version, the paths.
bool Varies(const std::string& key) {
  for (const char* v : {"/@created_utc", "/@command_line", "/@study_dir", "/@hoofimpact_version"})
    if (key == v) return true;
  // Each trial's folder (absolute) and its analysis time, in /results and /trials/<id>/metadata.
  for (const char* v : {"/dir", "/analysis_seconds"})
    if (key.ends_with(v) || key.find(std::string(v) + "@") != std::string::npos) return true;
  return false;
}

/// `text` with every mention of the source folder written as <source>.
std::string Portable(std::string text) {
  const std::string source = HOOF_SOURCE_DIR;
  for (std::size_t at = 0; (at = text.find(source, at)) != std::string::npos;)
    text.replace(at, source.size(), "<source>");
  return text;
}

std::map<std::string, std::vector<std::string>> ParseDigest(const std::string& text) {
  std::map<std::string, std::vector<std::string>> out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::size_t start = 0;
    for (std::size_t tab; (tab = line.find('\t', start)) != std::string::npos; start = tab + 1)
      fields.push_back(line.substr(start, tab - start));
    fields.push_back(line.substr(start));
    const std::string key = fields.front();
    fields.erase(fields.begin());
    if (!Varies(key)) out[key] = fields;
  }
  return out;
}

TEST(RunGoldenTest, SampleFramesGiveTheSameStudyFileAsBefore) {
  const fs::path out = hoof::testing::FreshDir("run_golden");
  const auto r = hoof::testing::RunHoofimpact("run " + std::string(HOOF_SOURCE_DIR) +
                                              "/sample_frames -o " + out.string() + " --jobs 2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string text =
      Portable(hoof::testing::DigestText(hoof::testing::DigestHdf5((out / "study.h5").string())));
  ASSERT_FALSE(text.empty());
  if (std::getenv("HOOF_WRITE_GOLDEN")) {
    std::ofstream(kGolden) << text;
    GTEST_SKIP() << "wrote " << kGolden;
  }
  std::ifstream in(kGolden);
  ASSERT_TRUE(in) << kGolden;
  std::stringstream golden_text;
  golden_text << in.rdbuf();
  const auto golden = ParseDigest(golden_text.str());
  const auto now = ParseDigest(text);
  ASSERT_GT(golden.size(), 100u);
  for (const auto& [key, want] : golden) {
    const auto it = now.find(key);
    if (it == now.end()) {
      ADD_FAILURE() << key << ": no longer in the study file";
      continue;
    }
    const auto& got = it->second;
    if (got.size() != want.size() || got.front() != want.front()) {
      ADD_FAILURE() << key << ": " << got.size() - 1 << " values of kind " << got.front()
                    << ", before " << want.size() - 1 << " of kind " << want.front();
      continue;
    }
    for (std::size_t i = 1; i < want.size(); ++i) {
      if (want.front() == "T") {
        EXPECT_EQ(got[i], want[i]) << key << "[" << i - 1 << "]";
        continue;
      }
      const double a = std::strtod(got[i].c_str(), nullptr),
                   b = std::strtod(want[i].c_str(), nullptr);
      if (std::isnan(a) && std::isnan(b)) continue;
      EXPECT_NEAR(a, b, 1e-9 * std::max(std::abs(a), std::abs(b)) + 1e-12)
          << key << "[" << i - 1 << "]";
    }
  }
  for (const auto& [key, value] : now)
    if (!golden.count(key)) ADD_FAILURE() << key << ": new in the study file";
}

}  // namespace
