// `hoofimpact init` on each kind of clip, then `hoofimpact track` on the trial.json it wrote,
// without edits, against the renderer's truth.json: a marked specimen's PNG frames (its layout
// from a study.json, or missing and said so), a back-lit ball at 1000 fps with the scale from
// gravity, a back-lit ball that bounces twice, a front-lit ball in a Phantom CINE, and the
// surface line of the real Photron ball clip against an independent estimate from its pixels.
// (A back-lit ball MRAW at 8000 fps is in init_command_test.cc.)
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "support/run_command.h"
#include "tracking/camera_file.h"
#include "tracking/frame_source.h"

namespace {

namespace fs = std::filesystem;
using hoof::testing::RunHoofimpact;
using json = nlohmann::json;

const fs::path kOut = fs::path(HOOF_BINARY_DIR) / "test-output" / "init_kinds";
const fs::path kStudy = fs::path(HOOF_SOURCE_DIR) / "sample_frames" / "study.json";

json Results(const hoof::testing::CommandResult& r) { return json::parse(r.out)["results"]; }

json Render(const std::string& name, const std::string& options) {
  const fs::path dir = kOut / name;
  fs::remove_all(dir);
  const auto s = RunHoofimpact("synth -o " + dir.string() + " " + options);
  EXPECT_EQ(s.exit_code, 0) << s.err;
  return json::parse(std::ifstream(dir / "truth.json"));
}

// A marked specimen (two white dots on black squares, the renderer's default body) in PNG
// frames at 8000 fps, 20 deg steel: init finds the dots, takes the layout of specimen A from the
// study (the renderer's specimen), the scale from the dots' spacing, the surface and the impact;
// track then gives e and mu_eff within 0.01 of the truth.
TEST(InitKindsTest, AMarkedSpecimenWithItsLayoutIsMeasuredWithoutEdits) {
  const json truth = Render("markers",
                            "--seed 1 --angle-deg 20 --width-px 384 --height-px 320 "
                            "--frames-before 16 --frames-after 16");
  ASSERT_EQ(truth["body"]["kind"], "markers");
  const double truth_m_per_px =
      json::parse(std::ifstream(kOut / "markers" / "trial.json"))["camera"]["m_per_px"];
  const fs::path trial = kOut / "markers_trial";
  fs::remove_all(trial);
  const auto r =
      RunHoofimpact("init " + (kOut / "markers" / "frames").string() + " -o " + trial.string() +
                    " --fps 8000 --specimen A --study " + kStudy.string() + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = Results(r);
  EXPECT_EQ(json::parse(r.out)["warnings"].size(), 0u) << r.out;
  EXPECT_EQ(j["body_shape"], "markers");
  EXPECT_EQ(j["marker_dots"], 2);
  EXPECT_TRUE(j["marker_layout_known"].get<bool>());
  EXPECT_NEAR(j["surface_angle_deg"].get<double>(), 20.0, 0.5);
  ASSERT_EQ(j["impact_frames"].size(), 1u);
  EXPECT_NEAR(j["impact_frames"][0].get<double>(), truth["impact_time_s"].get<double>() * 8000,
              2.0);
  EXPECT_EQ(j["scale_source"], "markers");
  EXPECT_NEAR(j["m_per_px"].get<double>(), truth_m_per_px, 0.01 * truth_m_per_px);
  EXPECT_EQ(j["trial"]["body"]["model"], "markers");
  EXPECT_EQ(j["trial"]["specimen"], "A");
  const auto t = RunHoofimpact("track " + trial.string() + " --json");
  ASSERT_EQ(t.exit_code, 0) << t.err;
  const json k = Results(t);
  EXPECT_EQ(k["scale_source"], "markers");
  EXPECT_NEAR(k["m_per_px_used"].get<double>(), truth_m_per_px, 0.01 * truth_m_per_px);
  EXPECT_NEAR(k["e"].get<double>(), truth["e"].get<double>(), 0.01);
  EXPECT_NEAR(k["mu_eff"].get<double>(), truth["mu_eff"].get<double>(), 0.01);

  // Without the specimen, init says what is missing and invents no layout: trial.json names
  // no specimen, and track stops at that field.
  const fs::path bare = kOut / "markers_no_layout";
  fs::remove_all(bare);
  const auto b = RunHoofimpact("init " + (kOut / "markers" / "frames").string() + " -o " +
                               bare.string() + " --fps 8000 --json");
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const json bj = json::parse(b.out);
  EXPECT_EQ(bj["results"]["body_shape"], "markers");
  EXPECT_FALSE(bj["results"]["marker_layout_known"].get<bool>());
  EXPECT_FALSE(bj["results"]["trial"].contains("specimen"));
  EXPECT_FALSE(bj["results"]["trial"].contains("specimen_parameters"));
  ASSERT_EQ(bj["warnings"].size(), 1u) << bj["warnings"].dump();
  const std::string w = bj["warnings"][0];
  EXPECT_NE(w.find("markers_B_m"), std::string::npos) << w;
  EXPECT_NE(w.find("--specimen"), std::string::npos) << w;
  const auto bt = RunHoofimpact("track " + bare.string());
  EXPECT_EQ(bt.exit_code, 1);
  EXPECT_NE(bt.err.find("\"specimen\""), std::string::npos) << bt.err;

  // A layout that is not the one seen is an error naming the specimen.
  const fs::path wrong_study = kOut / "wrong_layout" / "study.json";
  fs::remove_all(wrong_study.parent_path());
  fs::create_directories(wrong_study.parent_path());
  json study = json::parse(std::ifstream(kStudy));
  study["specimens"]["A"]["markers_B_m"] = {
      {"M1", {0.006, 0.0}}, {"M2", {0.024, 0.0}}, {"M3", {0.015, 0.006}}};
  std::ofstream(wrong_study) << study.dump(1);
  const auto x = RunHoofimpact("init " + (kOut / "markers" / "frames").string() + " -o " +
                               (kOut / "wrong_layout" / "t").string() +
                               " --fps 8000 --specimen A --study " + wrong_study.string());
  EXPECT_EQ(x.exit_code, 1);
  EXPECT_NE(x.err.find("specimen \"A\""), std::string::npos) << x.err;
  // Two markers give one distance, which cannot disagree with itself: a spacing 30 % too wide
  // is caught by gravity's scale instead, as a warning.
  study["specimens"]["A"]["markers_B_m"] = {{"M1", {0.006, 0.0}}, {"M2", {0.0294, 0.0}}};
  std::ofstream(wrong_study) << study.dump(1);
  const auto y = RunHoofimpact("init " + (kOut / "markers" / "frames").string() + " -o " +
                               (kOut / "wrong_layout" / "t").string() +
                               " --fps 8000 --specimen A --json --study " + wrong_study.string());
  ASSERT_EQ(y.exit_code, 0) << y.err;
  const json yj = json::parse(y.out);
  ASSERT_EQ(yj["warnings"].size(), 1u) << yj["warnings"].dump();
  EXPECT_NE(yj["warnings"][0].get<std::string>().find("markers_B_m"), std::string::npos);
  EXPECT_NEAR(yj["results"]["m_per_px"].get<double>(), 1.3 * truth_m_per_px, 0.01 * truth_m_per_px);
}

// A back-lit 10 mm ball at 1000 fps in a 12-bit MRAW, no scale given: init takes the scale from
// gravity within 1 % of the truth, and track measures init's trial as written.
TEST(InitKindsTest, ABallAt1000FpsGetsItsScaleFromGravity) {
  const json truth = Render("gravity_ball",
                            "--body ball --ball-diameter-m 0.01 --lighting backlit --fps 1000 "
                            "--speed-m-s 1 --frames-before 40 --frames-after 40 --width-px 160 "
                            "--height-px 288 --seed 1 --frame-format mraw --bit-depth 12");
  const double truth_m_per_px =
      json::parse(std::ifstream(kOut / "gravity_ball" / "trial.json"))["camera"]["m_per_px"];
  const fs::path trial = kOut / "gravity_ball_trial";
  fs::remove_all(trial);
  const auto r = RunHoofimpact("init " + (kOut / "gravity_ball" / "clip.mraw").string() + " -o " +
                               trial.string() + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = Results(r);
  EXPECT_EQ(j["body_shape"], "ball");
  EXPECT_EQ(j["polarity"], "dark_on_bright");
  EXPECT_EQ(j["scale_source"], "gravity");
  EXPECT_NEAR(j["m_per_px"].get<double>(), truth_m_per_px, 0.01 * truth_m_per_px);
  EXPECT_NEAR(j["body_diameter_px"].get<double>(), 0.01 / truth_m_per_px, 1.0);
  ASSERT_EQ(j["impact_frames"].size(), 1u);
  EXPECT_NEAR(j["impact_frames"][0].get<double>(), truth["impact_time_s"].get<double>() * 1000,
              1.0);
  const auto t = RunHoofimpact("track " + trial.string() + " --json");
  ASSERT_EQ(t.exit_code, 0) << t.err;
  const json k = Results(t);
  EXPECT_EQ(k["scale_source"], "gravity");
  EXPECT_NEAR(k["m_per_px_used"].get<double>(), truth_m_per_px, 0.01 * truth_m_per_px);
  EXPECT_NEAR(k["e"].get<double>(), truth["e"].get<double>(), 0.01);
}

// A back-lit ball that bounces twice on level steel (500 fps, as track_impacts_test.cc): init
// lists both impacts at the truth's touch frames, and track measures both from init's trial.
TEST(InitKindsTest, ABallThatBouncesTwiceHasBothImpactsListed) {
  const json truth = Render("two_bounces",
                            "--body ball --lighting backlit --bounces 2 --speed-m-s 1 --fps 500 "
                            "--m-per-px 4e-4 --exposure-s 1e-4 --width-px 256 --height-px 192 "
                            "--frames-before 15 --seed 1");
  ASSERT_EQ(truth["impacts"].size(), 2u);
  const fs::path trial = kOut / "two_bounces_trial";
  fs::remove_all(trial);
  const auto r = RunHoofimpact("init " + (kOut / "two_bounces" / "frames").string() + " -o " +
                               trial.string() + " --fps 500 --diameter-m 0.02 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = Results(r);
  EXPECT_EQ(j["body_shape"], "ball");
  EXPECT_NEAR(j["surface_angle_deg"].get<double>(), 0.0, 0.5);
  ASSERT_EQ(j["impact_frames"].size(), 2u) << j["impact_frames"].dump();
  for (std::size_t i = 0; i < 2; ++i)
    EXPECT_NEAR(j["impact_frames"][i].get<double>(),
                truth["impacts"][i]["touch_time_s"].get<double>() * 500, 1.0)
        << "impact " << i;
  EXPECT_NEAR(j["m_per_px"].get<double>(), 4e-4, 0.01 * 4e-4);
  const auto t = RunHoofimpact("track " + trial.string() + " --json");
  ASSERT_EQ(t.exit_code, 0) << t.err;
  const json impacts = Results(t)["impacts"];
  ASSERT_EQ(impacts.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    ASSERT_TRUE(impacts[i]["success"].get<bool>()) << impacts[i]["error"];
    EXPECT_NEAR(impacts[i]["e"].get<double>(), truth["impacts"][i]["e"].get<double>(), 0.01)
        << "impact " << i;
  }
}

// A front-lit ball (bright on a dark studio) in a Phantom CINE at 8000 fps: init finds the
// ball, its polarity and the surface angle. The silhouette tracker does not yet measure a
// front-lit ball's centre well (its shading pulls the fitted circle: 78 px for 100), so no
// impact, scale or e is asserted; track runs on init's trial and ends with a clear error or a
// result, never a crash.
TEST(InitKindsTest, AFrontLitBallInACineClipIsFoundAndTracked) {
  Render("front_ball",
         "--body ball --lighting front --frame-format cine --seed 2 --angle-deg 10 --width-px 320 "
         "--height-px 320");
  const fs::path trial = kOut / "front_ball_trial";
  fs::remove_all(trial);
  const auto r = RunHoofimpact("init " + (kOut / "front_ball" / "clip.cine").string() + " -o " +
                               trial.string() + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = Results(r);
  EXPECT_EQ(j["body_shape"], "ball");
  EXPECT_EQ(j["polarity"], "bright_on_dark");
  EXPECT_EQ(j["marker_dots"], 0);
  EXPECT_NEAR(j["surface_angle_deg"].get<double>(), 10.0, 0.5);
  EXPECT_EQ(j["frame_count"], 60);
  EXPECT_EQ(j["fps"], 8000.0);
  const auto t = RunHoofimpact("track " + trial.string());
  EXPECT_TRUE(t.exit_code == 0 || t.exit_code == 1 || t.exit_code == 4) << t.exit_code;
  if (t.exit_code == 1) {
    EXPECT_NE(t.err.find("trial.json"), std::string::npos) << t.err;
  }
}

// The row where a column band's mean level crosses halfway from the back light (the top rows)
// to the strip (the bottom tenth), scanning down: the strip's top edge there (px, sub-pixel).
double EdgeRowOfBand(const cv::Mat& unit, int x0, int x1) {
  std::vector<double> level;
  for (int y = 0; y < unit.rows; ++y)
    level.push_back(cv::mean(unit(cv::Range(y, y + 1), cv::Range(x0, x1)))[0]);
  std::vector<double> top(level.begin(), level.begin() + unit.rows / 10);
  std::vector<double> bottom(level.end() - unit.rows / 10, level.end());
  std::sort(top.begin(), top.end());
  std::sort(bottom.begin(), bottom.end());
  const double half = 0.5 * (top[top.size() / 2] + bottom[bottom.size() / 2]);
  for (int y = 1; y < unit.rows; ++y)
    if (level[y] < half && level[y - 1] >= half)
      return y - 1 + (level[y - 1] - half) / (level[y - 1] - level[y]);
  return std::nan("");
}

// The real 12-bit Photron ball clip: the textured strip along the bottom is the surface. Its
// top edge, as init finds it, agrees with an independent estimate (the halfway crossing of
// the mean level of two column bands beside the ball) to 0.2 deg and 1.5 px.
TEST(InitKindsTest, TheRealBallClipsSurfaceIsTheStripsTopEdge) {
  const fs::path clip =
      fs::path(HOOF_SOURCE_DIR) / "tests" / "data" / "real-footage" / "photron" / "ball_12bit.cihx";
  const fs::path trial = kOut / "real_ball_surface";
  fs::remove_all(trial);
  const auto r = RunHoofimpact("init " + clip.string() + " -o " + trial.string() + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = Results(r);
  ASSERT_TRUE(j["surface_found"].get<bool>());
  auto source = hoof::tracking::OpenCameraFile(clip);
  const cv::Mat unit =
      hoof::tracking::ToUnitFloat(hoof::tracking::ToGrey(source->Read(0), source->Describe(0)));
  // Bands clear of the ball (its centre near x = 470 px, 127 px across, in frame 0).
  const int w = unit.cols;
  const int a0 = w / 32, a1 = w / 4, b0 = 3 * w / 4, b1 = w - w / 32;
  const double ya = EdgeRowOfBand(unit, a0, a1), yb = EdgeRowOfBand(unit, b0, b1);
  ASSERT_TRUE(std::isfinite(ya) && std::isfinite(yb));
  const double xa = 0.5 * (a0 + a1), xb = 0.5 * (b0 + b1);
  const double angle = std::atan2(yb - ya, xb - xa) * 180 / M_PI;
  EXPECT_NEAR(j["surface_angle_deg"].get<double>(), angle, 0.2);
  // init's line at the bands' centres.
  const auto& e = j["surface_line_px"];
  const double x0 = e[0][0], y0 = e[0][1], x1 = e[1][0], y1 = e[1][1];
  const auto y_at = [&](double x) { return y0 + (y1 - y0) * (x - x0) / (x1 - x0); };
  EXPECT_NEAR(y_at(xa), ya, 1.5);
  EXPECT_NEAR(y_at(xb), yb, 1.5);
  std::cout << "surface: init " << j["surface_angle_deg"] << " deg, at the bands y " << y_at(xa)
            << " and " << y_at(xb) << " px; independent " << angle << " deg, y " << ya << " and "
            << yb << " px\n";
  EXPECT_EQ(j["trial"]["surface_angle_deg"], j["surface_angle_deg"]);
}

}  // namespace
