// `hoofimpact overlay` end to end: a tiny rendered study is run, and one trial's overlay is
// checked against its input frames and the stored simulation.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>
#include <Eigen/Core>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "compare/replay_convention.h"
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

/// The number of frames of a video, read one by one, and its frame rate; -1 when there is no
/// video in `dir` (no encoder).
std::pair<int, double> VideoFrames(const fs::path& dir) {
  fs::path video;
  for (const char* v : {"overlay.webm", "overlay.avi"})
    if (fs::exists(dir / v)) video = dir / v;
  if (video.empty()) return {-1, 0.0};
  cv::VideoCapture cap(video.string());
  EXPECT_TRUE(cap.isOpened()) << video;
  int read = 0;
  for (cv::Mat f; cap.read(f);) ++read;
  return {read, cap.get(cv::CAP_PROP_FPS)};
}

/// A column of doubles of a table.
const std::vector<double>& Doubles(const studyfile::Table& t, const std::string& name) {
  return std::get<std::vector<double>>(t.Get(name).values);
}

TEST_F(OverlayCommandTest, FramesAndVideoOfTheObliqueTrial) {
  const auto results = studyfile::ReadStudyResults(H5());
  ASSERT_EQ(results.trials.size(), 2u);
  const auto& trial =
      results.trials[1].surface_angle_deg > 0 ? results.trials[1] : results.trials[0];
  ASSERT_EQ(trial.fps, 8000.0);  // the expectations below are for an 8000 fps capture
  const fs::path x = base_ / "overlay";
  const auto r = RunHoofimpact("overlay " + H5().string() + " " + trial.id + " -o " + x.string());
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

  // At frame 12 the simulated markers are drawn: magenta pixels (red well above green) near
  // every simulated centre, where the grey input has none.
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

  // The video by default: 1/1000 of real time, i.e. 8 captured frames per second; each frame
  // written ceil(20 / 8) = 3 times, at 24 fps.
  const auto [read, fps] = VideoFrames(dir);
  if (read < 0) GTEST_SKIP() << "no video encoder: " << r.err;
  EXPECT_NE(r.out.find("1/1000 of real time, 8 frames/s"), std::string::npos) << r.out;
  EXPECT_EQ(read, 3 * static_cast<int>(inputs.size()));
  EXPECT_NEAR(fps, 24.0, 0.01);
  // --slowdown 400: 20 captured frames per second, each written once, at 20 fps.
  const fs::path x400 = base_ / "overlay400";
  auto r400 = RunHoofimpact("overlay " + H5().string() + " " + trial.id + " -o " + x400.string() +
                            " --slowdown 400 --video-only");
  ASSERT_EQ(r400.exit_code, 0) << r400.err;
  const auto [read400, fps400] = VideoFrames(x400 / trial.id);
  EXPECT_EQ(read400, static_cast<int>(inputs.size()));
  EXPECT_NEAR(fps400, 20.0, 0.01);
  EXPECT_TRUE(PngsIn(x400 / trial.id).empty());
  // --slowdown 20 would need 400 fps: the video runs at 60 fps, slower than asked, and says so.
  const fs::path x20 = base_ / "overlay20";
  auto r20 = RunHoofimpact("overlay " + H5().string() + " " + trial.id + " -o " + x20.string() +
                           " --slowdown 20 --video-only");
  ASSERT_EQ(r20.exit_code, 0) << r20.err;
  EXPECT_NE(r20.err.find("1/133 of real time"), std::string::npos) << r20.err;
  const auto [read20, fps20] = VideoFrames(x20 / trial.id);
  EXPECT_EQ(read20, static_cast<int>(inputs.size()));
  EXPECT_NEAR(fps20, 60.0, 0.01);
}

