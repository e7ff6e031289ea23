// Discovery explored by hand (docs/discovery.md, "How it was checked"): renders a study with
// `hoofimpact synth --study` unless it is already there, measures it, runs the discovery
// workflow on it and prints every round and candidate. It asserts nothing; it is neither a ctest
// test nor a Google Benchmark. (It was the test DiscoveryExplore.Run, skipped unless
// HOOF_EXPLORE was set.)
//
//   build/bench/discovery_explore NAME [--design "SYNTH OPTIONS"] [--args "SYNTH OPTIONS"]
//
// Studies live in build/test-output/discovery/NAME; a study already there is used as it is,
// whatever the options. (The tests' own studies are under build/test-output/studies/, one folder
// per name, options and build: tests/support/rendered_study.h.) Without --design, the tests' design
// (one surface, 24 trials, no per-trial scatter); --args adds synth options (a hidden effect, a
// seed). The environment variables the test read still work as defaults: HOOF_EXPLORE (NAME),
// HOOF_EXPLORE_DESIGN, HOOF_EXPLORE_ARGS.
#include <unistd.h>

#include <cstdlib>
#include <exception>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "discovery/discovery.h"
#include "pipeline/study_analysis.h"
#include "pipeline/study_format.h"
#include "support/discovery_print.h"

namespace {

namespace fs = std::filesystem;
using hoof::discovery::DiscoveryResult;

/// The design of tests/discovery/discovery_studies.h (kDiscoveryDesign): one surface, normal and
/// oblique impacts at three speeds, two repetitions, the paper's contact law in every trial (no
/// per-trial scatter) and every camera effect on.
const char* kDesign =
    "--surfaces steel --angles-deg 0,10,20,30 --speeds 1.5,2.75,4 --trials-per-cell 2 --no-scatter";

std::string Env(const char* name) {
  const char* v = std::getenv(name);
  return v ? v : "";
}

/// Renders a study with `hoofimpact synth --study` unless it is already there.
fs::path RenderStudy(const std::string& name, const std::string& options) {
  const fs::path dir = fs::path(HOOF_BINARY_DIR) / "test-output" / "discovery" / name;
  if (fs::exists(dir / "study.json")) {
    std::cerr << "using the study in " << dir.string() << "\n";
    return dir;
  }
  const fs::path tmp = dir.string() + ".tmp-" + std::to_string(::getpid());
  fs::remove_all(tmp);
  fs::create_directories(tmp.parent_path());
  // What the renderer prints goes to stderr with the progress; stdout is the result alone.
  const std::string cmd =
      std::string(HOOF_CLI_PATH) + " synth --study -o " + tmp.string() + " " + options + " 1>&2";
  std::cerr << "rendering: " << cmd << "\n";
  if (std::system(cmd.c_str()) != 0) {
    fs::remove_all(tmp);
    throw std::runtime_error("rendering the study failed: " + cmd);
  }
  fs::rename(tmp, dir);
  return dir;
}

void Print(const DiscoveryResult& r) { hoof::testing::PrintDiscoveryRounds(std::cout, r); }

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Renders (or reuses) a study, measures it, runs discovery on it and prints every round."};
  std::string name = Env("HOOF_EXPLORE");
  std::string design = Env("HOOF_EXPLORE_DESIGN");
  std::string extra = Env("HOOF_EXPLORE_ARGS");
  app.add_option("name", name,
                 "Study name: folder under build/test-output/discovery (default $HOOF_EXPLORE)");
  app.add_option(
      "--design", design,
      "Synth options of the design (default $HOOF_EXPLORE_DESIGN, else the tests' design)");
  app.add_option("--args", extra, "Synth options added to the design (default $HOOF_EXPLORE_ARGS)");
  CLI11_PARSE(app, argc, argv);
  if (name.empty()) {
    std::cerr << "discovery_explore: name a study (or set HOOF_EXPLORE)\n" << app.help();
    return 2;
  }
  try {
    const fs::path dir =
        RenderStudy(name, (design.empty() ? std::string(kDesign) : design) + " " + extra);
    const auto trials = hoof::pipeline::AnalyzeStudy(hoof::pipeline::ReadStudy(dir), {}, 2);
    Print(hoof::discovery::Discover(trials, {},
                                    [](const std::string& s) { std::cerr << s << "\n"; }));
  } catch (const std::exception& e) {
    std::cerr << "discovery_explore: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
