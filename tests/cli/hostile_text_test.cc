// Shell and gnuplot metacharacters in every text field of study.json and trial.json: every
// command that draws, reports or replays must run none of them and still show the text as
// written. The fields: the study's name, the specimen's id, the marker names, the
// trial's id, surface and notes.
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/run_command.h"

namespace {

namespace fs = std::filesystem;
using hoof::testing::RunHoofimpact;

/// A text that would run `touch <mark>` in a shell (both $(...) and backquotes) or in gnuplot
/// (backquotes), with quotes, a semicolon and a backslash besides.
std::string Hostile(const std::string& mark) {
  return "x$(touch " + mark + "a)`touch " + mark + "b`; echo 'q' \"dq\" \\\\ @m";
}

/// The same for an id (of a trial, a specimen or a marker), which names files and tables: no '/'
/// or '\\' (refused there), so the mark is made in the working folder.
std::string HostileId(const std::string& mark) {
  return "x$(touch " + mark + "a)`touch " + mark + "b`; echo 'q' \"dq\" @m";
}

class HostileTextTest : public ::testing::Test {
 protected:
  static fs::path Root() { return fs::path(HOOF_BINARY_DIR) / "test-output" / "hostile_text"; }
  static fs::path Marks() { return Root() / "marks"; }
  /// Every file a metacharacter could have made: in the marks folder (absolute) and in the
  /// working folder (relative).
  static std::vector<fs::path> Made() {
    std::vector<fs::path> made;
    for (const fs::path& dir : {Marks(), fs::current_path()})
      if (fs::exists(dir))
        for (const auto& e : fs::directory_iterator(dir))
          if (e.path().filename().string().rfind("RAN", 0) == 0) made.push_back(e.path());
    return made;
  }

  static void SetUpTestSuite() {
    fs::remove_all(Root());
    fs::create_directories(Marks());
    const fs::path study = Root() / "study";
    fs::copy(fs::path(HOOF_SOURCE_DIR) / "sample_frames", study, fs::copy_options::recursive);
    const std::string m = (Marks() / "RAN").string();
    nlohmann::json s = nlohmann::json::parse(std::ifstream(study / "study.json"));
    s["name"] = Hostile(m + "name");
    nlohmann::json specimen = s["specimens"]["A"];
    nlohmann::json markers = nlohmann::json::object();
    int k = 0;
    for (const auto& [name, p] : specimen["markers_B_m"].items())
      markers[name + HostileId("RANmarker" + std::to_string(k++))] = p;
    specimen["markers_B_m"] = markers;
    s["specimens"] = {{HostileId("RANspecimen"), specimen}};
    std::ofstream(study / "study.json") << s.dump(1);
    for (const auto& t : s["trials"]) {
      const fs::path file = study / t.get<std::string>() / "trial.json";
      nlohmann::json j = nlohmann::json::parse(std::ifstream(file));
      j["specimen"] = HostileId("RANspecimen");
      j["id"] = j["id"].get<std::string>() + HostileId("RANid");
      j["surface"] = j["surface"].get<std::string>() + Hostile(m + "surface");
      j["notes"] = Hostile(m + "notes");
      std::ofstream(file) << j.dump(1);
    }
  }
};

TEST_F(HostileTextTest, NoCommandRunsAndTheTextReadsAsWritten) {
  const fs::path study = Root() / "study";
  const fs::path out = Root() / "out";
  const std::string first = "steel_0deg_v3.00_r1";
  struct Step {
    std::string args;
    int exit_code;
  };
  const std::vector<Step> steps = {
      {"analyze " + study.string() + " -o " + (out / "a.h5").string() + " --figures " +
           (out / "afig").string(),
       0},
      {"track " + (study / first).string() + " --figures " + (out / "tfig").string(), 0},
      {"run " + study.string() + " -o " + (out / "run").string() + " --trial-figures", 0},
      {"figures " + (out / "run" / "study.h5").string() + " -o " + (out / "ffig").string(), 0},
      {"report " + (out / "run" / "study.h5").string() + " -o " + (out / "report").string(), 0},
  };
  for (const Step& s : steps) {
    const auto r = RunHoofimpact(s.args);
    EXPECT_EQ(r.exit_code, s.exit_code) << s.args << "\n" << r.out << r.err;
    for (const auto& made : Made())
      ADD_FAILURE() << s.args << " ran a command from the data: it made " << made;
  }
  // The labels read as written: the surface in the report (HTML-escaped) and a trial's figure
  // named by its id.
  std::ifstream page(out / "run" / "report.html");
  const std::string html((std::istreambuf_iterator<char>(page)), std::istreambuf_iterator<char>());
  EXPECT_NE(html.find("steelx$(touch "), std::string::npos);
  EXPECT_NE(html.find("`; echo &#39;q&#39; &quot;dq&quot;"), std::string::npos)
      << "the surface's quotes, escaped for HTML, are not in the report";
  bool figure_named_by_id = false;
  for (const auto& e : fs::directory_iterator(out / "tfig"))
    figure_named_by_id |= e.path().filename().string().rfind(first + "x$(touch ", 0) == 0;
  EXPECT_TRUE(figure_named_by_id);
}

}  // namespace
