// Every command's --json prints one envelope (docs/cli.md, "JSON output"): format "hoofimpact",
// format_version 1, the command's name, success == (exit code 0), the exit code, an object of
// results and a list of errors, and nothing else on stdout. Each command runs on a small input:
// the sample trials of sample_frames/ (track, analyze, score, stats of a CSV) and the catalog's
// smallest studies (tests/support/test_studies.h) for run, stats, figures, report, overlay and
// discover; failures (bad options, missing files, a discovery that cannot run) are envelopes
// too, with success false and the error named.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include "dynamics/parameters.h"
#include "support/run_command.h"
#include "support/test_studies.h"

namespace hoof::cli {
namespace {

namespace fs = std::filesystem;
using hoof::testing::CommandResult;
using hoof::testing::RunHoofimpact;
using nlohmann::json;

const std::string kSample = std::string(HOOF_SOURCE_DIR) + "/sample_frames";

fs::path Fresh(const std::string& name) {
  const fs::path p = fs::path(HOOF_BINARY_DIR) / "test-output" /
                     ("json_envelope_" + std::to_string(::getpid())) / name;
  fs::remove_all(p);
  fs::create_directories(p.parent_path());
  return p;
}

/// The envelope of `r` (stdout parsed whole: nothing else may be there), checked against
/// `command` and `success`; the test fails when it is not one.
json Envelope(const CommandResult& r, const std::string& command, bool success) {
  json j;
  try {
    j = json::parse(r.out);
  } catch (const std::exception& e) {
    ADD_FAILURE() << command << ": stdout is not one JSON document: " << e.what() << "\n"
                  << r.out.substr(0, 2000) << "\nstderr: " << r.err;
    return json::object();
  }
  EXPECT_TRUE(j.is_object()) << command;
  EXPECT_EQ(j.value("format", ""), "hoofimpact") << command;
  EXPECT_EQ(j.value("format_version", 0), 1) << command;
  EXPECT_EQ(j.value("command", ""), command);
  EXPECT_EQ(j.value("version", ""), "0.1.0") << command;
  EXPECT_EQ(j.value("success", !success), success) << command << "\n" << r.err;
  EXPECT_EQ(j.value("exit_code", -1), r.exit_code) << command;
  EXPECT_EQ(r.exit_code == 0, success) << command << " exit " << r.exit_code << "\n" << r.err;
  EXPECT_TRUE(j.contains("results")) << command;
  if (success) {
    EXPECT_TRUE(j["results"].is_object()) << command;
  }
  EXPECT_TRUE(j["errors"].is_array()) << command;
  EXPECT_TRUE(j["warnings"].is_array()) << command;
  if (success) {
    EXPECT_TRUE(j["errors"].empty()) << command << ": " << j["errors"].dump();
  } else {
    EXPECT_FALSE(j["errors"].empty()) << command;
    for (const auto& e : j["errors"]) EXPECT_TRUE(e["message"].is_string()) << e.dump();
  }
  return j;
}

/// The header of a CSV file.
std::vector<std::string> CsvHeader(const fs::path& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> columns;
  std::stringstream all(line);
  for (std::string c; std::getline(all, c, ',');) columns.push_back(c);
  return columns;
}

/// Whether `trial` (a trial's JSON) holds `column` of results.csv: as a key, or as the x or y
/// element of a [x, y] key ("v_SC_before_x_m_s" is "v_SC_before_m_s"[0]).
bool HoldsColumn(const json& trial, const std::string& column) {
  if (trial.contains(column)) return true;
  for (const char* axis : {"_x_", "_y_"}) {
    const auto at = column.rfind(axis);
    if (at == std::string::npos) continue;
    const std::string key = column.substr(0, at) + "_" + column.substr(at + 3);
    if (trial.contains(key) && trial[key].is_array() && trial[key].size() == 2) return true;
  }
  return false;
}

TEST(JsonEnvelopeTest, SimulateFitAndSynth) {
  // simulate: a normal impact without friction or gravity rebounds with the closed-form e of
  // the two-phase law at its zeta (docs/science.md).
  auto r = RunHoofimpact("simulate --k 1e8 --zeta 0.3 --mu 0 --gravity-m-s2 0 --json");
  auto j = Envelope(r, "simulate", true);
  EXPECT_NEAR(j["results"]["e"].get<double>(), dynamics::RestitutionOfTwoPhaseLaw(0.3), 1e-4);

  // fit: rebound speeds at e = 0.5 of the approach, without gravity: the zeta of that e, with
  // its interval under the names of /comparison/surfaces (zeta_ci_low, zeta_ci_high), not
  // zeta_ci95.
  const fs::path csv = Fresh("impacts.csv");
  {
    std::ofstream out(csv);
    out << "surface,v_before_m_s,v_after_m_s\n";
    for (double v : {1.5, 2.0, 2.5, 3.0, 3.5, 4.0}) out << "steel," << -v << "," << 0.5 * v << "\n";
  }
  r = RunHoofimpact("fit " + csv.string() + " --gravity-m-s2 0 --json");
  j = Envelope(r, "fit", true);
  ASSERT_EQ(j["results"]["groups"].size(), 1u);
  const json g = j["results"]["groups"][0];
  EXPECT_FALSE(g.contains("zeta_ci95"));
  EXPECT_LE(g["zeta_ci_low"].get<double>(), g["zeta"].get<double>());
  EXPECT_GE(g["zeta_ci_high"].get<double>(), g["zeta"].get<double>());
  EXPECT_NEAR(g["zeta"].get<double>(), dynamics::DampingRatioFromRestitution(0.5), 1e-3);

  // synth: one short trial.
  const fs::path trial = Fresh("trial");
  r = RunHoofimpact("synth -o " + trial.string() +
                    " --surface steel --angle-deg 0 --frames-before 4 --frames-after 4 --json");
  j = Envelope(r, "synth", true);
  ASSERT_EQ(j["results"]["trials"].size(), 1u);
  EXPECT_TRUE(j["results"]["trials"][0]["success"].get<bool>());
  EXPECT_EQ(j["results"]["trials"][0]["frames"], 8);
}

TEST(JsonEnvelopeTest, TrackAnalyzeScoreAndStatsOfATableOnTheSampleTrials) {
  auto r = RunHoofimpact("track " + kSample + "/steel_20deg_v3.28_r1 --json");
  auto j = Envelope(r, "track", true);
  const json& t = j["results"];
  EXPECT_EQ(t["id"], "steel_20deg_v3.28_r1");
  EXPECT_FALSE(t.contains("e_ci95"));
  EXPECT_FALSE(t.contains("mu_eff_ci95"));
  EXPECT_LT(t["e_ci_low"].get<double>(), t["e"].get<double>());
  EXPECT_GT(t["e_ci_high"].get<double>(), t["e"].get<double>());
  EXPECT_LT(t["mu_eff_ci_low"].get<double>(), t["mu_eff"].get<double>());

  // analyze: every column of results.csv is a key of each trial's JSON (under its own name).
  const fs::path out = Fresh("analyze");
  fs::create_directories(out);
  r = RunHoofimpact("analyze " + kSample + " -o " + (out / "study.h5").string() +
                    " --results-csv " + (out / "results.csv").string() + " --jobs 2 --json");
  j = Envelope(r, "analyze", true);
  ASSERT_EQ(j["results"]["trials"].size(), 4u);
  EXPECT_EQ(j["results"]["measured"], 4);
  const auto columns = CsvHeader(out / "results.csv");
  ASSERT_GT(columns.size(), 20u);
  for (const auto& trial : j["results"]["trials"])
    for (const auto& c : columns)
      if (c != "group") {  // the trial's group in the HDF5 file, not a property of the trial
        EXPECT_TRUE(HoldsColumn(trial, c)) << c;
      }

  // stats of this table by surface: two of the three surfaces have one trial, too few for a
  // variance. A failure in the envelope, naming the table.
  r = RunHoofimpact("stats " + (out / "results.csv").string() +
                    " --response e --factor surface --json");
  j = Envelope(r, "stats", false);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(j["errors"][0]["message"].get<std::string>().find("results.csv"), std::string::npos);

  r = RunHoofimpact("score " + kSample + " --jobs 2 --json");
  j = Envelope(r, "score", true);
  EXPECT_EQ(j["results"]["summary"]["succeeded"], 4);
  EXPECT_LT(j["results"]["summary"]["e_max_abs"].get<double>(), 1e-3);
  fs::remove_all(out.parent_path());
}

TEST(JsonEnvelopeTest, RunThenStatsFiguresReportOverlayAndDiscoverOnASmallStudy) {
  const fs::path study = hoof::testing::TestStudyDir("report_4");
  const fs::path out = Fresh("run");
  auto r = RunHoofimpact("run " + study.string() + " -o " + out.string() + " --jobs 2 --json");
  auto j = Envelope(r, "run", true);
  const json res = j["results"];
  EXPECT_EQ(res["measured"], 4);
  EXPECT_EQ(res["trials"].size(), 4u);
  ASSERT_EQ(res["surfaces"].size(), 2u);  // steel and asphalt
  for (const auto& s : res["surfaces"]) {
    // No scatter: the fitted zeta is the surface's (asphalt 0.2, steel 0.1 within the
    // interval).
    EXPECT_TRUE(s["success"].get<bool>()) << s.dump();
    EXPECT_TRUE(s.contains("zeta_ci_low") && s.contains("zeta_ci_high")) << s.dump();
  }
  EXPECT_TRUE(res["statistics"].is_object());
  EXPECT_TRUE(res["discovery"].is_null());
  EXPECT_TRUE(fs::exists(res["report_html"].get<std::string>()));
  const std::string h5 = res["study_h5"].get<std::string>();
  ASSERT_TRUE(fs::exists(h5));
  // The step text went to stderr: stdout is the envelope alone (parsed whole above).
  EXPECT_NE(r.err.find("Measuring"), std::string::npos);

  r = RunHoofimpact("stats " + h5 + " --json");
  j = Envelope(r, "stats", true);
  // stats of a table: the table as the positional input (--csv was its earlier spelling).
  const std::string table = res["results_csv"].get<std::string>();
  r = RunHoofimpact("stats " + table + " --response e --factor surface --json");
  j = Envelope(r, "stats", true);
  EXPECT_EQ(j["results"]["input"]["observations"], 4);
  const auto old = RunHoofimpact("stats --csv " + table + " --response e --factor surface --json");
  EXPECT_EQ(old.out, r.out);

  r = RunHoofimpact("figures " + h5 + " -o " + (out / "figs").string() + " --json");
  j = Envelope(r, "figures", true);
  EXPECT_FALSE(j["results"]["figures"].empty());
  for (const auto& f : j["results"]["figures"]) EXPECT_TRUE(fs::exists(f.get<std::string>()));

  r = RunHoofimpact("report " + h5 + " -o " + (out / "page").string() +
                    " --replay-trials 0 --json");
  j = Envelope(r, "report", true);
  EXPECT_TRUE(fs::exists(j["results"]["output"].get<std::string>()));
  EXPECT_EQ(j["results"]["trials"], 4);

  const std::string id = res["trials"][0]["id"].get<std::string>();
  r = RunHoofimpact("overlay " + h5 + " " + id + " -o " + (out / "overlay").string() +
                    " --frames-only --json");
  j = Envelope(r, "overlay", true);
  EXPECT_EQ(j["results"]["id"], id);
  EXPECT_GT(j["results"]["frames"].get<int>(), 0);

  // Four trials are too few for the discovery workflow: an envelope with success false, the
  // reason and the file in its errors, exit 1.
  r = RunHoofimpact("discover " + h5 + " -o " + (out / "d.h5").string() +
                    " --folds 2 --rounds 1 --jobs 2 --json");
  j = Envelope(r, "discover", false);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_FALSE(j["results"]["success"].get<bool>());
  ASSERT_FALSE(j["errors"].empty());
  EXPECT_EQ(j["errors"][0].value("file", ""), (out / "d.h5").string());
  fs::remove_all(out.parent_path());
}

TEST(JsonEnvelopeTest, DiscoverOnAStudyItCanRun) {
  const fs::path study = hoof::testing::TestStudyDir("figures_16");
  const fs::path out = Fresh("discover");
  auto r =
      RunHoofimpact("analyze " + study.string() + " -o " + (out / "s.h5").string() + " --jobs 2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = RunHoofimpact("discover " + (out / "s.h5").string() +
                    " --folds 2 --rounds 1 --candidates hunt_crossley --jobs 2 --json");
  auto j = Envelope(r, "discover", true);
  EXPECT_TRUE(j["results"]["success"].get<bool>());
  EXPECT_TRUE(j["results"]["rounds"].is_array());
  fs::remove_all(out.parent_path());
}

TEST(JsonEnvelopeTest, FailuresAreEnvelopesNamingTheOptionOrTheFile) {
  // A value out of range: exit 2, the option as the user typed it.
  auto r = RunHoofimpact("simulate --angle-deg 95 --json");
  auto j = Envelope(r, "simulate", false);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(j["errors"][0].value("option", ""), "--angle-deg") << j.dump();
  EXPECT_TRUE(j["results"].is_null());
  // A missing input file: exit 1, the file named.
  r = RunHoofimpact("figures /nonexistent-dir/study.h5 -o /tmp --json");
  j = Envelope(r, "figures", false);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(j["errors"][0].value("file", ""), "/nonexistent-dir/study.h5") << j.dump();
  // A trial that cannot be measured: the envelope names the trial.
  const fs::path broken = Fresh("broken");
  fs::create_directories(broken);
  fs::copy(kSample + "/steel_0deg_v3.00_r1", broken / "t", fs::copy_options::recursive);
  for (const auto& e : fs::directory_iterator(broken / "t" / "frames"))
    if (e.path().extension() == ".png") {
      std::ofstream(e.path(), std::ios::trunc) << "not a png";
    }
  r = RunHoofimpact("track " + (broken / "t").string() + " --json");
  j = Envelope(r, "track", false);
  EXPECT_EQ(r.exit_code, 1);
  ASSERT_FALSE(j["errors"].empty());
  fs::remove_all(broken.parent_path());
}

TEST(JsonEnvelopeTest, EveryCommandTakesJson) {
  const auto help = RunHoofimpact("--help");
  std::set<std::string> commands;
  for (const char* c : {"simulate", "fit", "stats", "synth", "track", "init", "run", "analyze",
                        "score", "figures", "report", "overlay", "discover"}) {
    EXPECT_NE(help.out.find(std::string("  ") + c), std::string::npos) << c;
    const auto h = RunHoofimpact(std::string(c) + " --help");
    EXPECT_NE(h.out.find("--json"), std::string::npos) << c;
    commands.insert(c);
  }
  EXPECT_EQ(commands.size(), 13u);
}

}  // namespace
}  // namespace hoof::cli
