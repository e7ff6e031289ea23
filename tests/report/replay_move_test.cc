// A report that moves with its study (issue 15): a small study is copied, run, and its folder
// (study and outputs) moved; `report --study-dir` finds the replay frames at their new place,
// and without it the page and stderr name every missing trial folder while the report still
// succeeds. The page also states how it and the study file were made, and carries the replay
// glyphs and the residual magnification (compare/replay_convention.h) in its replay JSON.
#include <algorithm>
#include <filesystem>
#include <regex>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include "compare/replay_convention.h"
#include "support/run_command.h"
#include "support/test_studies.h"
#include "support/test_util.h"

namespace hoof::report {
namespace {

namespace fs = std::filesystem;
using hoof::testing::ReadAll;
using hoof::testing::RunHoofimpact;

fs::path Root() {
  return fs::path(HOOF_BINARY_DIR) / "test-output" / ("replay_move_" + std::to_string(::getpid()));
}

/// Occurrences of `needle` in `text`.
int Count(const std::string& text, const std::string& needle) {
  int n = 0;
  for (auto p = text.find(needle); p != std::string::npos; p = text.find(needle, p + 1)) ++n;
  return n;
}

/// The page's replay JSON.
nlohmann::json ReplayData(const std::string& html) {
  const std::string open = "<script type=\"application/json\" id=\"replay-data\">";
  const auto a = html.find(open);
  if (a == std::string::npos) return {};
  const auto b = html.find("</script>", a);
  return nlohmann::json::parse(html.substr(a + open.size(), b - a - open.size()));
}

/// report_4 copied to Root()/before/study and run into Root()/before/out, then the whole
/// folder moved to Root()/after.
class ReplayMoveTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    fs::remove_all(Root());
    fs::create_directories(Root() / "before");
    fs::copy(hoof::testing::TestStudyDir("report_4"), Root() / "before" / "study",
             fs::copy_options::recursive);
    const auto r = RunHoofimpact("run " + (Root() / "before" / "study").string() + " -o " +
                                 (Root() / "before" / "out").string() + " --jobs 2");
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    fs::rename(Root() / "before", Root() / "after");
  }
  static void TearDownTestSuite() { fs::remove_all(Root()); }
  static fs::path H5() { return Root() / "after" / "out" / "study.h5"; }
  static fs::path NewStudy() { return Root() / "after" / "study"; }
  static fs::path OldStudy() { return Root() / "before" / "study"; }
};

TEST_F(ReplayMoveTest, WithTheStudyDirTheReplayFramesAreInThePage) {
  const std::string cmd = "report " + H5().string() + " -o " + (Root() / "r1").string() +
                          " --study-dir " + NewStudy().string();
  const auto r = RunHoofimpact(cmd);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("4 replays"), std::string::npos) << r.out;
  EXPECT_EQ(r.err.find("not drawn"), std::string::npos) << r.err;
  const std::string html = ReadAll(Root() / "r1" / "report.html");
  const nlohmann::json data = ReplayData(html);
  ASSERT_TRUE(data.contains("trials")) << data.dump().substr(0, 500);
  ASSERT_EQ(data["trials"].size(), 4u);
  // One <img class="frame"> per replayed frame: 20 frames per replay (the default) for each of
  // the four trials, each read from its folder under the new study folder.
  std::size_t frames = 0;
  for (const auto& t : data["trials"]) {
    frames += t["frames"].size();
    EXPECT_EQ(t["frames"].size(), 20u) << t["id"];
    const std::string folder = t["folder"].get<std::string>();
    EXPECT_EQ(folder.rfind(NewStudy().string(), 0), 0u) << folder;
  }
  EXPECT_EQ(Count(html, "<img class=\"frame\""), static_cast<int>(frames));
  EXPECT_EQ(frames, 80u);
  EXPECT_EQ(html.find("could not be drawn"), std::string::npos);
}

TEST_F(ReplayMoveTest, WithoutItThePageAndStderrNameTheMissingFolders) {
  const auto r = RunHoofimpact("report " + H5().string() + " -o " + (Root() / "r2").string());
  // A missing replay is not a failure of the report (docs/cli.md, report).
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("0 replays"), std::string::npos) << r.out;
  const std::string html = ReadAll(Root() / "r2" / "report.html");
  EXPECT_EQ(Count(html, "<img class=\"frame\""), 0);
  EXPECT_EQ(ReplayData(html)["trials"].size(), 0u);
  EXPECT_NE(html.find("4 replay(s) could not be drawn"), std::string::npos);
  // Each trial: its id and its recorded (now missing) folder, on stderr and in the page.
  int named = 0;
  for (const auto& e : fs::directory_iterator(NewStudy())) {
    if (!fs::exists(e.path() / "trial.json")) continue;
    const std::string id = e.path().filename().string();
    const std::string recorded = (OldStudy() / id).string();
    EXPECT_NE(r.err.find("replay of trial " + id +
                         " not drawn: no trial.json in its recorded "
                         "folder " +
                         recorded),
              std::string::npos)
        << r.err;
    EXPECT_NE(html.find("<li>" + id + ": no trial.json in its recorded folder " + recorded),
              std::string::npos)
        << id;
    ++named;
  }
  EXPECT_EQ(named, 4);
  EXPECT_NE(r.err.find("--study-dir"), std::string::npos) << r.err;
}

