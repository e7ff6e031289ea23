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
