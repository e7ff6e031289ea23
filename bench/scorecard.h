#pragma once
// The discovery scorecard's parts (docs/discovery.md, "Scorecard"): the grid of studies and how
// each is rendered, analysed, cached and discovered (scorecard_study.cc), and the tables it
// prints (scorecard_report.cc). The program is discovery_scorecard.cc.
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "synth/study.h"

namespace scorecard {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// The study designs of the grid.
extern const std::vector<std::string> kDesigns;

/// One hidden effect the scorecard can put into a study.
struct Effect {
  std::string key;            ///< as on the command line and in the output
  std::string flag;           ///< --sizes-<flag>
  std::string unit;           ///< of the size
  std::vector<double> sizes;  ///< default sizes; overridden by --sizes-<flag>
  /// Sets the effect at `size` (SI, or deg/s for the out-of-plane rate).
  std::function<void(hoof::synth::HiddenEffects&, double)> apply;
  /// Library key that names it, or the start of one ("out_of_plane" for the rate); empty for
  /// the null effect, which nothing names correctly.
  std::string library_prefix;
};

/// The keys of the discovery library, in its order.
std::vector<std::string> LibraryKeys();
/// Every effect the scorecard can hide, the null effect first.
std::vector<Effect> AllEffects();
/// Whether the library key `named` names the hidden effect.
bool NamesHidden(const Effect& hidden, const std::string& named);
/// A number as the scorecard prints it.
std::string Num(double v);

/// One study of the grid.
struct StudyPoint {
  std::string design;
  double scatter = 1.0;
  const Effect* effect = nullptr;
  double size = 0.0;
  int seed_index = 0;

  std::string Label() const;
  /// Distinct per (design, scatter, effect, size, seed index), and the same on every run.
  std::uint64_t StudySeed() const;
};

/// The study's design: one of the three layouts, the scatter scale and the hidden effect.
hoof::synth::StudyDesign MakeDesign(const StudyPoint& p);
/// The cache key of a design: everything that goes into its study.
std::string CacheKey(const hoof::synth::StudyDesign& design);
/// The cache file of study `p` with key `key`.
fs::path CacheFile(const fs::path& cache_dir, const StudyPoint& p, const std::string& key);

/// A study's row of the scorecard.
struct Row {
  StudyPoint point;
  std::uint64_t study_seed = 0;
  fs::path cache_file;
  bool from_cache = false;
  int trials = 0;
  int failed_trials = 0;  ///< trials whose analysis failed (cached with the study)
  double render_s = NAN, analyze_s = NAN, discover_s = NAN;
  bool discovered = false;  ///< discovery ran to a verdict
  std::vector<std::string> named;
  std::string stage;  ///< where it failed: "render", "analyze", "cache", "discover"; empty if ok
  std::string error;
  double cache_bytes = NAN;
  double limit = NAN;  ///< the hidden effect's detection limit as discovery printed it
  std::map<std::string, double> limits;  ///< every candidate's, by library key
};

/// Reads a cached study's record; false when the file is missing, unreadable or made for
/// another key (a hash collision or a file from an older format).
bool ReadCacheRecord(const fs::path& file, const std::string& key, Row& row);
/// One study: from the cache, or rendered, analysed and cached; then discovery (unless
/// `only_render`). Errors go into the row, by stage.
Row RunStudy(const StudyPoint& p, const fs::path& cache_dir, int jobs, bool only_render,
             bool verbose);
/// Removes what a killed earlier run left in the cache folder.
void RemoveLeftovers(const fs::path& cache_dir);

/// The scorecard's tables: confusion matrices, power, false and wrong names, times.
void PrintReport(const std::vector<Row>& rows, const std::vector<std::string>& designs,
                 const std::vector<double>& scatters, bool only_render);
/// One study's row as JSON.
nlohmann::json RowJson(const Row& r);

}  // namespace scorecard
