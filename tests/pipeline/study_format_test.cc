#include "pipeline/study_format.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "support/test_util.h"
#include "tracking/camera_file.h"

namespace hoof::pipeline {
namespace {

namespace fs = std::filesystem;

const char* kStudy = R"({"format": "hoofimpact-study/1", "name": "t",
  "specimens": {"A": {"mass_kg": 0.008, "inertia_kg_m2": 1.5207e-6, "end_radius_m": 0.009,
    "d_EC_m": 0.0135, "markers_B_m": {"M1": [0.006, 0.0], "M2": [0.024, 0.0]}}}})";

const char* kTrial = R"({"format": "hoofimpact-trial/1", "id": "t1", "specimen": "A",
  "surface": "steel", "surface_angle_deg": 20.0, "fps": 8000.0,
  "frames": {"pattern": "frames/%06d.png", "first": 0, "count": 64},
  "camera": {"m_per_px": 1.5e-4, "gravity_image": [0.0, 2.0]},
  "surface_line_px": [[10.0, 300.0], [500.0, 478.3]], "colour": "blue"})";

fs::path Write(const std::string& name, const std::string& study, const std::string& trial) {
  const fs::path dir = fs::path(HOOF_BINARY_DIR) / "test-output" / name;
  fs::remove_all(dir);
  fs::create_directories(dir / "t1");
  std::ofstream(dir / "study.json") << study;
  std::ofstream(dir / "t1" / "trial.json") << trial;
  return dir;
}

const auto ExpectError = [](auto fn, const std::string& needle) {
  hoof::testing::ExpectErrorContaining(fn, needle);
};

TEST(StudyFormatTest, ReadsTheDocumentedExample) {
  const fs::path dir = Write("format_ok", kStudy, kTrial);
  const StudySpec study = ReadStudy(dir);
  ASSERT_EQ(study.trial_dirs.size(), 1u);  // no "trials": every sub-folder with a trial.json
  const TrialSpec t = ReadTrial(study.trial_dirs[0], study);
  EXPECT_EQ(t.id, "t1");
  EXPECT_DOUBLE_EQ(t.specimen.mass_kg, 0.008);
  ASSERT_EQ(t.specimen.markers_B_m.size(), 2u);
  EXPECT_EQ(t.specimen.markers_B_m[1].first, "M2");
  EXPECT_DOUBLE_EQ(t.camera.gravity_image.y(), 1.0);  // normalized
  ASSERT_TRUE(t.surface_line_px.has_value());
  // The unknown field is a warning naming the file, not an error.
  ASSERT_EQ(t.warnings.size(), 1u);
  EXPECT_NE(t.warnings[0].find("unknown field \"colour\""), std::string::npos);
  EXPECT_NE(t.warnings[0].find("trial.json"), std::string::npos);
}

