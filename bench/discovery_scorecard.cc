// The discovery scorecard (docs/discovery.md, "Scorecard"): renders studies that hide an effect of
// known kind and size, measures them, runs discovery on them and counts what it names. It
// measures rates (detection, false naming, wrong names) over a grid of designs, scatters,
// effects, sizes and seeds; it asserts nothing, and it is neither a ctest test nor a Google
// Benchmark.
//   build/bench/discovery_scorecard --designs one_surface --seeds 3 --json scorecard.json
//
// Frames are large (a 144-trial study is about 500 MB of PNG) and discovery is what changes,
// so each study is rendered into a temporary folder, analysed, and only its analyses are kept,
// as a study file in the cache (studyfile::ReadTrialAnalyses reads them back); the frames are
// deleted at once. A later run finds the study in the cache and only runs discovery again.
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

#include <CLI/CLI.hpp>
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

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

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
std::vector<std::string> LibraryKeys() {
  std::vector<std::string> keys;
  for (const auto& entry : hoof::discovery::Library()) keys.push_back(entry.key);
  return keys;
}

// ---------------------------------------------------------------------------------------------
// The grid
// ---------------------------------------------------------------------------------------------

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

/// One study of the grid.
struct StudyPoint {
  std::string design;
  double scatter = 1.0;
  const Effect* effect = nullptr;
  double size = 0.0;
  int seed_index = 0;

  std::string Label() const {
    return design + " scatter " + Num(scatter) + " " + effect->key +
           (effect->key == "null" ? "" : " " + Num(size)) + " seed " + std::to_string(seed_index);
  }
  /// Distinct per (design, scatter, effect, size, seed index), and the same on every run.
  std::uint64_t StudySeed() const {
    return hoof::synth::MixSeed(Fnv1a("design=" + design + ";scatter=" + Exact(scatter) +
                                      ";effect=" + effect->key + ";size=" + Exact(size)),
                                static_cast<std::uint64_t>(seed_index));
  }
};

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
hoof::synth::RenderOptions RenderSettings() { return {}; }
hoof::pipeline::TrialAnalysisOptions AnalysisSettings() { return {}; }

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

/// The scorecard's own record in a cached study file: how the study was made and how long it
/// took, under /scorecard/study.
const char* kRecordGroup = "/scorecard";
const char* kRecordTable = "/scorecard/study";

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
std::pair<double, double> Wilson(int k, int n) {
  if (n == 0) return {NAN, NAN};
  return hoof::stats::WilsonInterval(k, n);
}

std::string Rate(int k, int n) {
  if (n == 0) return "-";
  const auto [lo, hi] = Wilson(k, n);
  char buf[96];
  std::snprintf(buf, sizeof buf, "%d/%d = %.2f [%.2f, %.2f]", k, n, static_cast<double>(k) / n, lo,
                hi);
  return buf;
}

void PrintTable(const std::vector<std::string>& header,
                const std::vector<std::vector<std::string>>& rows) {
  const auto line = [](const std::vector<std::string>& cells) {
    std::cout << "|";
    for (const auto& c : cells) std::cout << " " << c << " |";
    std::cout << "\n";
  };
  line(header);
  std::cout << "|";
  for (std::size_t i = 0; i < header.size(); ++i) std::cout << (i == 0 ? "---|" : "--:|");
  std::cout << "\n";
  for (const auto& r : rows) line(r);
  std::cout << "\n";
}

std::string SizeLabel(const Row& r) {
  return r.point.effect->key == "null"
             ? "null"
             : r.point.effect->key + " " + Num(r.point.size) + " " + r.point.effect->unit;
}

bool WrongName(const Row& r) {
  for (const auto& n : r.named)
    if (!NamesHidden(*r.point.effect, n)) return true;
  return false;
}

bool Detected(const Row& r) {
  for (const auto& n : r.named)
    if (NamesHidden(*r.point.effect, n)) return true;
  return false;
}

