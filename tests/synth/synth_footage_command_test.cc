// End-to-end tests of `hoofimpact synth footage`: a small H.264 clip and its truth, a slow-motion
// PNG variant, the rotation tag added by tools/tag-rotation and shown upright by a player, and bad
// options refused naming the option, before anything is written.
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "support/run_command.h"

namespace hoof::cli {
namespace {

using hoof::testing::RunHoofimpact;
namespace fs = std::filesystem;

fs::path Fresh(const std::string& name) {
  const fs::path p = fs::path(HOOF_BINARY_DIR) / "synth-footage-cli-test" / name;
  fs::remove_all(p);
  fs::create_directories(p.parent_path());
  return p;
}

nlohmann::json ReadJson(const fs::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

const std::string kSmall = " --width-px 256 --height-px 144 --duration-s 0.5";

TEST(SynthFootageCommandTest, WritesAClipAndItsTruthButNoTrial) {
  const fs::path out = Fresh("clip");
  const auto r = RunHoofimpact("synth footage -o " + out.string() + kSmall + " --seed 4 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["command"], "synth");
  const auto& res = j["results"];
  EXPECT_TRUE(res["footage"].get<bool>());
  EXPECT_EQ(res["frames"], 15);
  EXPECT_TRUE(fs::exists(out / "clip.mp4"));
  EXPECT_FALSE(fs::exists(out / "trial.json"));
  const auto truth = ReadJson(out / "truth.json");
  EXPECT_EQ(truth["format"], "hoofimpact-footage-truth/1");
  EXPECT_EQ(truth["frames"].size(), 15u);
  EXPECT_EQ(truth["image"]["width_px"], 256);
  EXPECT_EQ(truth["seed"], 4);
  cv::VideoCapture cap((out / "clip.mp4").string(), cv::CAP_FFMPEG);
  ASSERT_TRUE(cap.isOpened());
  EXPECT_EQ(cap.get(cv::CAP_PROP_FRAME_WIDTH), 256);
  EXPECT_NEAR(cap.get(cv::CAP_PROP_FPS), 30, 1e-6);
  // Not replaced without --overwrite.
  const auto again = RunHoofimpact("synth footage -o " + out.string() + kSmall);
  EXPECT_EQ(again.exit_code, 1);
  EXPECT_NE(again.err.find("--overwrite"), std::string::npos) << again.err;
}

TEST(SynthFootageCommandTest, SlowMotionAsLosslessFrames) {
  const fs::path out = Fresh("slow");
  const auto r = RunHoofimpact("synth footage -o " + out.string() +
                               " --width-px 160 --height-px 90 --duration-s 0.1 --timing "
                               "slow-motion --codec png --release-time-s 0.02");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto truth = ReadJson(out / "truth.json");
  EXPECT_EQ(truth["timing"]["capture_fps"], 240);
  EXPECT_EQ(truth["timing"]["container_fps"], 30);
  EXPECT_EQ(truth["frames"].size(), 24u);
  EXPECT_TRUE(fs::exists(out / "frames" / "000023.png"));
  EXPECT_NEAR(truth["frames"][23]["t_s"].get<double>(), 23 / 240.0, 1e-12);
  EXPECT_NEAR(truth["frames"][23]["container_time_s"].get<double>(), 23 / 30.0, 1e-12);
}

TEST(SynthFootageCommandTest, TagRotationAddsTheTagAPlayerTurnsUpright) {
  const fs::path out = Fresh("rotated");
  auto r = RunHoofimpact("synth footage -o " + out.string() + kSmall + " --rotation-tag-deg 270");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("tools/tag-rotation"), std::string::npos) << r.out;
  const std::string tool = std::string(HOOF_SOURCE_DIR) + "/tools/tag-rotation";
  ASSERT_EQ(std::system((tool + " " + out.string()).c_str()), 0);
  // A player (ffmpeg) shows the frames as truth.json's image: upright.
  const fs::path shown = out / "shown.png";
  ASSERT_EQ(std::system(("ffmpeg -v error -y -i '" + (out / "clip.mp4").string() +
                         "' -frames:v 1 '" + shown.string() + "'")
                            .c_str()),
            0);
  const cv::Mat frame = cv::imread(shown.string());
  ASSERT_FALSE(frame.empty());
  EXPECT_EQ(frame.cols, 256);
  EXPECT_EQ(frame.rows, 144);
  EXPECT_EQ(std::system((tool + " /nonexistent-dir 2>/dev/null").c_str()) != 0, true);
}

TEST(SynthFootageCommandTest, BadOptionsNameTheOptionAndWriteNothing) {
  const fs::path out = Fresh("bad");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--ball-radius-m 5", "--ball-radius-m"},
      {"--rotation-tag-deg 45", "--rotation-tag-deg"},
      {"--rotation-tag-deg 90 --codec png", "--rotation-tag-deg"},
      {"--codec gif", "--codec"},
      {"--ball-color purple", "--ball-color"},
      {"--e 1.5", "--e"},
      {"--velocity-m-s 0,0,30", "--velocity-m-s"},
      {"--scenario never-lands --velocity-m-s 0.5,0.5,0", "--velocity-m-s"},
      {"--velocity-m-s 0,0,-3", "--velocity-m-s"},  // into the back wall, in view
      {"--fps 0", "--fps"},
      {"--timing sideways", "--timing"},
      {"--release-time-s 9", "--release-time-s"},
      {"--camera-m 0,-1,1", "--camera-m"},
      {"--repeat-frames -2", "--repeat-frames"},
  };
  for (const auto& [args, option] : cases) {
    const auto r = RunHoofimpact("synth footage -o " + out.string() + " " + args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(option), std::string::npos) << args << "\n" << r.err;
    EXPECT_EQ(r.err.find("FootageSpec"), std::string::npos) << args << "\n" << r.err;
  }
  // The trial options of `synth` do not apply to footage.
  auto r = RunHoofimpact("synth --surface steel footage -o " + out.string());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--surface"), std::string::npos) << r.err;
  r = RunHoofimpact("synth footage");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--output"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  r = RunHoofimpact("synth footage --help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* option : {"--scenario", "--timing", "--rotation-tag-deg", "--ball-color"})
    EXPECT_NE(r.out.find(option), std::string::npos) << option;
}

}  // namespace
}  // namespace hoof::cli