TEST_F(OverlayCommandTest, TheResidualArrowEndsWhereTheStoredResidualPutsIt) {
  const auto results = studyfile::ReadStudyResults(H5());
  const auto& trial =
      results.trials[1].surface_angle_deg > 0 ? results.trials[1] : results.trials[0];
  const auto frames = studyfile::ReadTable(H5(), "/comparison/frames/" + trial.id);
  // The marker and frame of the largest stored residual |simulated - measured|.
  std::string marker;
  std::size_t frame = 0;
  double largest = 0;
  for (const auto& c : frames.columns) {
    const std::string suffix = "_sim_x_px";
    if (c.name.size() < suffix.size() ||
        c.name.compare(c.name.size() - suffix.size(), suffix.size(), suffix) != 0)
      continue;
    const std::string m = c.name.substr(0, c.name.size() - suffix.size());
    for (std::size_t f = 0; f < Doubles(frames, c.name).size(); ++f) {
      const double d =
          std::hypot(Doubles(frames, m + "_sim_x_px")[f] - Doubles(frames, m + "_meas_x_px")[f],
                     Doubles(frames, m + "_sim_y_px")[f] - Doubles(frames, m + "_meas_y_px")[f]);
      if (std::isfinite(d) && d > largest) largest = d, marker = m, frame = f;
    }
  }
  ASSERT_GT(largest, 0.0);
  // A magnification that draws it about 40 px long (the residual is sub-pixel or near it).
  const int scale = std::clamp(static_cast<int>(std::ceil(40.0 / largest)), 1, 1000);
  const fs::path x = base_ / "arrow";
  const auto r = RunHoofimpact("overlay " + H5().string() + " " + trial.id + " -o " + x.string() +
                               " --frames-only --residual-scale " + std::to_string(scale));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  char name[32];
  std::snprintf(name, sizeof name, "frame_%06zu.png", frame);
  const cv::Mat img = cv::imread((x / trial.id / name).string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(img.empty()) << name;
  const Eigen::Vector2d meas(Doubles(frames, marker + "_meas_x_px")[frame],
                             Doubles(frames, marker + "_meas_y_px")[frame]);
  const Eigen::Vector2d sim(Doubles(frames, marker + "_sim_x_px")[frame],
                            Doubles(frames, marker + "_sim_y_px")[frame]);
  const Eigen::Vector2d end = meas + scale * (sim - meas);
  // The arrow's colour (compare/replay_convention.h) in a corridor 6 px wide about the ray
  // from the measured centre through the expected end, out to twice its length (so that a
  // legend line in the same colour elsewhere does not count); the farthest such pixel is the
  // arrow's end.
  const auto& g = compare::replay::kResidual;
  const Eigen::Vector2d u = (end - meas).normalized();
  const double reach = 2 * (end - meas).norm() + 8;
  double farthest = 0;
  Eigen::Vector2d tip(0, 0);
  int n = 0;
  for (int y = std::max(0, static_cast<int>(meas.y() - reach));
       y < std::min(img.rows, static_cast<int>(meas.y() + reach)); ++y)
    for (int xx = std::max(0, static_cast<int>(meas.x() - reach));
         xx < std::min(img.cols, static_cast<int>(meas.x() + reach)); ++xx) {
      const cv::Vec3b p = img.at<cv::Vec3b>(y, xx);
      if (std::abs(p[0] - g.b) > 60 || std::abs(p[1] - g.g) > 60 || std::abs(p[2] - g.r) > 60)
        continue;
      const Eigen::Vector2d q = Eigen::Vector2d(xx, y) - meas;
      const double along = q.dot(u), across = std::abs(q.x() * u.y() - q.y() * u.x());
      if (along < -3 || along > reach || across > 6) continue;
      ++n;
      if (along > farthest) farthest = along, tip = q + meas;
    }
  ASSERT_GT(n, 10) << marker << " frame " << frame << " F " << scale;
  EXPECT_LE((tip - end).norm(), 2.0)
      << marker << " frame " << frame << " F " << scale << ": tip at " << tip.transpose()
      << ", expected " << end.transpose();
}

TEST_F(OverlayCommandTest, BadPaceAndScaleAreCommandLineErrors) {
  for (const auto& [args, option] :
       {std::pair<std::string, std::string>{"--residual-scale 0", "--residual-scale"},
        {"--residual-scale 1001", "--residual-scale"},
        {"--slowdown 0", "--slowdown"}}) {
    const auto r = RunHoofimpact("overlay " + H5().string() + " x -o " +
                                 (base_ / "bad-option").string() + " " + args);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.err;
    EXPECT_NE(r.err.find(option), std::string::npos) << args << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(base_ / "bad-option"));
}

TEST_F(OverlayCommandTest, AnUnknownTrialIsAClearError) {
  const auto r =
      RunHoofimpact("overlay " + H5().string() + " no_such_trial -o " + (base_ / "bad").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("no_such_trial"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(base_ / "bad" / "no_such_trial"));
}

TEST(OverlayBallTest, ABallIsItsSimulatedCircleAndItsCentresResidualArrow) {
  // A ball has no markers: the overlay draws its simulated circle (R = 10 mm, 50 px at 0.2 mm/px)
  // about the simulated centre of mass, the measured and simulated centres, and the residual
  // arrow of the centre, ending at measured + F (simulated - measured) as the study file stores
  // them (/comparison/frames/<id>, centre_px_*).
  const fs::path base =
      fs::path(HOOF_BINARY_DIR) / "test-output" / ("overlay_ball_" + std::to_string(::getpid()));
  fs::remove_all(base);
  auto r = RunHoofimpact("run " + hoof::testing::TestStudyDir("ball_8").string() + " -o " +
                         (base / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const fs::path h5 = base / "out" / "study.h5";
  const std::string id = "steel_20deg_v3.50_r1";
  const auto frames = studyfile::ReadTable(h5, "/comparison/frames/" + id);
  const auto& sx = Doubles(frames, "centre_px_sim_x");
  const auto& sy = Doubles(frames, "centre_px_sim_y");
  const auto& mx = Doubles(frames, "centre_px_meas_x");
  const auto& my = Doubles(frames, "centre_px_meas_y");
  std::size_t frame = 0;
  double largest = 0;
  for (std::size_t f = 0; f < sx.size(); ++f) {
    const double d = std::hypot(sx[f] - mx[f], sy[f] - my[f]);
    if (std::isfinite(d) && d > largest) largest = d, frame = f;
  }
  ASSERT_GT(largest, 0.0);
  const int scale = std::clamp(static_cast<int>(std::ceil(30.0 / largest)), 1, 1000);
  r = RunHoofimpact("overlay " + h5.string() + " " + id + " -o " + (base / "ov").string() +
                    " --frames-only --residual-scale " + std::to_string(scale));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  char name[32];
  std::snprintf(name, sizeof name, "frame_%06zu.png", frame);
  const cv::Mat img = cv::imread((base / "ov" / id / name).string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(img.empty()) << name;
  // A pixel of `g`'s hue: each channel's excess over the grey it is drawn on (its smallest
  // channel) within 40 % of the glyph's, so that a thin anti-aliased line, half over the frame's
  // grey, still counts.
  const auto near = [&](const compare::replay::Glyph& g, const Eigen::Vector2d& p, int reach) {
    const int gmin = std::min({g.b, g.g, g.r});
    for (int y = static_cast<int>(p.y()) - reach; y <= static_cast<int>(p.y()) + reach; ++y)
      for (int x = static_cast<int>(p.x()) - reach; x <= static_cast<int>(p.x()) + reach; ++x) {
        if (y < 0 || x < 0 || y >= img.rows || x >= img.cols) continue;
        const cv::Vec3b c = img.at<cv::Vec3b>(y, x);
        const int cmin = std::min({c[0], c[1], c[2]});
        const double w = static_cast<double>(std::max({c[0], c[1], c[2]}) - cmin) /
                         (std::max({g.b, g.g, g.r}) - gmin);
        if (w < 0.4) continue;
        bool same = true;
        for (const auto& [have, want] : {std::pair<int, int>{c[0], g.b}, {c[1], g.g}, {c[2], g.r}})
          same = same && std::abs((have - cmin) - w * (want - gmin)) <= 0.4 * w * 255;
        if (same) return true;
      }
    return false;
  };
  const Eigen::Vector2d sim(sx[frame], sy[frame]), meas(mx[frame], my[frame]);
  // The simulated circle: its colour 50 px from the simulated centre all around (12 directions),
  // and not at 40 px or 60 px.
  int on = 0, off = 0;
  for (int k = 0; k < 12; ++k) {
    const Eigen::Vector2d u(std::cos(k * M_PI / 6), std::sin(k * M_PI / 6));
    // (Within 2 px: the lens's distortion bends the circle by up to a px.)
    on += near(compare::replay::kSimulated, sim + 50 * u, 2);
    off += near(compare::replay::kSimulated, sim + 40 * u, 2) +
           near(compare::replay::kSimulated, sim + 60 * u, 2);
  }
  EXPECT_GE(on, 10) << "frame " << frame << ", simulated centre " << sim.transpose();
  EXPECT_EQ(off, 0);
  // The measured centre's ring and the arrow's tip at measured + F (simulated - measured).
  EXPECT_TRUE(near(compare::replay::kMeasured, meas, 6));
  EXPECT_TRUE(near(compare::replay::kResidual, meas + scale * (sim - meas), 2))
      << "F " << scale << ", largest residual " << largest << " px in frame " << frame;
  if (!::testing::Test::HasFailure()) fs::remove_all(base);
}

}  // namespace
}  // namespace hoof::cli