void PrintConfusion(const std::vector<Row>& rows, const std::string& design, double scatter) {
  std::vector<std::string> columns = LibraryKeys();
  for (const Row& r : rows)
    for (const auto& n : r.named)
      if (std::find(columns.begin(), columns.end(), n) == columns.end()) columns.push_back(n);
  std::vector<std::string> labels;
  std::map<std::string, std::map<std::string, int>> counts;
  for (const Row& r : rows) {
    if (r.point.design != design || r.point.scatter != scatter) continue;
    const std::string label = SizeLabel(r);
    if (std::find(labels.begin(), labels.end(), label) == labels.end()) labels.push_back(label);
    const std::string column = !r.discovered        ? "error"
                               : r.named.empty()    ? "nothing"
                               : r.named.size() > 1 ? "several"
                                                    : r.named.front();
    ++counts[label][column];
  }
  if (labels.empty()) return;
  columns.insert(columns.end(), {"nothing", "several", "error"});
  std::vector<std::string> header = {"hidden \\ named"};
  header.insert(header.end(), columns.begin(), columns.end());
  std::vector<std::vector<std::string>> table;
  for (const auto& label : labels) {
    std::vector<std::string> cells = {label};
    for (const auto& c : columns) {
      const int n = counts[label].count(c) ? counts[label][c] : 0;
      cells.push_back(n ? std::to_string(n) : ".");
    }
    table.push_back(cells);
  }
  std::cout << "### Confusion: " << design << ", scatter " << Num(scatter) << "\n\n";
  PrintTable(header, table);
}