TEST(StudyFormatTest, MissingOrWrongFieldsNameFileAndField) {
  std::string trial = kTrial;
  trial.replace(trial.find("\"fps\": 8000.0,"), 14, "");
  ExpectError([&] { ReadTrial(Write("format_nofps", kStudy, trial) / "t1"); },
              "trial.json: field \"fps\" is missing");
  trial = kTrial;
  trial.replace(trial.find("\"m_per_px\": 1.5e-4"), 18, "\"m_per_px\": \"big\"");
  ExpectError([&] { ReadTrial(Write("format_badscale", kStudy, trial) / "t1"); },
              "field \"camera.m_per_px\" must be a number");
  // camera.scale_from: an unknown source is named; with markers, "gravity" still needs an
  // approximate m_per_px (the tracker matches the markers with it); a ball's diameter as the
  // source needs a ball.
  trial = kTrial;
  trial.replace(trial.find("\"m_per_px\": 1.5e-4"), 18, "\"scale_from\": \"tape\"");
  ExpectError([&] { ReadTrial(Write("format_badsource", kStudy, trial) / "t1"); },
              "field \"camera.scale_from\" is \"tape\"");
  // A calibration image as the source needs its description (camera.ruler here).
  trial = kTrial;
  trial.replace(trial.find("\"m_per_px\": 1.5e-4"), 18, "\"scale_from\": \"ruler\"");
  ExpectError([&] { ReadTrial(Write("format_noruler", kStudy, trial) / "t1"); },
              "field \"camera.ruler\" is missing: camera.scale_from \"ruler\" needs it");
  trial = kTrial;
  trial.replace(trial.find("\"m_per_px\": 1.5e-4"), 18, "\"scale_from\": \"gravity\"");
  ExpectError(
      [&] { ReadTrial(Write("format_gravity_markers", kStudy, trial) / "t1"); },
      "field \"camera.m_per_px\" is missing: the marker tracker needs an approximate scale");
  trial = kTrial;
  trial.replace(trial.find("\"m_per_px\": 1.5e-4"), 18,
                "\"m_per_px\": 1.5e-4, \"scale_from\": \"gravity\"");
  EXPECT_EQ(ReadTrial(Write("format_gravity", kStudy, trial) / "t1").camera.scale_from, "gravity");
  trial = kTrial;
  trial.replace(trial.find("\"m_per_px\": 1.5e-4"), 18, "\"scale_from\": \"body_diameter\"");
  ExpectError([&] { ReadTrial(Write("format_nodiameter", kStudy, trial) / "t1"); },
              "field \"camera.scale_from\" is \"body_diameter\" but the body is not a ball");
  trial = kTrial;
  trial.replace(trial.find("\"m_per_px\": 1.5e-4"), 18, "\"scale_from\": \"end_radius\"");
  ExpectError([&] { ReadTrial(Write("format_endradius_markers", kStudy, trial) / "t1"); },
              "field \"camera.scale_from\" is \"end_radius\" but the body is not an unmarked "
              "outline");
  trial = kTrial;
  trial.replace(trial.find("\"specimen\": \"A\""), 15, "\"specimen\": \"B\"");
  ExpectError([&] { ReadTrial(Write("format_nospecimen", kStudy, trial) / "t1"); },
              "field \"specimen\" names \"B\"");
  ExpectError([&] { ReadTrial(Write("format_badjson", kStudy, "{\"format\": ") / "t1"); },
              "trial.json: not valid JSON");
  ExpectError([&] { ReadTrial(Write("format_array", kStudy, "[1, 2]") / "t1"); },
              "trial.json: must hold a JSON object ({...}), found array");
  trial = kTrial;
  trial.replace(trial.find("8000.0"), 6, "1e999");
  ExpectError([&] { ReadTrial(Write("format_hugefps", kStudy, trial) / "t1"); },
              "trial.json: a number is out of range");
  // A rate no camera has (one frame in 10^6 s), by the camera readers' rule.
  trial = kTrial;
  trial.replace(trial.find("8000.0"), 6, "1e-6");
  ExpectError([&] { ReadTrial(Write("format_tinyfps", kStudy, trial) / "t1"); },
              "trial.json: field \"fps\" 1e-06 fps is not within 0.001 to 1e+09");
  // A pattern of 200 000 characters (which crashed the tracker) and one with two conversions.
  trial = kTrial;
  trial.replace(trial.find("frames/%06d.png"), 15,
                "frames/%06d" + std::string(200000, 'A') + ".png");
  ExpectError([&] { ReadTrial(Write("format_longpattern", kStudy, trial) / "t1"); },
              "field \"frames.pattern\" is 200015 characters long; at most 4096 are accepted");
  trial = kTrial;
  trial.replace(trial.find("frames/%06d.png"), 15, "frames/%06d_%d.png");
  ExpectError(
      [&] { ReadTrial(Write("format_twoconversions", kStudy, trial) / "t1"); },
      "field \"frames.pattern\" \"frames/%06d_%d.png\" must hold exactly one integer conversion");
  // Found by fuzzing: a specimen, frames or camera that is not an object is named as such.
  std::string study_bad = kStudy;
  study_bad.replace(study_bad.find("\"A\": {"), 6, "\"A\": 5.0, \"B\": {");
  ExpectError([&] { ReadStudy(Write("format_specimen_number", study_bad, kTrial)); },
              "study.json: field \"specimens.A\" must be an object ({...}), found number");
  trial = kTrial;
  trial.replace(trial.find("\"frames\": {"), 11, "\"frames\": [1], \"x\": {");
  ExpectError([&] { ReadTrial(Write("format_frames_array", kStudy, trial) / "t1"); },
              "trial.json: field \"frames\" must be an object ({...}), found array");
  // Counts beyond an int are refused, not wrapped (4294967297 = 2^32 + 1 would read as 1).
  for (const char* count : {"4294967297", "18446744073709551615", "-1", "2.5"}) {
    trial = kTrial;
    trial.replace(trial.find("\"count\": 64"), 11, std::string("\"count\": ") + count);
    ExpectError(
        [&] { ReadTrial(Write("format_count", kStudy, trial) / "t1"); },
        std::string("field \"frames.count\" must be an integer in [1, 2147483647], found ") +
            count);
  }
  std::string study = kStudy;
  study.replace(study.find("\"M2\": [0.024, 0.0]"), 18, "\"M2\": [0.024]");
  ExpectError([&] { ReadStudy(Write("format_badmarker", study, kTrial)); },
              "study.json: field \"specimens.A.markers_B_m.M2\" must be [x, y]");
  ExpectError([&] { ReadStudy(fs::path(HOOF_BINARY_DIR) / "no-such-study"); },
              "study.json: cannot open");
}