TEST_F(ReplayMoveTest, TheOverlayFindsTheMovedTrialToo) {
  std::string id;
  for (const auto& e : fs::directory_iterator(NewStudy()))
    if (fs::exists(e.path() / "trial.json")) id = e.path().filename().string();
  ASSERT_FALSE(id.empty());
  auto r = RunHoofimpact("overlay " + H5().string() + " " + id + " -o " +
                         (Root() / "ov1").string() + " --frames-only");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("no trial.json in its recorded folder " + (OldStudy() / id).string()),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("--study-dir"), std::string::npos) << r.err;
  r = RunHoofimpact("overlay " + H5().string() + " " + id + " -o " + (Root() / "ov2").string() +
                    " --frames-only --study-dir " + NewStudy().string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(Root() / "ov2" / id / "frame_000000.png"));
}

TEST_F(ReplayMoveTest, ThePageSaysHowItWasMade) {
  const auto r = RunHoofimpact("report " + H5().string() + " -o " + (Root() / "r3").string() +
                               " --study-dir " + NewStudy().string() + " --residual-scale 7");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string html = ReadAll(Root() / "r3" / "report.html");
  const auto at = html.find("id=\"provenance\"");
  ASSERT_NE(at, std::string::npos);
  const std::string block = html.substr(at, html.find("</section>", at) - at);
  // The report's own command line, as typed.
  EXPECT_NE(
      block.find("<code>hoofimpact report " + H5().string() + " -o " + (Root() / "r3").string() +
                 " --study-dir " + NewStudy().string() + " --residual-scale 7</code>"),
      std::string::npos)
      << block;
  // The command line that made the study file (`run`, before the move), and the version.
  EXPECT_NE(block.find("<code>hoofimpact run " + OldStudy().string() + " -o " +
                       (Root() / "before" / "out").string() + " --jobs 2</code>"),
            std::string::npos)
      << block;
  EXPECT_NE(block.find("hoofimpact 0.1.0"), std::string::npos) << block;
  // The analysis options (/study/analysis_options at their defaults: 20 frames per fit, 95 %
  // intervals), the statistics' options (their alpha), the report's options.
  EXPECT_NE(block.find("<code>fit_frames</code> = 20 "), std::string::npos) << block;
  EXPECT_NE(block.find("<code>confidence</code> = 0.9500"), std::string::npos) << block;
  EXPECT_NE(block.find("Statistics options"), std::string::npos);
  EXPECT_NE(block.find("alpha 0.05"), std::string::npos) << block;
  EXPECT_NE(block.find("residual scale = 7&times;"), std::string::npos) << block;
  EXPECT_NE(block.find("no discovery in the study file"), std::string::npos) << block;
  // The replay JSON carries the magnification and the glyphs of the one convention, and the
  // legend states F.
  const nlohmann::json data = ReplayData(html);
  EXPECT_EQ(data["residual_scale"], 7);
  for (const auto* g :
       {&compare::replay::kMeasured, &compare::replay::kSimulated, &compare::replay::kResidual}) {
    EXPECT_EQ(data["glyphs"][g->key]["colour"], compare::replay::HexColour(*g)) << g->key;
    EXPECT_EQ(data["glyphs"][g->key]["shape"], compare::replay::ShapeName(g->shape)) << g->key;
  }
  EXPECT_EQ(data["glyphs"]["measured"]["shape"], "ring");
  EXPECT_EQ(data["glyphs"]["simulated"]["shape"], "plus");
  EXPECT_NE(html.find("magnified <b id=\"residual-scale\">7&times;</b>"), std::string::npos);
}

TEST_F(ReplayMoveTest, BadOptionsAreCommandLineErrors) {
  for (const auto& [args, option] :
       {std::pair<std::string, std::string>{"--residual-scale 0", "--residual-scale"},
        {"--residual-scale 5000", "--residual-scale"},
        {"--study-dir " + (Root() / "nowhere").string(), "--study-dir"}}) {
    const auto r =
        RunHoofimpact("report " + H5().string() + " -o " + (Root() / "bad").string() + " " + args);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.err;
    EXPECT_NE(r.err.find(option), std::string::npos) << args << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(Root() / "bad" / "report.html"));
}

}  // namespace
}  // namespace hoof::report
