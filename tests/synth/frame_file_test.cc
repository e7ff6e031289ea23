// Tests of the renderer's camera-file output (issue 16, item 7: MRAW and CINE clips). One short
// trial is rendered with the same seed as PNG frames and as a Photron MRAW and a Phantom CINE
// clip; every frame read back through tracking::OpenCameraFile must equal its PNG (read by
// OpenCV) pixel for pixel, the headers must hold the options' frame rate, size, bit depth and
// shutter, the CINE time stamps the capture times of truth.json, and the MRAW trial must be
// accepted by the trial.json parser with its frame rate taken from the file. Small frames only.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "pipeline/study_format.h"
#include "synth/renderer.h"
#include "synth/test_support.h"
#include "synth/trial_files.h"
#include "tracking/camera_file.h"

namespace hoof::synth {
namespace {

namespace fs = std::filesystem;
using testing::FreshDir;
using testing::ReadJson;

// A CINE stamp is a TIME64: 2^-32 s fractions whose two low bits are flags, so it resolves
// 2^-30 s (0.93 ns).
constexpr double kStampResolution_s = 1.0 / (1 << 30);

TrialSpec Trial() {
  TrialSpec s;
  s.id = "clip";
  s.surface = dynamics::Surface::kConcrete;
  s.angle_deg = 20;
  s.speed_m_s = 3;
  s.seed = 77;
  return s;
}

// 12 frames of 160 x 128 at 4000 fps, exposure 1/10000 s, one dropped capture and one repeated
// image (with every other effect at its default: noise, blur, distortion, ...).
RenderOptions Small(int bit_depth, FrameFormat format) {
  RenderOptions o;
  o.width_px = 160;
  o.height_px = 128;
  o.m_per_px = 4e-4;
  o.fps = 4000;
  o.frames_before = 6;
  o.frames_after = 6;
  o.bit_depth = bit_depth;
  o.frame_format = format;
  o.camera.exposure_s = 1e-4;
  o.camera.drop_frames = 1;
  o.camera.duplicate_frames = 1;
  return o;
}

// Renders the trial into study/NAME/clip with study.json beside it; returns the trial folder.
fs::path Render(const std::string& name, const RenderOptions& o) {
  const fs::path study = FreshDir(name);
  fs::create_directories(study);
  const SpecimenGeometry g;
  const TrialSpec spec = Trial();
  const SceneAssets assets = BuildSceneAssets(g, o, {spec.surface}, spec.seed);
  RenderTrial(spec, g, o, assets, study / spec.id);
  std::ofstream(study / "study.json") << StudyJson(name, g, {spec.id}).dump(2);
  return study / spec.id;
}

cv::Mat Png(const fs::path& trial, int index) {
  char name[32];
  std::snprintf(name, sizeof(name), "%06d.png", index);
  return cv::imread((trial / "frames" / name).string(), cv::IMREAD_UNCHANGED);
}

bool SamePixels(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0;
}

TEST(FrameFileTest, MrawAndCineHoldThePngFramesAndTheOptionsInTheirHeaders) {
  for (int bits : {8, 16}) {
    const fs::path png = Render("png" + std::to_string(bits), Small(bits, FrameFormat::kPng));
    ASSERT_TRUE(fs::exists(png / "frames"));
    const nlohmann::json truth = ReadJson(png / "truth.json");
    const int n = static_cast<int>(truth["frames"].size());
    ASSERT_EQ(n, 12);
    for (FrameFormat format : {FrameFormat::kMraw, FrameFormat::kCine}) {
      SCOPED_TRACE(std::string(ToString(format)) + " " + std::to_string(bits) + "-bit");
      const RenderOptions o = Small(bits, format);
      const fs::path dir = Render(std::string(ToString(format)) + std::to_string(bits), o);
      EXPECT_FALSE(fs::exists(dir / "frames"));  // one clip file, no PNG folder
      const auto clip = tracking::OpenCameraFile(dir / ClipFileName(format));
      const tracking::CameraFileInfo& info = clip->info();
      EXPECT_EQ(info.format, format == FrameFormat::kMraw ? "photron-mraw" : "phantom-cine");
      EXPECT_EQ(info.width, 160);
      EXPECT_EQ(info.height, 128);
      EXPECT_EQ(info.frame_count, n);
      EXPECT_EQ(info.bit_depth, bits);
      EXPECT_EQ(info.storage_bits, bits);
      EXPECT_DOUBLE_EQ(info.fps, 4000.0);
      ASSERT_TRUE(info.shutter_s.has_value());
      EXPECT_NEAR(*info.shutter_s, 1e-4, 0.5e-9);  // both headers hold whole nanoseconds
      ASSERT_EQ(clip->count(), n);
      for (int i = 0; i < n; ++i)
        EXPECT_TRUE(SamePixels(clip->Read(i), Png(png, i))) << "frame " << i;
      // The clip's truth is the PNG trial's, frame for frame.
      const nlohmann::json t = ReadJson(dir / "truth.json");
      EXPECT_EQ(t["frames"], truth["frames"]);
      EXPECT_EQ(t["frame_file"]["file"], ClipFileName(format));
    }
  }
}

TEST(FrameFileTest, CineStampsAreTheCaptureTimesWithTheDropAsAGap) {
  const RenderOptions o = Small(16, FrameFormat::kCine);
  const fs::path dir = Render("cine_stamps", o);
  const nlohmann::json truth = ReadJson(dir / "truth.json");
  const auto clip = tracking::OpenCameraFile(dir / "clip.cine");
  const int n = static_cast<int>(truth["frames"].size());
  int drops = 0, duplicates = 0;
  for (int i = 0; i < n; ++i) {
    const nlohmann::json& f = truth["frames"][i];
    const std::string defect = f.value("defect", "");
    const std::optional<double> stamp = clip->TimeOf(i);
    ASSERT_TRUE(stamp.has_value()) << "frame " << i;
    if (defect == "duplicate") {
      // The repeated image keeps the previous frame's capture time, but the camera stamps the
      // slot it was written in: the capture it lost, one period after the one it repeats.
      ++duplicates;
      EXPECT_NEAR(f["t_s"].get<double>(), truth["frames"][i - 1]["t_s"].get<double>(), 1e-15);
      EXPECT_NEAR(*stamp, f["t_s"].get<double>() + 1 / o.fps, kStampResolution_s) << i;
    } else {
      EXPECT_NEAR(*stamp, f["t_s"].get<double>(), kStampResolution_s) << "frame " << i;
    }
    if (defect == "dropped_before") {
      // A dropped capture: two periods since the previous stamp.
      ++drops;
      EXPECT_NEAR(*stamp - *clip->TimeOf(i - 1), 2 / o.fps, 2 * kStampResolution_s) << i;
    }
  }
  EXPECT_EQ(drops, 1);
  EXPECT_EQ(duplicates, 1);
  // truth.json lists the stamps it wrote.
  ASSERT_EQ(truth["frame_file"]["time_stamps_s"].size(), static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
    EXPECT_NEAR(truth["frame_file"]["time_stamps_s"][i].get<double>(), *clip->TimeOf(i),
                kStampResolution_s);
}

TEST(FrameFileTest, TwelveBitClipsAreTheSixteenBitFramesAtTheirScale) {
  // The sensor model rounds offset + gain * v with full scale 2^bits - 1 from the same noise
  // stream, so a 12-bit count is the 16-bit one times 4095/65535 to within the two roundings
  // (0.5 + 0.5 * 4095/65535).
  const fs::path png = Render("png16_for12", Small(16, FrameFormat::kPng));
  const fs::path mraw = Render("mraw12", Small(12, FrameFormat::kMraw));
  const fs::path cine = Render("cine12", Small(12, FrameFormat::kCine));
  const auto m = tracking::OpenCameraFile(mraw / "clip.mraw");
  const auto c = tracking::OpenCameraFile(cine / "clip.cine");
  EXPECT_EQ(m->info().bit_depth, 12);
  EXPECT_EQ(m->info().storage_bits, 12);  // packed
  EXPECT_EQ(c->info().bit_depth, 12);     // RealBPP 12 in 16-bit storage
  EXPECT_EQ(c->info().storage_bits, 16);
  ASSERT_EQ(m->count(), 12);
  for (int i = 0; i < m->count(); ++i) {
    const cv::Mat twelve = m->Read(i);
    EXPECT_TRUE(SamePixels(twelve, c->Read(i))) << "frame " << i;
    double lo = 0, hi = 0;
    cv::minMaxLoc(twelve, &lo, &hi);
    EXPECT_LE(hi, 4095) << "frame " << i;
    EXPECT_GT(hi, 400) << "frame " << i;  // not an empty frame
    cv::Mat sixteen, twelve_d;
    Png(png, i).convertTo(sixteen, CV_64F, 4095.0 / 65535.0);
    twelve.convertTo(twelve_d, CV_64F);
    EXPECT_LE(cv::norm(sixteen, twelve_d, cv::NORM_INF), 0.5 + 0.5 * 4095.0 / 65535.0 + 1e-9)
        << "frame " << i;
  }
}

TEST(FrameFileTest, AnMrawTrialIsReadByTheTrialParserWithTheFileFrameRate) {
  const fs::path dir = Render("mraw_trial", Small(8, FrameFormat::kMraw));
  const nlohmann::json trial = ReadJson(dir / "trial.json");
  EXPECT_FALSE(trial.contains("fps"));  // the file records it
  EXPECT_EQ(trial["frames"]["camera_file"], "clip.mraw");
  const pipeline::TrialSpec t = pipeline::ReadTrial(dir);
  EXPECT_EQ(t.fps, 4000.0);
  EXPECT_TRUE(t.frames.is_camera_file());
  EXPECT_EQ(t.frames.first, 0);
  EXPECT_EQ(t.frames.count, 12);
  EXPECT_TRUE(t.warnings.empty());
  EXPECT_EQ(pipeline::OpenFrames(t)->count(), 12);
}

TEST(FrameFileTest, TwelveBitsAreRefusedForPngAndOddWidthsForPackedMraw) {
  RenderOptions o = Small(12, FrameFormat::kPng);
  EXPECT_THROW(o.Validate(), std::invalid_argument);
  o.frame_format = FrameFormat::kMraw;
  EXPECT_NO_THROW(o.Validate());
  o.width_px = 161;
  EXPECT_THROW(o.Validate(), std::invalid_argument);
  o.frame_format = FrameFormat::kCine;  // 16-bit storage: any width
  EXPECT_NO_THROW(o.Validate());
  EXPECT_EQ(ParseFrameFormat("cine"), FrameFormat::kCine);
  EXPECT_THROW(ParseFrameFormat("avi"), std::invalid_argument);
}

}  // namespace
}  // namespace hoof::synth