// trial.json may name a camera file instead of a pattern; its frame rate comes from the file.
TEST(StudyFormatTest, ACameraFileGivesTheFramesAndTheirRate) {
  const std::string base = kTrial;
  const auto with_frames = [&](const std::string& frames, bool fps) {
    std::string t = base;
    const std::size_t a = t.find("\"frames\": {"), b = t.find('}', a);
    t.replace(a, b + 1 - a, "\"frames\": " + frames);
    if (!fps) t.replace(t.find("\"fps\": 8000.0,"), 14, "");
    return t;
  };
  const auto clip_dir = [&](const std::string& name, const std::string& trial) {
    const fs::path dir = Write(name, kStudy, trial);
    tracking::CameraFileSpec spec;
    spec.width = 6;
    spec.height = 4;
    spec.frame_count = 5;
    spec.bits = 12;
    spec.fps = 8000;
    tracking::MrawWriter w(dir / "t1" / "clip.mraw", spec);
    for (int i = 0; i < 5; ++i) w.Write(cv::Mat(4, 6, CV_16U, cv::Scalar(100 * i)));
    w.Finish();
    return dir / "t1";
  };
  {
    const TrialSpec t =
        ReadTrial(clip_dir("format_camera", with_frames(R"({"camera_file": "clip.mraw"})", false)));
    EXPECT_EQ(t.fps, 8000.0);  // from the header: trial.json gives none
    EXPECT_TRUE(t.frames.is_camera_file());
    EXPECT_EQ(t.frames.Source(), "clip.mraw");
    EXPECT_EQ(t.frames.first, 0);
    EXPECT_EQ(t.frames.count, 5);
    EXPECT_TRUE(t.warnings.size() == 1u);  // "colour" only
    EXPECT_EQ(OpenFrames(t)->count(), 5);
  }
  {
    // A range, and a frame rate that agrees with the header.
    const TrialSpec t = ReadTrial(clip_dir(
        "format_camera_range", with_frames(R"({"camera_file": "clip.mraw", "first": 2})", true)));
    EXPECT_EQ(t.frames.first, 2);
    EXPECT_EQ(t.frames.count, 3);
    auto frames = OpenFrames(t);
    ASSERT_EQ(frames->count(), 3);
    EXPECT_EQ(frames->Read(1).at<std::uint16_t>(0, 0), 300);  // frame 3 of the clip
  }
  std::string disagree = with_frames(R"({"camera_file": "clip.mraw"})", true);
  disagree.replace(disagree.find("8000.0"), 6, "7999.9");
  ExpectError([&] { ReadTrial(clip_dir("format_camera_fps", disagree)); },
              "trial.json: field \"fps\" is 7999.9 but ");
  ExpectError([&] { ReadTrial(clip_dir("format_camera_fps", disagree)); },
              "clip.mraw records 8000.0 frames per second");
  ExpectError(
      [&] {
        ReadTrial(clip_dir(
            "format_camera_count",
            with_frames(R"({"camera_file": "clip.mraw", "first": 2, "count": 4})", false)));
      },
      "field \"frames.count\" asks for frames 2 to 5 but");
  ExpectError(
      [&] {
        ReadTrial(
            clip_dir("format_camera_ext", with_frames(R"({"camera_file": "clip.avi"})", true)));
      },
      "field \"frames.camera_file\" \"clip.avi\" must name a camera file");
  // A TIFF records no frame rate: trial.json must give it.
  const fs::path tiff =
      clip_dir("format_camera_tiff", with_frames(R"({"camera_file": "clip.tif"})", false));
  cv::imwrite((tiff / "clip.tif").string(), cv::Mat(4, 6, CV_16U, cv::Scalar(7)));
  ExpectError([&] { ReadTrial(tiff); }, "trial.json: field \"fps\" is missing, and ");
  ExpectError([&] { ReadTrial(tiff); }, "clip.tif does not record its frame rate");
  ExpectError(
      [&] {
        ReadTrial(clip_dir("format_camera_missing",
                           with_frames(R"({"camera_file": "other.cine"})", true)));
      },
      "trial.json: field \"frames.camera_file\" names a clip that cannot be read: ");
  ExpectError(
      [&] {
        ReadTrial(clip_dir("format_camera_missing",
                           with_frames(R"({"camera_file": "other.cine"})", true)));
      },
      "other.cine: file is missing");
}

