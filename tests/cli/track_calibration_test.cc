// The scale from a calibration image in `track` and `init` (camera.scale_from "checkerboard"
// and "ruler"): rendered trials with calibration.png (`synth --calibration`) whose trial.json
// states no m_per_px. The scale is within 4 of its s.e. of the truth (the ruler's: 0.05 %), v
// before and after are within 1 % of truth.json and scale with it against the same trial at the
// true scale, their standard errors carry the scale's, and e is unchanged. init takes the
// calibration image on its command line. Bad input (a missing image, another corner count, a ruler
// segment off the image, a frame beyond the clip) is an error naming the file and the field,
// exit 1.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/run_command.h"

namespace {

namespace fs = std::filesystem;
using hoof::testing::RunHoofimpact;
using json = nlohmann::json;

const fs::path kOut = fs::path(HOOF_BINARY_DIR) / "test-output" / "track_calibration";
const std::string kStudy = " --study " + std::string(HOOF_SOURCE_DIR) + "/sample_frames/study.json";

json Results(const hoof::testing::CommandResult& r) { return json::parse(r.out)["results"]; }
json ReadJson(const fs::path& p) { return json::parse(std::ifstream(p)); }
void WriteJson(const fs::path& p, const json& j) { std::ofstream(p) << j.dump(1); }

/// A marked specimen at 500 fps, 256 x 192 px, with a calibration image of `target`.
fs::path Render(const std::string& name, const std::string& target) {
  const fs::path trial = kOut / name;
  fs::remove_all(trial);
  const auto s = RunHoofimpact("synth -o " + trial.string() + " --calibration " + target +
                               " --speed-m-s 1 --fps 500 --m-per-px 4e-4 --exposure-s 1e-4"
                               " --width-px 256 --height-px 192 --frames-before 15"
                               " --frames-after 20 --seed 3");
  EXPECT_EQ(s.exit_code, 0) << s.err;
  return trial;
}

void ExpectScaleFromCalibration(const std::string& target) {
  const fs::path trial = Render(target, target);
  const json truth = ReadJson(trial / "truth.json");
  const double m_true = truth["calibration"]["m_per_px"].get<double>();
  json tj = ReadJson(trial / "trial.json");
  ASSERT_EQ(tj["camera"]["scale_from"], target);
  ASSERT_FALSE(tj["camera"].contains("m_per_px"));
  const auto r = RunHoofimpact("track " + trial.string() + " --json" + kStudy);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json b = Results(r);
  EXPECT_EQ(b["scale_source"], target);
  const double m = b["m_per_px_used"].get<double>(), se = b["m_per_px_se"].get<double>();
  EXPECT_GT(se, 0.0);
  // The board's s.e. is honest (tests/pipeline/calibration_scale_test.cc); the ruler's is too
  // small, and its scale is checked to 0.05 % as there.
  if (target == "checkerboard") {
    EXPECT_LT(std::abs(m - m_true), 4 * se) << m << " +- " << se << " vs " << m_true;
  } else {
    EXPECT_LT(std::abs(m - m_true), 5e-4 * m_true) << m << " +- " << se << " vs " << m_true;
  }
  EXPECT_EQ(b["calibration_scale"]["m_per_px"], b["m_per_px_used"]);
  EXPECT_GE(b["calibration_scale"]["points"].get<int>(), target == "checkerboard" ? 54 : 8);
  // The same trial at the true scale.
  tj["camera"].erase("scale_from");
  tj["camera"].erase(target);
  tj["camera"]["m_per_px"] = m_true;
  const fs::path stated = kOut / (target + "_stated");
  fs::remove_all(stated);
  fs::copy(trial, stated, fs::copy_options::recursive);
  WriteJson(stated / "trial.json", tj);
  const auto ra = RunHoofimpact("track " + stated.string() + " --json" + kStudy);
  ASSERT_EQ(ra.exit_code, 0) << ra.err;
  const json a = Results(ra);
  EXPECT_NEAR(b["e"].get<double>(), a["e"].get<double>(), 0.002);
  EXPECT_NEAR(b["e"].get<double>(), truth["e"].get<double>(), 0.03);
  const double rel = se / m;
  for (const char* key : {"v_SC_before_m_s", "v_SC_after_m_s"}) {
    const double v = b[key][1].get<double>(), v_true = truth[key][1].get<double>();
    EXPECT_NEAR(v, v_true, 0.01 * std::abs(v_true)) << key;
    // Velocities scale with the scale used.
    EXPECT_NEAR(v / a[key][1].get<double>(), m / m_true, 2e-3) << key;
    const std::string se_key =
        std::string(key).replace(std::string(key).find("_m_s"), 4, "_se_m_s");
    const double fit = a[se_key][1].get<double>() * m / m_true;
    EXPECT_NEAR(b[se_key][1].get<double>(), std::hypot(fit, rel * v),
                0.02 * std::hypot(fit, rel * v))
        << se_key;
  }
  // The text names the source.
  const auto text = RunHoofimpact("track " + trial.string() + kStudy);
  EXPECT_NE(text.out.find("m/px from " + target), std::string::npos) << text.out;
}

TEST(TrackCalibrationTest, TheScaleFromARenderedCheckerboardGivesTheTrueVelocities) {
  ExpectScaleFromCalibration("checkerboard");
}

TEST(TrackCalibrationTest, TheScaleFromARenderedRulerGivesTheTrueVelocities) {
  ExpectScaleFromCalibration("ruler");
}

/// Runs track on `trial` with trial.json edited by `edit`; expects exit 1 and every `words`
/// in the error.
void ExpectError(const fs::path& trial, const std::function<void(json&)>& edit,
                 const std::vector<std::string>& words) {
  json tj = ReadJson(trial / "trial.json");
  edit(tj);
  WriteJson(trial / "trial.json", tj);
  const auto r = RunHoofimpact("track " + trial.string() + kStudy);
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  for (const auto& w : words) EXPECT_NE(r.err.find(w), std::string::npos) << w << " in " << r.err;
}

TEST(TrackCalibrationTest, BadCalibrationInputIsAClearErrorNamingTheFileAndField) {
  const fs::path trial = Render("bad_board", "checkerboard");
  ExpectError(trial, [](json& t) { t["camera"]["checkerboard"]["image"] = "nope.png"; },
              {"nope.png", "camera.checkerboard.image"});
  ExpectError(trial,
              [](json& t) {
                t["camera"]["checkerboard"]["image"] = "calibration.png";
                t["camera"]["checkerboard"]["inner_corners"] = {7, 5};
              },
              {"calibration.png", "camera.checkerboard", "9 x 6", "7 x 5"});
  ExpectError(trial,
              [](json& t) {
                t["camera"]["checkerboard"] = {
                    {"frame", 0}, {"inner_corners", {9, 6}}, {"square_m", 0.004}};
              },
              {"frames/000000.png", "camera.checkerboard.frame", "no checkerboard"});
  ExpectError(trial,
              [](json& t) {
                t["camera"]["checkerboard"] = {
                    {"frame", 999}, {"inner_corners", {9, 6}}, {"square_m", 0.004}};
              },
              {"trial.json", "camera.checkerboard.frame", "999"});
  ExpectError(trial, [](json& t) { t["camera"]["scale_from"] = "ruler"; },
              {"trial.json", "camera.ruler", "missing"});
  ExpectError(trial,
              [](json& t) {
                t["camera"]["ruler"] = {{"image", "calibration.png"},
                                        {"from_px", {10, 10}},
                                        {"to_px", {300, 10}},
                                        {"tick_m", 0.001}};
              },
              {"calibration.png", "camera.ruler", "outside"});
}

TEST(TrackCalibrationTest, InitTakesTheScaleFromACheckerboardImage) {
  const fs::path clip = kOut / "init_ball";
  fs::remove_all(clip);
  const auto s = RunHoofimpact(
      "synth -o " + clip.string() +
      " --body ball --ball-diameter-m 0.01 --lighting backlit --fps 1000 --speed-m-s 1"
      " --frames-before 40 --frames-after 40 --width-px 160 --height-px 288 --seed 1"
      " --frame-format mraw --bit-depth 12 --calibration checkerboard");
  ASSERT_EQ(s.exit_code, 0) << s.err;
  const json truth = ReadJson(clip / "truth.json");
  const double m_true = truth["calibration"]["m_per_px"].get<double>();
  const json& cal = truth["calibration"];
  const std::string corners = std::to_string(cal["inner_corners"][0].get<int>()) + "x" +
                              std::to_string(cal["inner_corners"][1].get<int>());
  const std::string square = json(cal["square_m"].get<double>()).dump();
  const fs::path trial = kOut / "init_ball_trial";
  fs::remove_all(trial);
  const auto r = RunHoofimpact("init " + (clip / "clip.mraw").string() + " -o " + trial.string() +
                               " --checkerboard " + (clip / "calibration.png").string() +
                               " --corners " + corners + " --square-m " + square + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = Results(r);
  EXPECT_EQ(j["scale_source"], "checkerboard");
  // init writes no lens model, and the renderer's lens distorts: the scale is checked to 1 %.
  EXPECT_NEAR(j["m_per_px"].get<double>(), m_true, 0.01 * m_true);
  const json tj = ReadJson(trial / "trial.json");
  EXPECT_EQ(tj["camera"]["scale_from"], "checkerboard");
  EXPECT_EQ(tj["camera"]["checkerboard"]["inner_corners"], cal["inner_corners"]);
  EXPECT_FALSE(tj["camera"].contains("m_per_px"));
  const auto t = RunHoofimpact("track " + trial.string() + " --json");
  ASSERT_EQ(t.exit_code, 0) << t.err;
  EXPECT_EQ(Results(t)["scale_source"], "checkerboard");
  // Bad input: a missing image, a board option without its image, a wrong corner count.
  const auto missing = RunHoofimpact("init " + (clip / "clip.mraw").string() + " -o " +
                                     (kOut / "init_bad").string() +
                                     " --checkerboard nope.png --corners 9x6 --square-m 0.002");
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.err.find("nope.png"), std::string::npos) << missing.err;
  const auto orphan = RunHoofimpact("init " + (clip / "clip.mraw").string() + " -o " +
                                    (kOut / "init_bad").string() + " --corners 9x6");
  EXPECT_EQ(orphan.exit_code, 2);
  EXPECT_NE(orphan.err.find("--checkerboard"), std::string::npos) << orphan.err;
}

}  // namespace
