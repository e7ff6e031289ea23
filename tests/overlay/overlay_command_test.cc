// `hoofimpact overlay` end to end: a tiny rendered study is run, and one trial's overlay is
// checked against its input frames and the stored simulation.
#include <cmath>
#include <filesystem>
#include <string>
#include <variant>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "studyfile/study_file.h"
#include "support/run_command.h"
#include "support/test_studies.h"

namespace hoof::cli {
namespace {

namespace fs = std::filesystem;
using hoof::testing::RunHoofimpact;

class OverlayCommandTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    base_ = fs::path(HOOF_BINARY_DIR) / "test-output" / ("overlay_" + std::to_string(::getpid()));
    fs::remove_all(base_);
    const auto r = RunHoofimpact("run " + hoof::testing::TestStudyDir("overlay_2").string() +
                                 " -o " + (base_ / "out").string());
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  }
  static void TearDownTestSuite() { fs::remove_all(base_); }
  static fs::path H5() { return base_ / "out" / "study.h5"; }
  static fs::path base_;
};
fs::path OverlayCommandTest::base_;

std::vector<fs::path> PngsIn(const fs::path& dir) {
  std::vector<fs::path> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.path().extension() == ".png") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

TEST_F(OverlayCommandTest, FramesAndVideoOfTheObliqueTrial) {
  const auto results = studyfile::ReadStudyResults(H5());
  ASSERT_EQ(results.trials.size(), 2u);
  const auto& trial =
      results.trials[1].surface_angle_deg > 0 ? results.trials[1] : results.trials[0];
  const fs::path x = base_ / "overlay";
  const auto r = RunHoofimpact("overlay " + H5().string() + " " + trial.id + " -o " + x.string() +
                               " --slow 2");
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;

  // One PNG per input frame, the same size, in colour.
  const auto inputs =
      PngsIn(fs::path(trial.dir).is_absolute()
                 ? fs::path(trial.dir)
                 : hoof::testing::TestStudyDir("overlay_2") / fs::path(trial.dir).filename());
  const fs::path dir = x / trial.id;
  std::vector<fs::path> outputs;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".png") outputs.push_back(e.path());
  ASSERT_FALSE(inputs.empty());
  ASSERT_EQ(outputs.size(), inputs.size());
  const cv::Mat in0 = cv::imread(inputs.front().string(), cv::IMREAD_UNCHANGED);
  for (const char* name : {"frame_000000.png", "frame_000012.png"}) {
    const cv::Mat out = cv::imread((dir / name).string(), cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(out.empty()) << name;
    EXPECT_EQ(out.size(), in0.size()) << name;
    EXPECT_EQ(out.channels(), 3) << name;
  }

  // At frame 12 the simulated markers are drawn: red pixels (red well above green and blue)
  // near every simulated centre, where the grey input has none.
  const auto frames = studyfile::ReadTable(H5(), "/comparison/frames/" + trial.id);
  const cv::Mat in12 = cv::imread(inputs[12].string(), cv::IMREAD_COLOR);
  const cv::Mat out12 = cv::imread((dir / "frame_000012.png").string(), cv::IMREAD_COLOR);
  int markers = 0;
  for (const auto& c : frames.columns) {
    const std::string suffix = "_sim_x_px";
    if (c.name.size() < suffix.size() ||
        c.name.compare(c.name.size() - suffix.size(), suffix.size(), suffix) != 0)
      continue;
    const std::string m = c.name.substr(0, c.name.size() - suffix.size());
    const double cx = std::get<std::vector<double>>(c.values)[12];
    const double cy = std::get<std::vector<double>>(frames.Get(m + "_sim_y_px").values)[12];
    ASSERT_TRUE(std::isfinite(cx) && std::isfinite(cy)) << m;
    int red_out = 0, red_in = 0;
    for (int y = static_cast<int>(cy) - 15; y <= static_cast<int>(cy) + 15; ++y)
      for (int xx = static_cast<int>(cx) - 15; xx <= static_cast<int>(cx) + 15; ++xx) {
        if (y < 0 || xx < 0 || y >= out12.rows || xx >= out12.cols) continue;
        const auto o = out12.at<cv::Vec3b>(y, xx), i = in12.at<cv::Vec3b>(y, xx);
        red_out += o[2] > o[1] + 80 ? 1 : 0;
        red_in += i[2] > i[1] + 80 ? 1 : 0;
      }
    EXPECT_GT(red_out, 10) << m;
    EXPECT_EQ(red_in, 0) << m;
    ++markers;
  }
  EXPECT_GE(markers, 2);

  // The video: each frame shown twice (--slow 2).
  fs::path video;
  for (const char* v : {"overlay.webm", "overlay.avi"})
    if (fs::exists(dir / v)) video = dir / v;
  if (video.empty()) GTEST_SKIP() << "no video encoder: " << r.err;
  EXPECT_NE(r.out.find(video.filename().string()), std::string::npos) << r.out;
  cv::VideoCapture cap(video.string());
  ASSERT_TRUE(cap.isOpened()) << video;
  int read = 0;
  for (cv::Mat f; cap.read(f);) ++read;
  EXPECT_EQ(read, 2 * static_cast<int>(inputs.size())) << video;
  EXPECT_NEAR(cap.get(cv::CAP_PROP_FRAME_COUNT), 2.0 * static_cast<double>(inputs.size()), 1.0)
      << video;
}

TEST_F(OverlayCommandTest, AnUnknownTrialIsAClearError) {
  const auto r =
      RunHoofimpact("overlay " + H5().string() + " no_such_trial -o " + (base_ / "bad").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("no_such_trial"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(base_ / "bad" / "no_such_trial"));
}

}  // namespace
}  // namespace hoof::cli