// An id names the trial's files (figures, overlay frames), and a trials entry a folder: neither
// may lead outside the study or the output folder.
// A video's container records the rate it plays at: trial.json may leave fps out and take it,
// or state the capture rate (a slow-motion file's differs from the container's).
TEST(StudyFormatTest, AVideoGivesItsContainerRateWhereTrialJsonGivesNone) {
  const std::string no_fps = R"({"format": "hoofimpact-trial/1", "id": "t1", "specimen": "A",
    "surface": "steel", "surface_angle_deg": 0, "frames": {"video": "clip.mp4"},
    "camera": {"m_per_px": 1e-3}})";
  const fs::path dir = Write("format_video_rate", kStudy, no_fps);
  ExpectError([&] { ReadTrial(dir / "t1"); }, "field \"frames.video\" names a clip");
  {
    cv::VideoWriter writer((dir / "t1" / "clip.mp4").string(), cv::CAP_FFMPEG,
                           cv::VideoWriter::fourcc('a', 'v', 'c', '1'), 25.0, cv::Size(64, 48));
    ASSERT_TRUE(writer.isOpened());
    for (int i = 0; i < 3; ++i) writer.write(cv::Mat(48, 64, CV_8UC3, cv::Scalar(90, 90, 90)));
  }
  EXPECT_NEAR(ReadTrial(dir / "t1").fps, 25.0, 1e-9);
  std::string stated = no_fps;
  stated.replace(stated.find("\"frames\""), 0, "\"fps\": 240, ");
  std::ofstream(dir / "t1" / "trial.json") << stated;
  EXPECT_DOUBLE_EQ(ReadTrial(dir / "t1").fps, 240.0);
}

TEST(StudyFormatTest, IdsAndTrialFoldersStayInside) {
  for (const std::string& id :
       {std::string("../../x"), std::string("a/b"), std::string(".."), std::string("x\\u0001y")}) {
    std::string trial = kTrial;
    trial.replace(trial.find("\"id\": \"t1\""), 10, "\"id\": \"" + id + "\"");
    ExpectError([&] { ReadTrial(Write("format_badid", kStudy, trial) / "t1"); },
                "trial.json: field \"id\"");
  }
  std::string trial = kTrial;
  trial.replace(trial.find("\"id\": \"t1\""), 10, "\"id\": \"steel 20 deg (r1) x$y\"");
  EXPECT_EQ(ReadTrial(Write("format_oddid", kStudy, trial) / "t1").id, "steel 20 deg (r1) x$y");
  for (const std::string& entry :
       {std::string("/etc"), std::string("../.."), std::string("t1/../../x"), std::string(".")}) {
    std::string study = kStudy;
    study.insert(study.size() - 1, ", \"trials\": [\"" + entry + "\"]");
    ExpectError(
        [&] { ReadStudy(Write("format_badtrials", study, kTrial)); },
        "study.json: field \"trials\" \"" + entry + "\" is not a folder inside the study folder");
  }
  std::string study = kStudy;
  study.insert(study.size() - 1, ", \"trials\": [\"./t1\"]");
  const StudySpec ok = ReadStudy(Write("format_goodtrials", study, kTrial));
  ASSERT_EQ(ok.trial_dirs.size(), 1u);
  EXPECT_EQ(ok.trial_dirs[0].filename(), "t1");
}

