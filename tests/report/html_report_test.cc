// The HTML report: the encoders against their standards' examples, and the page of a tiny
// rendered study (synth -> run -> report) opened in headless Chromium (Debian's `chromium`):
// it must render (not blank), run its scripts without an error, draw the replay with the
// overlay, hold every section, and need no network.
#include "report/html_report.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "support/run_command.h"
#include "support/test_studies.h"
#include "support/test_util.h"

namespace hoof::report {
namespace {

namespace fs = std::filesystem;
using hoof::testing::ReadAll;
using hoof::testing::RunHoofimpact;

TEST(HtmlEscapeTest, EscapesTheFiveSpecialCharacters) {
  EXPECT_EQ(HtmlEscape("a<b>&\"c'"), "a&lt;b&gt;&amp;&quot;c&#39;");
  EXPECT_EQ(HtmlEscape("plain"), "plain");
}

TEST(Base64Test, Rfc4648Examples) {  // RFC 4648 section 10
  EXPECT_EQ(Base64(""), "");
  EXPECT_EQ(Base64("f"), "Zg==");
  EXPECT_EQ(Base64("fo"), "Zm8=");
  EXPECT_EQ(Base64("foo"), "Zm9v");
  EXPECT_EQ(Base64("foob"), "Zm9vYg==");
  EXPECT_EQ(Base64("fooba"), "Zm9vYmE=");
  EXPECT_EQ(Base64("foobar"), "Zm9vYmFy");
  EXPECT_EQ(Base64(std::string("\xff\xfe\x00", 3)), "//4A");
}

TEST(HtmlReportOptionsTest, ValidateNamesTheField) {
  HtmlReportOptions o;
  o.jpeg_quality = 0;
  try {
    o.Validate();
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("jpeg_quality"), std::string::npos) << e.what();
  }
}

fs::path Root() {
  return fs::path(HOOF_BINARY_DIR) / "html_report_test" / std::to_string(::getpid());
}

/// Runs headless Chromium on `page` with `what` (--dump-dom or --screenshot=FILE); returns its
/// stdout, and its stderr in `err`.
std::string Chromium(const fs::path& page, const std::string& what, std::string& err) {
  static int run = 0;
  const fs::path dir = Root() / ("chromium" + std::to_string(++run));
  fs::create_directories(dir);
  const std::string cmd =
      "cd " + dir.string() +
      " && timeout 60 chromium --headless --no-sandbox --disable-gpu "
      "--disable-quic --no-first-run --disable-background-networking --disable-component-update "
      "--disable-sync --hide-scrollbars --user-data-dir=" +
      (dir / "profile").string() +
      " --enable-logging=stderr --v=0 --virtual-time-budget=10000 --window-size=1280,2000 " + what +
      " file://" + fs::absolute(page).string() + " >" + (dir / "out.txt").string() + " 2>" +
      (dir / "err.txt").string();
  const int rc = std::system(cmd.c_str());
  EXPECT_EQ(rc, 0) << cmd;
  err = ReadAll(dir / "err.txt");
  return ReadAll(dir / "out.txt");
}

/// Occurrences of `needle` in `text`.
int Count(const std::string& text, const std::string& needle) {
  int n = 0;
  for (auto p = text.find(needle); p != std::string::npos; p = text.find(needle, p + 1)) ++n;
  return n;
}

/// A study of 2 surfaces x 2 angles x 1 speed x 1 trial, run and reported once.
class HtmlReportPageTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    fs::remove_all(Root());
    auto r = RunHoofimpact("run " + hoof::testing::TestStudyDir("report_4").string() + " -o " +
                           (Root() / "out").string());
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    r = RunHoofimpact("report " + (Root() / "out" / "study.h5").string() + " -o " +
                      (Root() / "report").string());
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    // Figures: e and mu_eff by angle and by speed (4), velocities after normal and oblique
    // impacts (2), and the energy through one oblique impact per surface (2).
    EXPECT_NE(r.out.find("4 trials, 8 figures, 4 replays"), std::string::npos) << r.out << r.err;
  }
  static void TearDownTestSuite() { fs::remove_all(Root()); }
  static fs::path Page() { return Root() / "report" / "report.html"; }
};

TEST_F(HtmlReportPageTest, ScriptsRunWithoutErrorAndDrawTheReplay) {
  std::string err;
  const std::string dom = Chromium(Page(), "--dump-dom", err);
  ASSERT_FALSE(dom.empty()) << err;
  // The page's error trap (window.onerror, console.error) marks the title and <html>.
  EXPECT_FALSE(std::regex_search(dom, std::regex("<title>JS-ERROR"))) << dom.substr(0, 2000);
  EXPECT_FALSE(std::regex_search(dom, std::regex("<html[^>]* data-js-error=")));
  EXPECT_EQ(err.find("Uncaught"), std::string::npos) << err;
  // The replay script drew a frame of the first replay (it marks the body and the canvas).
  EXPECT_TRUE(std::regex_search(dom, std::regex("<body[^>]* data-replay-drawn=\"[^\"]+\"")))
      << dom.substr(0, 3000);
  EXPECT_TRUE(std::regex_search(dom, std::regex("<canvas[^>]* data-drawn-frame=\"[0-9]+\"")));
  // Every section, and the trial selector filled with the four replays.
  for (const char* id : {"summary", "model", "replay", "figures", "trials", "statistics"})
    EXPECT_NE(dom.find(std::string("<section id=\"") + id + "\""), std::string::npos) << id;
  EXPECT_EQ(Count(dom, "<option value="), 4);
  EXPECT_EQ(Count(dom, "<tr class=\"trial\">"), 4);  // the synthetic trials all measure
  for (const char* text :
       {"k not identified", "<h4>e by surface</h4>", "One-way ANOVA of e by angle",
        "e per surface and angle", "steel", "asphalt", "mu_eff_by_angle"})
    EXPECT_NE(dom.find(text), std::string::npos) << text;
}

