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
#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "core/parallel.h"
#include "io/atomic_file.h"
#include "scorecard.h"
#include "studyfile/study_file.h"

using namespace scorecard;

namespace {

/// The command line.
struct ScorecardArgs {
  std::vector<std::string> designs = kDesigns;
  std::vector<double> scatters = {1.0, 0.5};
  std::vector<Effect> effects = AllEffects();
  std::vector<std::string> effect_keys;
  int seeds = 10;
  int jobs = 0;
  std::string cache_dir = std::string(HOOF_BINARY_DIR) + "/scorecard-cache";
  std::string json_file;
  bool only_render = false, list = false, verbose = false;
};

void AddOptions(CLI::App& app, ScorecardArgs& a) {
  for (const auto& e : a.effects) a.effect_keys.push_back(e.key);
  app.add_option("--designs", a.designs, "paper, unreplicated, one_surface (comma-separated)")
      ->delimiter(',')
      ->check(CLI::IsMember(kDesigns))
      ->capture_default_str();
  app.add_option("--scatters", a.scatters,
                 "Scatter scales of the per-trial e and mu draws (1 = the paper's spread)")
      ->delimiter(',')
      ->check(CLI::Range(0.0, 4.0))
      ->capture_default_str();
  app.add_option("--effects", a.effect_keys, "Hidden effects (comma-separated)")
      ->delimiter(',')
      ->check(CLI::IsMember(std::vector<std::string>(a.effect_keys)))
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
  for (auto& e : a.effects) {
    if (e.flag.empty()) continue;
    std::string underscored = e.flag;
    std::replace(underscored.begin(), underscored.end(), '-', '_');
    app.add_option("--sizes-" + e.flag + ",--sizes-" + underscored, e.sizes,
                   "Sizes of " + e.key + " (" + e.unit + ", comma-separated)")
        ->delimiter(',')
        ->check(positive)
        ->capture_default_str();
  }
  app.add_option("--seeds", a.seeds, "Studies per grid point (seed indices 1..N)")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  app.add_option("--jobs", a.jobs, "Threads for rendering, analysis and discovery (0 = all cores)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--cache", a.cache_dir, "Folder of cached study analyses")->capture_default_str();
  app.add_option("--json", a.json_file, "Also write every study's row as JSON to this file");
  app.add_flag("--only-render", a.only_render, "Fill the cache; do not run discovery");
  app.add_flag("--list", a.list, "List the studies of the grid and whether each is cached");
  app.add_flag("--verbose", a.verbose, "Discovery's own progress lines on stderr");
}

/// The grid, in a fixed order.
std::vector<StudyPoint> Grid(const ScorecardArgs& a) {
  std::vector<StudyPoint> points;
  for (const auto& d : a.designs)
    for (double s : a.scatters)
      for (const auto& key : a.effect_keys) {
        const Effect& e = *std::find_if(a.effects.begin(), a.effects.end(),
                                        [&](const Effect& x) { return x.key == key; });
        for (double size : e.sizes)
          for (int i = 1; i <= a.seeds; ++i) points.push_back({d, s, &e, size, i});
      }
  return points;
}

/// Lists each study of the grid and whether the cache holds it.
void List(const std::vector<StudyPoint>& points, const std::string& cache_dir) {
  for (const auto& p : points) {
    const auto design = MakeDesign(p);
    const std::string key = CacheKey(design);
    Row row;
    const fs::path file = CacheFile(cache_dir, p, key);
    std::cout << (ReadCacheRecord(file, key, row) ? "cached  " : "missing ") << p.Label() << "  "
              << file.filename().string() << "\n";
  }
}

/// The progress line of study `i` of `n` once it is done.
std::string DoneLine(std::size_t i, std::size_t n, const StudyPoint& p, const Row& row,
                     bool only_render) {
  std::ostringstream os;
  os << "[" << i + 1 << "/" << n << "] " << p.Label() << ": ";
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
  return os.str();
}

/// Every study's row as JSON, written atomically to `file`.
void WriteJson(const std::string& file, const ScorecardArgs& a, double seconds,
               const std::vector<Row>& rows) {
  nlohmann::json out = {{"generated_utc", hoof::studyfile::NowUtc()},
                        {"cache", a.cache_dir},
                        {"only_render", a.only_render},
                        {"seconds", seconds},
                        {"studies", nlohmann::json::array()}};
  for (const Row& r : rows) out["studies"].push_back(RowJson(r));
  hoof::io::WriteTextAtomically(file, out.dump(2) + "\n");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "The discovery scorecard: renders studies with hidden effects, measures them, runs "
      "discovery and prints how often it names the right effect, a wrong one, or anything in "
      "null studies (docs/discovery.md, section Scorecard)"};
  ScorecardArgs a;
  AddOptions(app, a);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  const int jobs = hoof::core::ResolveJobs(a.jobs);

  // Every design is checked before any work starts.
  const std::vector<StudyPoint> points = Grid(a);
  for (const auto& p : points) {
    try {
      MakeDesign(p).Validate();
    } catch (const std::exception& ex) {
      std::cerr << "discovery_scorecard: " << p.Label() << ": " << ex.what() << "\n";
      return 2;
    }
  }
  std::error_code ec;
  fs::create_directories(a.cache_dir, ec);
  if (ec || !fs::is_directory(a.cache_dir)) {
    std::cerr << "discovery_scorecard: cannot create the cache folder " << a.cache_dir
              << (ec ? ": " + ec.message() : "") << "\n";
    return 1;
  }
  if (a.list) {
    List(points, a.cache_dir);
    return 0;
  }
  RemoveLeftovers(a.cache_dir);

  std::vector<Row> rows;
  const auto start = Clock::now();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const StudyPoint& p = points[i];
    std::cerr << "[" << i + 1 << "/" << points.size() << "] " << p.Label() << " ..." << std::endl;
    Row row = RunStudy(p, a.cache_dir, jobs, a.only_render, a.verbose);
    std::cerr << DoneLine(i, points.size(), p, row, a.only_render) << std::endl;
    rows.push_back(std::move(row));
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();

  PrintReport(rows, a.designs, a.scatters, a.only_render);
  std::cout << "Wall time: " << Num(seconds) << " s\n";
  if (!a.json_file.empty()) {
    try {
      WriteJson(a.json_file, a, seconds, rows);
    } catch (const std::exception& e) {
      std::cerr << "discovery_scorecard: " << e.what() << "\n";
      return 1;
    }
  }
  return 0;
}