// A symlink loop among the sub-folders of a study without a trials list is skipped with a
// warning that names it; the trials are still found.
TEST(StudyFormatTest, AnUnreadableSubfolderIsAWarning) {
  const fs::path dir = Write("format_symlink_loop", kStudy, kTrial);
  fs::create_symlink(dir / "loop_a", dir / "loop_b");
  fs::create_symlink(dir / "loop_b", dir / "loop_a");
  const StudySpec study = ReadStudy(dir);
  ASSERT_EQ(study.trial_dirs.size(), 1u);
  EXPECT_EQ(study.trial_dirs[0].filename(), "t1");
  std::string all;
  for (const auto& w : study.warnings) all += w + "\n";
  EXPECT_NE(all.find("loop_a: skipped, cannot be read"), std::string::npos) << all;
}

TEST(StudyFormatTest, ATrialMayCarryItsSpecimen) {
  std::string trial = kTrial;
  trial.insert(1, R"("specimen_parameters": {"mass_kg": 0.01, "inertia_kg_m2": 2e-6,
    "end_radius_m": 0.009, "d_EC_m": 0.0135, "markers_B_m": {"A": [0, 0], "B": [0.02, 0]}},)");
  const fs::path dir = fs::path(HOOF_BINARY_DIR) / "test-output" / "format_inline";
  fs::remove_all(dir);
  fs::create_directories(dir / "t1");
  std::ofstream(dir / "t1" / "trial.json") << trial;  // no study.json anywhere
  const TrialSpec t = ReadTrial(dir / "t1");
  EXPECT_DOUBLE_EQ(t.specimen.mass_kg, 0.01);
}

/// A study of one ball specimen `ball` (its JSON) and one trial of a ball naming it.
fs::path WriteBallStudy(const std::string& name, const std::string& ball,
                        const std::string& body = R"({"model": "silhouette", "shape": "ball"})") {
  const std::string study =
      R"({"format": "hoofimpact-study/1", "specimens": {"ball": )" + ball + "}}";
  std::string trial = kTrial;
  trial.insert(1, R"("body": )" + body + ",");
  trial.replace(trial.find(R"("specimen": "A")"), 15, R"("specimen": "ball")");
  return Write(name, study, trial);
}