void PrintReport(const std::vector<Row>& rows, const std::vector<std::string>& designs,
                 const std::vector<double>& scatters, bool only_render) {
  std::cout << "# Discovery scorecard\n\n";
  std::vector<std::pair<std::string, double>> combos;
  for (const auto& d : designs)
    for (double s : scatters) combos.push_back({d, s});
  if (!only_render) {
    for (const auto& [d, s] : combos) PrintConfusion(rows, d, s);

    // Power: rate at which the hidden effect is named, per effect size.
    std::vector<std::string> header = {"hidden effect"};
    for (const auto& [d, s] : combos) header.push_back(d + ", scatter " + Num(s));
    std::vector<std::string> labels;
    for (const Row& r : rows)
      if (r.point.effect->key != "null" &&
          std::find(labels.begin(), labels.end(), SizeLabel(r)) == labels.end())
        labels.push_back(SizeLabel(r));
    std::vector<std::vector<std::string>> table;
    for (const auto& label : labels) {
      std::vector<std::string> cells = {label};
      for (const auto& [d, s] : combos) {
        int k = 0, n = 0;
        for (const Row& r : rows)
          if (r.discovered && SizeLabel(r) == label && r.point.design == d &&
              r.point.scatter == s) {
            ++n;
            k += Detected(r) ? 1 : 0;
          }
        cells.push_back(Rate(k, n));
      }
      table.push_back(cells);
    }
    if (!table.empty()) {
      std::cout << "### Power: hidden effect named (rate, Wilson 95 %)\n\n";
      PrintTable(header, table);
    }

    // Power against the size in units of the detection limit discovery printed for each study:
    // where the limits are right, about 80 % at 1 and at least 90 % from 2.
    {
      const std::vector<double> edges = {0.0, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 1e300};
      std::vector<std::string> effects;
      for (const Row& r : rows)
        if (r.point.effect->key != "null" &&
            std::find(effects.begin(), effects.end(), r.point.effect->key) == effects.end())
          effects.push_back(r.point.effect->key);
      std::vector<std::string> head = {"size / printed limit"};
      for (const auto& e : effects) head.push_back(e);
      head.push_back("all");
      std::vector<std::vector<std::string>> bins;
      for (std::size_t b = 0; b + 1 < edges.size(); ++b) {
        std::vector<std::string> cells = {b + 2 < edges.size()
                                              ? Num(edges[b]) + " - " + Num(edges[b + 1])
                                              : ">= " + Num(edges[b])};
        int all_k = 0, all_n = 0;
        for (std::size_t j = 0; j <= effects.size(); ++j) {
          int k = 0, n = 0;
          for (const Row& r : rows) {
            if (!r.discovered || r.point.effect->key == "null" || !(r.limit > 0)) continue;
            if (j < effects.size() && r.point.effect->key != effects[j]) continue;
            const double x = r.point.size / r.limit;
            if (x < edges[b] || x >= edges[b + 1]) continue;
            ++n;
            k += Detected(r) ? 1 : 0;
          }
          if (j == effects.size()) all_k = k, all_n = n;
          cells.push_back(j == effects.size()
                              ? Rate(all_k, all_n)
                              : (n ? std::to_string(k) + "/" + std::to_string(n) : "-"));
        }
        bins.push_back(cells);
      }
      std::cout << "### Power against the printed detection limit (hidden effect named; size over "
                   "the limit "
                   "discovery printed for that study in round 1)\n\n";
      PrintTable(head, bins);
    }

    // False naming on null studies and wrong names over all studies.
    table.clear();
    const auto add = [&](const std::string& label, const std::function<bool(const Row&)>& in) {
      int null_k = 0, null_n = 0, wrong_k = 0, wrong_n = 0;
      for (const Row& r : rows) {
        if (!r.discovered || !in(r)) continue;
        ++wrong_n;
        wrong_k += WrongName(r) ? 1 : 0;
        if (r.point.effect->key == "null") {
          ++null_n;
          null_k += r.named.empty() ? 0 : 1;
        }
      }
      table.push_back({label, Rate(null_k, null_n), Rate(wrong_k, wrong_n)});
    };
    for (const auto& combo : combos)
      add(combo.first + ", scatter " + Num(combo.second), [&combo](const Row& r) {
        return r.point.design == combo.first && r.point.scatter == combo.second;
      });
    add("all", [](const Row&) { return true; });
    std::cout << "### False and wrong names (rate, Wilson 95 %)\n\n"
                 "False naming: a null study in which anything is named. Wrong effect: a study "
                 "in which a key other than the hidden effect's is named.\n\n";
    PrintTable({"studies", "false naming (null studies)", "wrong effect (all studies)"}, table);
  }

  // Time per study and size of a cache entry.
  std::vector<std::vector<std::string>> table;
  for (const auto& d : designs) {
    double render = 0, analyze = 0, discover = 0, bytes = 0;
    int n_made = 0, n_disc = 0, n_bytes = 0, trials = 0;
    for (const Row& r : rows) {
      if (r.point.design != d) continue;
      if (std::isfinite(r.render_s) && std::isfinite(r.analyze_s)) {
        render += r.render_s;
        analyze += r.analyze_s;
        trials = r.trials;
        ++n_made;
      }
      if (std::isfinite(r.discover_s)) {
        discover += r.discover_s;
        ++n_disc;
      }
      if (std::isfinite(r.cache_bytes)) {
        bytes += r.cache_bytes;
        ++n_bytes;
      }
    }
    const auto mean = [](double sum, int n) {
      char buf[32];
      if (n == 0) return std::string("-");
      std::snprintf(buf, sizeof buf, "%.1f", sum / n);
      return std::string(buf);
    };
    table.push_back({d, std::to_string(trials), mean(render, n_made), mean(analyze, n_made),
                     mean(discover, n_disc), mean(bytes / 1e6, n_bytes),
                     std::to_string(n_made) + " / " + std::to_string(n_disc)});
  }
  std::cout << "### Time per study (mean wall seconds; render and analysis as recorded when the "
               "study was cached)\n\n";
  PrintTable({"design", "trials", "render s", "analyze s", "discover s", "cache entry MB",
              "studies (made / discovered)"},
             table);

  int errors = 0;
  for (const Row& r : rows) errors += r.stage.empty() ? 0 : 1;
  std::cout << "Studies: " << rows.size() << ", errors: " << errors << "\n";
  for (const Row& r : rows)
    if (!r.stage.empty())
      std::cout << "  ERROR (" << r.stage << ") " << r.point.Label() << ": " << r.error << "\n";
}

