// The scorecard's grid and its studies: each rendered, analysed and cached, then discovered
// (bench/scorecard.h; docs/discovery.md, "Scorecard").
#include "scorecard.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <exception>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/parallel.h"
#include "discovery/discovery.h"
#include "io/atomic_file.h"
#include "pipeline/study_analysis.h"
#include "pipeline/study_format.h"
#include "stats/distributions.h"
#include "studyfile/study_file.h"
#include "synth/projection.h"
#include "synth/study.h"
#include "synth/trial_files.h"

namespace scorecard {
namespace {

/// Bump when what goes into a cached study changes in a way its key does not show (the render
/// or analysis settings below, the cache file's own layout). A change to the renderer or the
/// tracker is not seen either: delete the cache after one.
constexpr const char* kCacheFormat = "discovery-scorecard-cache/1";

// ---------------------------------------------------------------------------------------------
// Reading the discovery result. Everything the scorecard takes from a DiscoveryResult is read
// here and nowhere else, so that a change of the result's shape is mended in one place.
// ---------------------------------------------------------------------------------------------

/// What the scorecard needs of one discovery run.
struct Verdict {
  bool ran = false;                ///< the workflow could run on the study
  std::string error;               ///< why not
  std::vector<std::string> named;  ///< library keys of the effects named, in the result's order
  /// The detection limit discovery printed for `key` in its first round (against the baseline);
  /// NaN when it gave none.
  double limit = NAN;
  /// Every candidate's first-round detection limit, by library key.
  std::map<std::string, double> limits;
};

Verdict ReadVerdict(const hoof::discovery::DiscoveryResult& r, const std::string& key) {
  Verdict v;
  v.ran = r.success;
  v.error = r.message;
  for (const auto& f : r.findings)
    if (f.status == hoof::discovery::FindingStatus::kNamed) v.named.push_back(f.key);
  if (!r.rounds.empty())
    for (const auto& c : r.rounds.front().candidates) {
      if (c.key == key) v.limit = c.detection_limit;
      v.limits[c.key] = c.detection_limit;
    }
  return v;
}

/// The library's keys, in its order: the columns of the confusion matrix.
}  // namespace

std::vector<std::string> LibraryKeys() {
  std::vector<std::string> keys;
  for (const auto& entry : hoof::discovery::Library()) keys.push_back(entry.key);
  return keys;
}

// ---------------------------------------------------------------------------------------------
// The grid
// ---------------------------------------------------------------------------------------------

namespace {

/// Sets the contact extension of the discovery library's effect `key` (its
/// LibraryEntry::extension, a row of dynamics::ContactExtensionFields()).
std::function<void(hoof::synth::HiddenEffects&, double)> SetsExtensionOf(const std::string& key) {
  for (const auto& e : hoof::discovery::Library())
    if (e.key == key)
      if (const auto* f = hoof::dynamics::FindContactExtension(e.extension))
        return [member = f->member](hoof::synth::HiddenEffects& h, double v) {
          h.contact.*member = v;
        };
  throw std::logic_error("scorecard: no contact extension for the library effect '" + key + "'");
}

}  // namespace

std::vector<Effect> AllEffects() {
  using hoof::synth::HiddenEffects;
  return {
      {"null", "", "", {0.0}, [](HiddenEffects&, double) {}, ""},
      {"hunt_crossley",
       "hunt-crossley",
       "N s/m^2",
       {2e7, 4e7},
       SetsExtensionOf("hunt_crossley"),
       "hunt_crossley"},
      {"hertz_stiffness",
       "hertz-stiffness",
       "1",
       {0.3, 0.6},
       SetsExtensionOf("hertz_stiffness"),
       "hertz_stiffness"},
      {"rolling_resistance",
       "rolling-resistance",
       "m",
       {5e-4, 1e-3},
       SetsExtensionOf("rolling_resistance"),
       "rolling_resistance"},
      {"tangential_compliance",
       "tangential-compliance",
       "1",
       {1.0, 2.0},
       SetsExtensionOf("tangential_compliance"),
       "tangential_compliance"},
      // A tilt that grows from 0 at touch: the marker distance drifts in time instead of
      // standing off by a constant cos(tilt).
      {"out_of_plane_rate",
       "out-of-plane-rate",
       "deg/s",
       {500.0, 1000.0},
       [](HiddenEffects& h, double v) {
         h.out_of_plane = {0.0, 0.0, v, 0.0};
       },
       "out_of_plane_rate"},
  };
}

const std::vector<std::string> kDesigns = {"paper", "unreplicated", "one_surface"};

/// True when discovery naming `named` names the hidden effect.
bool NamesHidden(const Effect& hidden, const std::string& named) {
  if (hidden.library_prefix.empty()) return false;
  return named == hidden.library_prefix;
}

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

namespace {

std::string Exact(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

/// FNV-1a: a stable 64-bit hash of text (std::hash may differ between library versions, and
/// cache names and seeds must not).
std::uint64_t Fnv1a(const std::string& text) {
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

}  // namespace

std::string StudyPoint::Label() const {
  return design + " scatter " + Num(scatter) + " " + effect->key +
         (effect->key == "null" ? "" : " " + Num(size)) + " seed " + std::to_string(seed_index);
}

std::uint64_t StudyPoint::StudySeed() const {
  return hoof::synth::MixSeed(Fnv1a("design=" + design + ";scatter=" + Exact(scatter) +
                                    ";effect=" + effect->key + ";size=" + Exact(size)),
                              static_cast<std::uint64_t>(seed_index));
}

/// The study's design: one of the three layouts, the scatter scale and the hidden effect.
hoof::synth::StudyDesign MakeDesign(const StudyPoint& p) {
  hoof::synth::StudyDesign d;
  d.seed = p.StudySeed();
  d.name = "scorecard " + p.Label();
  d.scatter_scale = p.scatter;
  p.effect->apply(d.hidden, p.size);
  if (p.design == "paper") return d;  // 3 surfaces x 4 angles x 4 speeds x 3 trials = 144
  if (p.design == "one_surface") {    // steel, 4 angles x 4 speeds x 3 trials = 48
    d.surfaces = {hoof::dynamics::Surface::kSteel};
    return d;
  }
  // unreplicated: every surface and angle three times, each trial at its own speed drawn
  // uniformly in [1.5, 4] m/s, so no two trials share a cell (36 trials).
  hoof::synth::DrawUnreplicatedCells(d);
  return d;
}

/// Render and analysis settings of every study: the programs' defaults.
namespace {

hoof::synth::RenderOptions RenderSettings() { return {}; }
hoof::pipeline::TrialAnalysisOptions AnalysisSettings() { return {}; }

}  // namespace

/// Everything that defines a cached study, as canonical JSON text (keys sorted): the trials
/// with their seeds, scatter and hidden effects, the specimen, the camera and image settings,
/// the format.
std::string CacheKey(const hoof::synth::StudyDesign& design) {
  nlohmann::json trials = nlohmann::json::array();
  for (const auto& t : design.Trials())
    trials.push_back({{"id", t.id},
                      {"surface", hoof::dynamics::SurfaceName(t.surface)},
                      {"angle_deg", t.angle_deg},
                      {"speed_m_s", t.speed_m_s},
                      {"seed", t.seed},
                      {"scatter_parameters", t.scatter_parameters},
                      {"scatter_scale", t.scatter_scale},
                      {"hidden_effects", hoof::synth::HiddenEffectsJson(t.hidden)}});
  const auto r = RenderSettings();
  const nlohmann::json key = {{"format", kCacheFormat},
                              {"trials", trials},
                              {"specimen", hoof::synth::SpecimenJson({})},
                              {"render",
                               {{"width_px", r.width_px},
                                {"height_px", r.height_px},
                                {"bit_depth", r.bit_depth},
                                {"m_per_px", r.m_per_px},
                                {"fps", r.fps},
                                {"frames_before", r.frames_before},
                                {"frames_after", r.frames_after},
                                {"camera", hoof::synth::CameraEffectsJson(r.camera)}}},
                              {"analysis", "TrialAnalysisOptions defaults"}};
  return key.dump();
}

fs::path CacheFile(const fs::path& cache_dir, const StudyPoint& p, const std::string& key) {
  std::string size = Num(p.size);
  size.erase(std::remove(size.begin(), size.end(), '+'), size.end());
  char hash[20];
  std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(Fnv1a(key)));
  return cache_dir / (p.design + "-s" + Num(p.scatter) + "-" + p.effect->key + "-" + size +
                      "-seed" + std::to_string(p.seed_index) + "-" + hash + ".h5");
}

// ---------------------------------------------------------------------------------------------
// One study: render, analyse, cache; then discover
// ---------------------------------------------------------------------------------------------

namespace {

/// The scorecard's own record in a cached study file: how the study was made and how long it
/// took, under /scorecard/study.
const char* kRecordGroup = "/scorecard";
const char* kRecordTable = "/scorecard/study";

}  // namespace

/// Reads a cached study's record; false when the file is missing, unreadable or made for
/// another key (a hash collision or a file from an older format).
bool ReadCacheRecord(const fs::path& file, const std::string& key, Row& row) {
  if (!fs::exists(file)) return false;
  try {
    const auto t = hoof::studyfile::ReadTable(file, kRecordTable);
    const auto& keys = std::get<std::vector<std::string>>(t.Get("key").values);
    if (keys.size() != 1 || keys[0] != key) return false;
    row.render_s = std::get<std::vector<double>>(t.Get("render_seconds").values).at(0);
    row.analyze_s = std::get<std::vector<double>>(t.Get("analyze_seconds").values).at(0);
    row.trials =
        static_cast<int>(std::get<std::vector<std::int64_t>>(t.Get("trials").values).at(0));
    row.failed_trials =
        static_cast<int>(std::get<std::vector<std::int64_t>>(t.Get("failed_trials").values).at(0));
    row.cache_bytes = static_cast<double>(fs::file_size(file));
    return true;
  } catch (const std::exception& e) {
    std::cerr << "scorecard: cache file " << file << " unusable (" << e.what()
              << "); it is made again\n";
    return false;
  }
}

namespace {

/// Removes a folder when it goes out of scope (the frames, whatever happens).
struct RemoveOnExit {
  fs::path dir;
  ~RemoveOnExit() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

/// Renders the study into a temporary folder in the cache, analyses it, writes the analyses
/// and the record to a temporary file and renames it into the cache; the frames are removed in
/// every case. On failure sets row.stage and row.error. A study some of whose trials failed to
/// render is not cached (those failures come from the machine, a full disk say, not from the
/// study); trials whose analysis failed are, since the same frames would fail again.
void RenderAndAnalyze(const StudyPoint& p, const hoof::synth::StudyDesign& design,
                      const std::string& key, const fs::path& cache_dir, int jobs, Row& row) {
  static int counter = 0;
  const fs::path frames_dir =
      cache_dir / (".render-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
  const RemoveOnExit cleanup{frames_dir};
  row.stage = "render";
  auto start = Clock::now();
  const hoof::synth::StudyResult rendered =
      hoof::synth::RenderStudy(design, {}, RenderSettings(), frames_dir, jobs);
  row.render_s = std::chrono::duration<double>(Clock::now() - start).count();
  row.trials = static_cast<int>(rendered.trials.size());
  if (rendered.failed > 0) {
    for (const auto& t : rendered.trials)
      if (!t.ok) {
        row.error = std::to_string(rendered.failed) + " of " + std::to_string(row.trials) +
                    " trials failed to render, e.g. " + t.spec.id + ": " + t.error;
        return;
      }
  }

  row.stage = "analyze";
  start = Clock::now();
  const hoof::pipeline::StudySpec study = hoof::pipeline::ReadStudy(frames_dir);
  const auto analyses = hoof::pipeline::AnalyzeStudy(study, AnalysisSettings(), jobs);
  row.analyze_s = std::chrono::duration<double>(Clock::now() - start).count();
  row.failed_trials = 0;
  for (const auto& a : analyses) row.failed_trials += a.success ? 0 : 1;
  // Nothing worth caching: an analysis that fails everywhere is broken, not the study.
  if (analyses.empty()) {
    row.error = "the rendered study has no trials to analyse";
    return;
  }
  if (row.failed_trials == static_cast<int>(analyses.size())) {
    row.error = "the analysis of every trial failed, e.g. " + analyses.front().spec.id + ": " +
                analyses.front().error;
    return;
  }

  row.stage = "cache";
  auto info = hoof::studyfile::StudyInfo::Of(
      study, AnalysisSettings(),
      "discovery_scorecard: " + p.Label() + " (frames deleted after analysis)");
  info.study_dir = frames_dir;
  using hoof::studyfile::Column;
  const hoof::studyfile::Table record{
      "study",
      "How the scorecard made this study",
      {Column::Texts("key", "everything that defines the study (canonical JSON)", {key}),
       Column::Texts("label", "design, scatter, effect, size, seed index", {p.Label()}),
       Column::Numbers("render_seconds", "s", "wall time of rendering", {row.render_s}),
       Column::Numbers("analyze_seconds", "s", "wall time of the analysis", {row.analyze_s}),
       Column::Integers("trials", "1", "trials rendered", {row.trials}),
       Column::Integers("failed_trials", "1", "trials whose analysis failed",
                        {row.failed_trials})}};
  const fs::path file = CacheFile(cache_dir, p, key);
  const fs::path tmp = hoof::io::TemporaryPathFor(file);
  try {
    hoof::studyfile::WriteStudyFile(tmp, info, analyses);
    hoof::studyfile::WriteTables(tmp, kRecordGroup, "the discovery scorecard's record", {record});
    hoof::io::CommitTemporary(tmp, file);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
  row.cache_bytes = static_cast<double>(fs::file_size(file));
  row.stage.clear();
}

}  // namespace

/// Makes sure the study is in the cache (from an earlier run or made now), then runs
/// discovery on the cached analyses unless `only_render`. Never throws: failures are recorded
/// in the row.
Row RunStudy(const StudyPoint& p, const fs::path& cache_dir, int jobs, bool only_render,
             bool verbose) {
  Row row;
  row.point = p;
  try {
    const hoof::synth::StudyDesign design = MakeDesign(p);
    row.study_seed = design.seed;
    const std::string key = CacheKey(design);
    row.cache_file = CacheFile(cache_dir, p, key);
    row.from_cache = ReadCacheRecord(row.cache_file, key, row);
    if (!row.from_cache) {
      RenderAndAnalyze(p, design, key, cache_dir, jobs, row);
      if (!row.stage.empty()) return row;
    }
    if (only_render) return row;
    row.stage = "discover";
    const auto trials = hoof::studyfile::ReadTrialAnalyses(row.cache_file);
    hoof::discovery::DiscoveryOptions options;
    options.jobs = jobs;
    const auto start = Clock::now();
    const auto result = hoof::discovery::Discover(trials, options, [&](const std::string& line) {
      if (verbose) std::cerr << "    " << line << "\n";
    });
    row.discover_s = std::chrono::duration<double>(Clock::now() - start).count();
    const Verdict v = ReadVerdict(result, row.point.effect->library_prefix);
    if (!v.ran) {
      row.error = "discovery could not run: " + v.error;
      return row;
    }
    row.discovered = true;
    row.named = v.named;
    row.limit = v.limit;
    row.limits = v.limits;
    row.stage.clear();
  } catch (const std::exception& e) {
    row.error = e.what();
    if (row.stage.empty()) row.stage = "setup";
  }
  return row;
}

/// Removes what a killed run left in the cache: frame folders and temporary files of
/// processes that no longer exist.
void RemoveLeftovers(const fs::path& cache_dir) {
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(cache_dir, ec)) {
    const std::string name = entry.path().filename().string();
    std::size_t at = name.find(".render-");
    std::size_t skip = 8;
    if (at != 0) {
      at = name.find(".tmp-");
      skip = 5;
    }
    if (at == std::string::npos) continue;
    const long pid = std::strtol(name.c_str() + at + skip, nullptr, 10);
    if (pid <= 0 || pid == ::getpid()) continue;
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM) continue;  // still running
    fs::remove_all(entry.path(), ec);
    std::cerr << "scorecard: removed " << entry.path() << " left by process " << pid << "\n";
  }
}

// ---------------------------------------------------------------------------------------------
// Output
// ---------------------------------------------------------------------------------------------

/// Wilson score interval of k successes in n trials at 95 %.

}  // namespace scorecard