TEST(StudyFormatTest, ABallSpecimenGivesItsInertiaByItsRule) {
  // R = 10 mm, m = 8 g: solid 2/5 m R^2 = 3.2e-7, hollow 2/3 m R^2 = 5.333e-7 kg m^2.
  const std::string ball = R"({"shape": "ball", "diameter_m": 0.02, "mass_kg": 0.008)";
  struct Case {
    std::string inertia;
    BallInertia rule;
    double expected_kg_m2;
  };
  for (const Case& c :
       {Case{"", BallInertia::kSolid, 0.4 * 0.008 * 1e-4},
        Case{R"(, "inertia": "solid")", BallInertia::kSolid, 0.4 * 0.008 * 1e-4},
        Case{R"(, "inertia": "hollow")", BallInertia::kHollow, 2.0 / 3.0 * 0.008 * 1e-4},
        Case{R"(, "inertia": 4e-7)", BallInertia::kGiven, 4e-7}}) {
    const fs::path dir = WriteBallStudy("format_ball", ball + c.inertia + "}");
    const StudySpec study = ReadStudy(dir);
    const TrialSpec t = ReadTrial(study.trial_dirs.at(0), study);
    EXPECT_TRUE(t.specimen.is_ball());
    EXPECT_EQ(t.specimen.inertia, c.rule) << c.inertia;
    EXPECT_NEAR(t.specimen.inertia_kg_m2, c.expected_kg_m2, 1e-18) << c.inertia;
    EXPECT_DOUBLE_EQ(t.specimen.mass_kg, 0.008);
    EXPECT_DOUBLE_EQ(t.specimen.end_radius_m, 0.01);
    EXPECT_EQ(t.specimen.d_EC_m, 0.0);
    // The trial's body takes the specimen's diameter (so it can give the scale).
    EXPECT_DOUBLE_EQ(t.body.diameter_m, 0.02);
    EXPECT_TRUE(t.specimen.mass_known());
    EXPECT_NE(t.specimen_origin.find("study.json, specimens.ball"), std::string::npos);
  }
  // Without its mass the ball is measured all the same: mass and inertia unknown (NaN).
  const fs::path dir = WriteBallStudy("format_ball", R"({"shape": "ball", "diameter_m": 0.02})");
  const TrialSpec t = ReadTrial(dir / "t1");
  EXPECT_FALSE(t.specimen.mass_known());
  EXPECT_TRUE(std::isnan(t.specimen.inertia_kg_m2));
}

TEST(StudyFormatTest, ABadBallNamesTheFileAndTheField) {
  const auto expect = [](const std::string& ball, const std::string& needle,
                         const std::string& body = R"({"model": "silhouette", "shape": "ball"})") {
    const fs::path dir = WriteBallStudy("format_bad_ball", ball, body);
    ExpectError([&] { ReadTrial(dir / "t1"); }, needle);
  };
  expect(R"({"shape": "cube", "diameter_m": 0.02})",
         "study.json: field \"specimens.ball.shape\" is \"cube\": must be \"ball\"");
  expect(R"({"shape": "ball"})", "study.json: field \"specimens.ball.diameter_m\" is missing");
  expect(R"({"shape": "ball", "diameter_m": 0.02, "mass_kg": 0.008, "inertia": "wooden"})",
         "field \"specimens.ball.inertia\" must be \"solid\" (2/5 m R^2), \"hollow\"");
  // More than a thin shell's 2/3 m R^2 = 5.33e-7 kg m^2: no such ball.
  expect(R"({"shape": "ball", "diameter_m": 0.02, "mass_kg": 0.008, "inertia": 6e-7})",
         "field \"specimens.ball.inertia\" is 6e-07 kg m^2, more than a thin shell's");
  expect(R"({"shape": "ball", "diameter_m": 0.02, "inertia": 3e-7})",
         "field \"specimens.ball.inertia\" is a number, which needs the ball's mass_kg");
  expect(R"({"shape": "ball", "diameter_m": 0.02, "d_EC_m": 0.001})",
         "field \"specimens.ball.d_EC_m\" applies to the hoof-wall specimen");
  // A trial that tracks markers cannot name a ball, and a ball's diameters must agree.
  expect(R"({"shape": "ball", "diameter_m": 0.02})",
         "trial.json: field \"specimen\" names the ball specimen \"ball\"",
         R"({"model": "markers"})");
  expect(R"({"shape": "ball", "diameter_m": 0.02})",
         "trial.json: field \"body.diameter_m\" is 0.025 m, but the trial names the ball "
         "specimen",
         R"({"model": "silhouette", "shape": "ball", "diameter_m": 0.025})");
}

TEST(StudyFormatTest, ANegativeDistanceFromEToCIsNamed) {
  std::string study = kStudy;
  study.replace(study.find("\"d_EC_m\": 0.0135"), 16, "\"d_EC_m\": -0.001");
  const fs::path dir = Write("format_negative_d", study, kTrial);
  ExpectError([&] { ReadStudy(dir); },
              "study.json: field \"specimens.A.d_EC_m\" must be >= 0, found -0.001");
}

}  // namespace
}  // namespace hoof::pipeline