nlohmann::json RowJson(const Row& r) {
  const auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  return {{"design", r.point.design},
          {"scatter", r.point.scatter},
          {"effect", r.point.effect->key},
          {"size", r.point.size},
          {"size_unit", r.point.effect->unit},
          {"seed", r.point.seed_index},
          {"study_seed", r.study_seed},
          {"named", r.named},
          {"discovered", r.discovered},
          {"detected", Detected(r)},
          {"detection_limit", num(r.limit)},
          {"size_over_limit", num(r.point.size / r.limit)},
          {"detection_limits",
           [&] {
             nlohmann::json j = nlohmann::json::object();
             for (const auto& [k, v] : r.limits) j[k] = num(v);
             return j;
           }()},
          {"wrong_name", WrongName(r)},
          {"trials", r.trials},
          {"failed_trials", r.failed_trials},
          {"from_cache", r.from_cache},
          {"cache_file", r.cache_file.string()},
          {"cache_bytes", num(r.cache_bytes)},
          {"seconds",
           {{"render", num(r.render_s)},
            {"analyze", num(r.analyze_s)},
            {"discover", num(r.discover_s)}}},
          {"error_stage", r.stage},
          {"error", r.error}};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "The discovery scorecard: renders studies with hidden effects, measures them, runs "
      "discovery and prints how often it names the right effect, a wrong one, or anything in "
      "null studies (docs/discovery.md, section Scorecard)"};
  std::vector<std::string> designs = kDesigns;
  std::vector<double> scatters = {1.0, 0.5};
  std::vector<Effect> effects = AllEffects();
  std::vector<std::string> effect_keys;
  for (const auto& e : effects) effect_keys.push_back(e.key);
  int seeds = 10;
  int jobs = 0;
  std::string cache_dir = std::string(HOOF_BINARY_DIR) + "/scorecard-cache";
  std::string json_file;
  bool only_render = false, list = false, verbose = false;
  app.add_option("--designs", designs, "paper, unreplicated, one_surface (comma-separated)")
      ->delimiter(',')
      ->check(CLI::IsMember(kDesigns))
      ->capture_default_str();
  app.add_option("--scatters", scatters,
                 "Scatter scales of the per-trial e and mu draws (1 = the paper's spread)")
      ->delimiter(',')
      ->check(CLI::Range(0.0, 4.0))
      ->capture_default_str();
  app.add_option("--effects", effect_keys, "Hidden effects (comma-separated)")
      ->delimiter(',')
      ->check(CLI::IsMember(std::vector<std::string>(effect_keys)))
      ->capture_default_str();
  // CLI::PositiveNumber would print its range with every digit of DBL_MAX.
  const CLI::Validator positive(
      [](std::string& text) {
        try {
          if (std::stod(text) > 0) return std::string();
        } catch (const std::exception&) {
        }
        return "must be a number > 0, got " + text;
      },
      "> 0");
  for (auto& e : effects) {
    if (e.flag.empty()) continue;
    std::string underscored = e.flag;
    std::replace(underscored.begin(), underscored.end(), '-', '_');
    app.add_option("--sizes-" + e.flag + ",--sizes-" + underscored, e.sizes,
                   "Sizes of " + e.key + " (" + e.unit + ", comma-separated)")
        ->delimiter(',')
        ->check(positive)
        ->capture_default_str();
  }
  app.add_option("--seeds", seeds, "Studies per grid point (seed indices 1..N)")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  app.add_option("--jobs", jobs, "Threads for rendering, analysis and discovery (0 = all cores)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--cache", cache_dir, "Folder of cached study analyses")->capture_default_str();
  app.add_option("--json", json_file, "Also write every study's row as JSON to this file");
  app.add_flag("--only-render", only_render, "Fill the cache; do not run discovery");
  app.add_flag("--list", list, "List the studies of the grid and whether each is cached");
  app.add_flag("--verbose", verbose, "Discovery's own progress lines on stderr");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  jobs = hoof::core::ResolveJobs(jobs);

  // The grid, in a fixed order; every design is checked before any work starts.
  std::vector<StudyPoint> points;
  for (const auto& d : designs)
    for (double s : scatters)
      for (const auto& key : effect_keys) {
        const Effect& e = *std::find_if(effects.begin(), effects.end(),
                                        [&](const Effect& x) { return x.key == key; });
        for (double size : e.sizes)
          for (int i = 1; i <= seeds; ++i) points.push_back({d, s, &e, size, i});
      }
  for (const auto& p : points) {
    try {
      MakeDesign(p).Validate();
    } catch (const std::exception& ex) {
      std::cerr << "discovery_scorecard: " << p.Label() << ": " << ex.what() << "\n";
      return 2;
    }
  }
  std::error_code ec;
  fs::create_directories(cache_dir, ec);
  if (ec || !fs::is_directory(cache_dir)) {
    std::cerr << "discovery_scorecard: cannot create the cache folder " << cache_dir
              << (ec ? ": " + ec.message() : "") << "\n";
    return 1;
  }
  if (list) {
    for (const auto& p : points) {
      const auto design = MakeDesign(p);
      const std::string key = CacheKey(design);
      Row row;
      const fs::path file = CacheFile(cache_dir, p, key);
      std::cout << (ReadCacheRecord(file, key, row) ? "cached  " : "missing ") << p.Label() << "  "
                << file.filename().string() << "\n";
    }
    return 0;
  }
  RemoveLeftovers(cache_dir);

  std::vector<Row> rows;
  const auto start = Clock::now();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const StudyPoint& p = points[i];
    std::cerr << "[" << i + 1 << "/" << points.size() << "] " << p.Label() << " ..." << std::endl;
    Row row = RunStudy(p, cache_dir, jobs, only_render, verbose);
    std::ostringstream os;
    os << "[" << i + 1 << "/" << points.size() << "] " << p.Label() << ": ";
    if (row.from_cache)
      os << "cached";
    else if (std::isfinite(row.analyze_s))
      os << "rendered " << Num(row.render_s) << " s, analysed " << Num(row.analyze_s) << " s";
    if (row.failed_trials > 0) os << " (" << row.failed_trials << " trials failed)";
    if (std::isfinite(row.discover_s)) os << "; discovery " << Num(row.discover_s) << " s";
    if (!row.stage.empty()) {
      os << "; ERROR in " << row.stage << ": " << row.error;
    } else if (!only_render) {
      os << "; named: ";
      if (row.named.empty()) os << "nothing";
      for (std::size_t k = 0; k < row.named.size(); ++k) os << (k ? ", " : "") << row.named[k];
    }
    std::cerr << os.str() << std::endl;
    rows.push_back(std::move(row));
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();

  PrintReport(rows, designs, scatters, only_render);
  std::cout << "Wall time: " << Num(seconds) << " s\n";
  if (!json_file.empty()) {
    nlohmann::json out = {{"generated_utc", hoof::studyfile::NowUtc()},
                          {"cache", cache_dir},
                          {"only_render", only_render},
                          {"seconds", seconds},
                          {"studies", nlohmann::json::array()}};
    for (const Row& r : rows) out["studies"].push_back(RowJson(r));
    try {
      hoof::io::WriteTextAtomically(json_file, out.dump(2) + "\n");
    } catch (const std::exception& e) {
      std::cerr << "discovery_scorecard: " << e.what() << "\n";
      return 1;
    }
  }
  return 0;
}
