// End-to-end tests of `hoofimpact synth`: a small trial and study, and clear errors for bad
// input naming the option.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/run_command.h"

namespace hoof::cli {
namespace {

using hoof::testing::RunHoofimpact;
namespace fs = std::filesystem;

fs::path Fresh(const std::string& name) {
  const fs::path p = fs::path(HOOF_BINARY_DIR) / "synth-cli-test" / name;
  fs::remove_all(p);
  fs::create_directories(p.parent_path());
  return p;
}

TEST(SynthCommandTest, WritesATrialAndPrintsAJsonSummary) {
  const fs::path out = Fresh("trial");
  const auto r = RunHoofimpact("synth -o " + out.string() +
                               " --surface concrete --angle-deg 10 --speed-m-s 2.5 --seed 3 "
                               "--frames-before 4 --frames-after 4 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out).at("results");
  ASSERT_EQ(j["trials"].size(), 1u);
  EXPECT_EQ(j["trials"][0]["frames"], 8);
  EXPECT_TRUE(fs::exists(out / "trial.json"));
  EXPECT_TRUE(fs::exists(out / "truth.json"));
  EXPECT_TRUE(fs::exists(out / "frames" / "000007.png"));
  // An existing trial is not replaced without --overwrite.
  const auto again =
      RunHoofimpact("synth -o " + out.string() + " --frames-before 4 --frames-after 4");
  EXPECT_EQ(again.exit_code, 1);
  EXPECT_NE(again.err.find("--overwrite"), std::string::npos) << again.err;
}

TEST(SynthCommandTest, WritesASmallStudy) {
  const fs::path out = Fresh("study");
  const auto r = RunHoofimpact("synth --study -o " + out.string() +
                               " --surfaces steel,asphalt --angles-deg 0 --speeds 3 "
                               "--trials-per-cell 1 --frames-before 3 --frames-after 3 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out).at("results");
  EXPECT_EQ(j["trials"].size(), 2u);
  EXPECT_TRUE(fs::exists(out / "study.json"));
  EXPECT_TRUE(fs::exists(out / "asphalt_0deg_v3.00_r1" / "frames" / "000005.png"));
}

// A study rendered into a folder that holds one already: refused at once without --overwrite,
// with nothing rendered and study.json as it was; with it, the design's trials are replaced and
// the earlier study's other trials stay listed (study.json once listed only the new ones).
TEST(SynthCommandTest, AStudyIntoAnExistingStudyIsRefusedOrKeepsItsTrialsListed) {
  const fs::path out = Fresh("existing-study");
  const std::string small =
      " --angles-deg 0 --speeds 3 --trials-per-cell 1 --frames-before 3 "
      "--frames-after 3 --json";
  auto r = RunHoofimpact("synth --study -o " + out.string() + " --surfaces steel,asphalt" + small);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto read_list = [&] {
    std::ifstream in(out / "study.json");
    return nlohmann::json::parse(in).at("trials").get<std::vector<std::string>>();
  };
  const std::vector<std::string> first = read_list();
  ASSERT_EQ(first.size(), 2u);

  r = RunHoofimpact("synth --study -o " + out.string() + " --surfaces concrete" + small);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find((out / "study.json").string() + " exists"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--overwrite"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out / "concrete_0deg_v3.00_r1"));
  EXPECT_EQ(read_list(), first);

  r = RunHoofimpact("synth --study --overwrite -o " + out.string() + " --surfaces concrete,steel" +
                    small);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> both = read_list();
  EXPECT_EQ(both.size(), 3u);
  for (const std::string id :
       {"steel_0deg_v3.00_r1", "asphalt_0deg_v3.00_r1", "concrete_0deg_v3.00_r1"})
    EXPECT_NE(std::find(both.begin(), both.end(), id), both.end()) << id;
}

TEST(SynthCommandTest, SpeedDependentFrictionIsHiddenAndRecordedInTruth) {
  // The effect outside the discovery library, from the flag and from a study config: truth.json
  // records the slope, and the simulator used it (at 30 deg T slides the whole contact at
  // about 1 m/s or more, so mu_eff ~ mu (1 + s |v_T|) lies well above the drawn mu).
  const fs::path trial = Fresh("speed-friction-trial");
  auto r = RunHoofimpact("synth -o " + trial.string() +
                         " --surface steel --angle-deg 30 --speed-m-s 3 --seed 5 "
                         "--frames-before 2 --frames-after 2 --clean "
                         "--friction-speed-slope-s-m 0.5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(trial / "truth.json");
  const auto truth = nlohmann::json::parse(in);
  const auto& model = truth["model"];
  EXPECT_EQ(model["hidden_effects"]["friction_speed_slope_s_m"].get<double>(), 0.5);
  EXPECT_GT(truth["mu_eff"].get<double>(), 1.2 * model["mu"].get<double>());

  const fs::path study = Fresh("speed-friction-study");
  const fs::path config = study.string() + ".json";
  {
    std::ofstream out(config);
    out << R"({"cells": [{"surface": "asphalt", "angle_deg": 20, "speed_m_s": 2.5}],
               "trials_per_cell": 1, "hidden_effects": {"friction_speed_slope_s_m": 0.25}})";
  }
  r = RunHoofimpact("synth --study -o " + study.string() + " --study-config " + config.string() +
                    " --frames-before 2 --frames-after 2 --clean");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in_study(study / "asphalt_20deg_v2.50_r1" / "truth.json");
  const auto study_truth = nlohmann::json::parse(in_study);
  EXPECT_EQ(study_truth["model"]["hidden_effects"]["friction_speed_slope_s_m"].get<double>(), 0.25);
  // A negative slope is a command-line error naming the option.
  r = RunHoofimpact("synth -o " + Fresh("speed-friction-bad").string() +
                    " --friction-speed-slope-s-m -1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--friction-speed-slope-s-m"), std::string::npos) << r.err;
}

TEST(SynthCommandTest, ScatterScaleIsAFlagAndAStudyConfigKeyAndIsRecordedInTruth) {
  const fs::path trial = Fresh("scatter-scale-trial");
  auto r = RunHoofimpact("synth -o " + trial.string() +
                         " --surface steel --seed 5 --frames-before 2 --frames-after 2 --clean "
                         "--scatter-scale 0.5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(trial / "truth.json");
  const auto truth = nlohmann::json::parse(in);
  EXPECT_EQ(truth["model"]["scatter_scale"].get<double>(), 0.5);
  EXPECT_TRUE(truth["model"]["scatter_parameters"].get<bool>());

  const fs::path study = Fresh("scatter-scale-study");
  const fs::path config = study.string() + ".json";
  {
    std::ofstream out(config);
    out << R"({"cells": [{"surface": "concrete", "angle_deg": 10, "speed_m_s": 2.5}],
               "trials_per_cell": 1, "scatter_scale": 0.25})";
  }
  r = RunHoofimpact("synth --study -o " + study.string() + " --study-config " + config.string() +
                    " --frames-before 2 --frames-after 2 --clean");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in_study(study / "concrete_10deg_v2.50_r1" / "truth.json");
  EXPECT_EQ(nlohmann::json::parse(in_study)["model"]["scatter_scale"].get<double>(), 0.25);

  // Bad values name the option (a command-line error, exit 2), or the field and the file when
  // they come from the config (bad input, exit 1).
  r = RunHoofimpact("synth -o " + Fresh("scatter-scale-bad").string() + " --scatter-scale 5");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--scatter-scale"), std::string::npos) << r.err;
  {
    std::ofstream out(config);
    out << R"({"scatter_scale": -0.5})";
  }
  r = RunHoofimpact("synth --study -o " + Fresh("scatter-scale-bad-study").string() +
                    " --study-config " + config.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("scatter_scale"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(config.string()), std::string::npos) << r.err;
}

TEST(SynthCommandTest, BadInputNamesTheOptionAndFails) {
  // Option values out of range are command-line errors (exit 2) naming the option; the others
  // (an unknown surface name) are bad input (exit 1).
  const std::string out = Fresh("bad").string();
  auto r = RunHoofimpact("synth -o " + out + " --speed-m-s -3");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--speed-m-s"), std::string::npos) << r.err;
  r = RunHoofimpact("synth -o " + out + " --angle-deg 75");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--angle-deg"), std::string::npos) << r.err;
  r = RunHoofimpact("synth -o " + out + " --surface wood");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("--surface"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("wood"), std::string::npos) << r.err;
  r = RunHoofimpact("synth -o /proc/hoof-no-such/trial");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--output"), std::string::npos) << r.err;
  r = RunHoofimpact("synth -o " + out + " --study --speeds 2,-1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--speeds"), std::string::npos) << r.err;
  r = RunHoofimpact("synth -o " + out + " --tilt-deg 80");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--tilt-deg"), std::string::npos) << r.err;
  r = RunHoofimpact("synth");
  EXPECT_EQ(r.exit_code, 2);  // --output is required
  r = RunHoofimpact("synth --help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* option :
       {"--speed-m-s", "--angle-deg", "--m-per-px", "--no-noise", "--exposure-s", "--tilt-deg",
        "--hunt-crossley-n-s-m2", "--study", "--trials-per-cell"})
    EXPECT_NE(r.out.find(option), std::string::npos) << option;
  EXPECT_FALSE(fs::exists(out));
}

// A back-lit ball that bounces three times at 250 fps, with flicker and counted frame faults:
// the clip is sized from the flight and truth lists every impact and fault.
TEST(SynthCommandTest, BouncingBackLitBallWithFrameFaultsAndFlicker) {
  const fs::path out = Fresh("ball");
  const auto r = RunHoofimpact(
      "synth -o " + out.string() +
      " --body ball --ball-diameter-m 0.01 --lighting backlit --bounces 3 --speed-m-s 0.8 "
      "--fps 250 --m-per-px 4e-4 --width-px 96 --height-px 96 --frames-from-flight --mu 0 "
      "--flicker-hz 100 --flicker-depth 0.2 --duplicate-frames 2 --drop-frames 1 --seed 4");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto truth = nlohmann::json::parse(std::ifstream(out / "truth.json"));
  EXPECT_EQ(truth["body"]["kind"], "ball");
  EXPECT_EQ(truth["lighting"], "backlit");
  ASSERT_EQ(truth["impacts"].size(), 3u);
  EXPECT_EQ(truth["impacts"][0]["e"], truth["e"]);  // the single-impact fields: the first
  EXPECT_EQ(truth["duplicate_frames"].size(), 2u);
  EXPECT_EQ(truth["dropped_captures"].size(), 1u);
  // Released at rest 0.8 / g = 0.082 s before touch: 20 frames at 250 fps.
  EXPECT_EQ(truth["first_frame_after_touch"], 20);
  const auto trial = nlohmann::json::parse(std::ifstream(out / "trial.json"));
  EXPECT_EQ(trial["frames"]["count"], truth["frames"].size());
  EXPECT_NE(trial["notes"].get<std::string>().find("ball"), std::string::npos);
}

// --frame-format mraw writes one clip that trial.json names, and no frames/ folder.
TEST(SynthCommandTest, FrameFormatMrawWritesOneClipThatTrialJsonNames) {
  const fs::path out = Fresh("mraw");
  const auto r = RunHoofimpact("synth -o " + out.string() +
                               " --frame-format mraw --width-px 96 --height-px 96 --m-per-px 4e-4 "
                               "--frames-before 3 --frames-after 3 --seed 2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_regular_file(out / "clip.mraw"));
  EXPECT_TRUE(fs::is_regular_file(out / "clip.cihx"));
  EXPECT_FALSE(fs::exists(out / "frames"));
  EXPECT_EQ(fs::file_size(out / "clip.mraw"), 6u * 96 * 96);  // 6 frames of 8 bits
  const auto trial = nlohmann::json::parse(std::ifstream(out / "trial.json"));
  EXPECT_EQ(trial["frames"]["camera_file"], "clip.mraw");
  EXPECT_EQ(trial["frames"]["count"], 6);
  EXPECT_FALSE(trial.contains("fps"));
}

TEST(SynthCommandTest, BadBodyLightingAndFaultOptionsNameTheOption) {
  const std::string out = Fresh("bad-new").string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--body cube", "--body"},
      {"--study --bounces 2", "--bounces"},
      {"--flicker-hz 100 --flicker-depth 1.5", "--flicker-depth"},
      // The default exposure (1/16000 s) is longer than a frame at 30 000 fps: the message
      // names --exposure-s (it named --fps, found as the word 'fps' in '1/fps').
      {"--fps 30000", "--exposure-s: must not exceed the frame period"},
      {"--frames-before 2 --frames-after 2 --duplicate-frames 4", "duplicate_frames"},
      {"--frame-format avi", "--frame-format"},
      {"--bit-depth 12", "--bit-depth: must be 8 or 16 for PNG frames"},
      {"--frame-format mraw --bit-depth 12 --width-px 511", "--width-px: must be even"},
      {"--frame-format cine --contact-sheet x.png", "--contact-sheet reads PNG frames"},
  };
  for (const auto& [args, name] : cases) {
    const auto r = RunHoofimpact("synth -o " + out + " " + args);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.err;
    EXPECT_NE(r.err.find(name), std::string::npos) << args << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace hoof::cli