TEST_F(HtmlReportPageTest, TheErrorTrapCatchesAScriptError) {
  // Negative control of the check above: the same page with a script that throws.
  std::string html = ReadAll(Page());
  html.insert(html.rfind("</body>"), "<script>notDefinedAnywhere();</script>");
  const fs::path broken = Root() / "broken.html";
  { std::ofstream(broken) << html; }
  std::string err;
  const std::string dom = Chromium(broken, "--dump-dom", err);
  EXPECT_TRUE(std::regex_search(dom, std::regex("<title>JS-ERROR[^<]*notDefinedAnywhere")))
      << dom.substr(0, 600);
  EXPECT_NE(err.find("Uncaught"), std::string::npos);
}

/// Pixels of the simulated markers' magenta (#ff2d95, compare/replay_convention.h) in `image`,
/// inside `rect` or outside it.
int Magenta(const cv::Mat& image, const cv::Rect& rect, bool inside) {
  int n = 0;
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) {
      if (rect.contains({x, y}) != inside) continue;
      const cv::Vec3b p = image.at<cv::Vec3b>(y, x);  // B, G, R
      if (p[2] >= 245 && std::abs(p[1] - 45) <= 15 && std::abs(p[0] - 149) <= 15) ++n;
    }
  return n;
}

TEST_F(HtmlReportPageTest, TheScreenshotIsNotBlankAndShowsTheOverlay) {
  // The replay canvas's place on the page, which the script records (data-rect).
  std::string err;
  const std::string dom = Chromium(Page(), "--dump-dom", err);
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      dom, m, std::regex("<canvas[^>]* data-rect=\"([0-9-]+),([0-9-]+),([0-9]+),([0-9]+)\"")))
      << err;
  const cv::Rect canvas(std::stoi(m[1]), std::stoi(m[2]), std::stoi(m[3]), std::stoi(m[4]));
  ASSERT_GT(canvas.area(), 1000);
  const fs::path png = Root() / "screenshot.png";
  Chromium(Page(), "--screenshot=" + png.string(), err);
  const cv::Mat image = cv::imread(png.string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(image.empty()) << err;
  EXPECT_EQ(image.cols, 1280);
  ASSERT_LE(canvas.y + canvas.height, image.rows) << "the canvas is below the screenshot";
  cv::Scalar mean, sd;
  cv::meanStdDev(image, mean, sd);
  EXPECT_GT(sd[0] + sd[1] + sd[2], 30.0);
  // Not nearly all one colour: the most common colour covers less than 80 % of the page.
  std::map<int, int> counts;
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) {
      const cv::Vec3b p = image.at<cv::Vec3b>(y, x);  // B, G, R
      ++counts[p[0] << 16 | p[1] << 8 | p[2]];
    }
  int most = 0;
  for (const auto& [c, n] : counts) most = std::max(most, n);
  EXPECT_LT(most, 0.8 * image.rows * image.cols);
  // The simulated markers drawn on the canvas, and the legend's glyph in the same colour.
  EXPECT_GT(Magenta(image, canvas, true), 20);
  EXPECT_GT(Magenta(image, canvas, false), 5);
  // Negative control: with the overlay turned off (the page reads #overlay=off) none is drawn
  // on the canvas; the legend still shows its glyph.
  const fs::path off = Root() / "screenshot-off.png";
  Chromium(Page().string() + "#overlay=off", "--screenshot=" + off.string(), err);
  const cv::Mat plain = cv::imread(off.string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(plain.empty()) << err;
  EXPECT_EQ(Magenta(plain, canvas, true), 0);
  EXPECT_GT(Magenta(plain, canvas, false), 5);
}

TEST_F(HtmlReportPageTest, NeedsNoNetwork) {
  const std::string html = ReadAll(Page());
  EXPECT_FALSE(std::regex_search(
      html, std::regex("(src|href)\\s*=\\s*[\"']?\\s*(https?:)?//", std::regex::icase)));
  EXPECT_EQ(html.find("<link"), std::string::npos);  // no external style sheets
  EXPECT_LT(fs::file_size(Page()), 3u << 20);        // and stays small enough to mail
}

TEST_F(HtmlReportPageTest, AStudyFileWithoutTheComparisonIsAClearError) {
  const fs::path h5 = Root() / "analyzed.h5";
  auto r = RunHoofimpact("analyze " + hoof::testing::TestStudyDir("report_4").string() + " -o " +
                         h5.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = RunHoofimpact("report " + h5.string() + " -o " + (Root() / "no-comparison").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find(h5.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("run `hoofimpact run` first"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(Root() / "no-comparison" / "report.html"));
}

TEST(HtmlReportCommandTest, AMissingStudyFileIsAClearError) {
  auto r = RunHoofimpact("report /nonexistent/study.h5 -o " + (Root() / "x").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("/nonexistent/study.h5"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace hoof::report
