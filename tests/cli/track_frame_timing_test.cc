// `hoofimpact track` on rendered low-frame-rate clips with repeated frames and dropped captures
// (hoofimpact synth --duplicate-frames / --drop-frames, whose truth.json lists them): the
// frame timing (tracking/frame_timing.h) finds exactly the faults truth lists, and e comes out
// within the 0.03 of the truth at 60 fps. Small frames (128 x 160 px), 24 frames each.
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/run_command.h"

namespace {

namespace fs = std::filesystem;
using hoof::testing::RunHoofimpact;

/// A back-lit 30 mm ball dropped from rest, touching at 2 m/s, 2 mm/px, from release to the
/// rebound's apex (--frames-from-flight), rendered with `faults` and `seed`.
fs::path RenderBall(const std::string& name, const std::string& options, int seed) {
  const fs::path dir = fs::path(HOOF_BINARY_DIR) / "test-output" / "track_frame_timing" /
                       (name + std::to_string(seed));
  fs::remove_all(dir);
  const auto r = RunHoofimpact(
      "synth -o " + dir.string() +
      " --body ball --lighting backlit --ball-diameter-m 0.03 --m-per-px 2e-3 --width-px 128 "
      "--height-px 160 --frames-from-flight --speed-m-s 2 --seed " +
      std::to_string(seed) + " " + options);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return dir;
}

struct Tracked {
  nlohmann::json truth, results;
};

Tracked Track(const fs::path& dir, const std::string& options = "") {
  Tracked t;
  t.truth = nlohmann::json::parse(std::ifstream(dir / "truth.json"));
  const auto r = RunHoofimpact("track " + dir.string() + " --json " + options);
  t.results = nlohmann::json::parse(r.out)["results"];
  return t;
}

std::vector<int> Ints(const nlohmann::json& j) { return j.get<std::vector<int>>(); }

// The figure: e within 0.03 of the truth at 60 fps with duplicated frames. Measured
// over seeds 1-20 (docs/tracking.md): the repeats were found exactly in 20 of 20 and e was
// within 0.001 in every one; three seeds here.
TEST(TrackFrameTimingTest, RepeatedFramesAt60FpsAreFoundAndLeftOut) {
  for (int seed : {1, 2, 3}) {
    const auto t = Track(RenderBall("repeats-60-", "--fps 60 --duplicate-frames 2", seed));
    const auto& j = t.results;
    ASSERT_TRUE(j["success"]) << j["error"];
    EXPECT_EQ(Ints(j["frame_timing"]["repeated_frames"]), Ints(t.truth["duplicate_frames"]))
        << seed;
    EXPECT_TRUE(j["frame_timing"]["dropped_captures"].empty()) << seed;
    EXPECT_NEAR(j["e"].get<double>(), t.truth["e"].get<double>(), 0.03) << seed;
    // Every frame that is not a repeat is timed by the capture it shows.
    const auto& frames = t.truth["frames"];
    const auto slots = Ints(j["frame_timing"]["capture_slots"]);
    for (std::size_t i = 0; i < frames.size(); ++i) {
      if (frames[i].contains("duplicate")) continue;
      EXPECT_EQ(slots[i], frames[i]["capture_index"].get<int>()) << seed << " frame " << i;
    }
  }
}

// Switched off, the same clip's repeats are samples again.
TEST(TrackFrameTimingTest, NoFrameTimingTakesEveryFrameAsANewCapture) {
  const auto t = Track(RenderBall("off-", "--fps 60 --duplicate-frames 2", 1), "--no-frame-timing");
  EXPECT_EQ(t.results["frame_timing"]["source"], "frame_index");
  EXPECT_TRUE(t.results["frame_timing"]["repeated_frames"].empty());
}

// A dropped capture inside a flight is found from the motion (no time stamps in PNG frames).
// Measured over seeds 1-20: 18 of 20 found exactly; the two missed (seeds 5 and 16) lie
// between the last frame before the impact and the first after it, where the motion cannot
// show a drop (docs/tracking.md). Seeds 1 and 2 drop captures 19 and 4, inside the flights.
// The search is asked for (--drops-from-motion); by default frame i is capture i.
TEST(TrackFrameTimingTest, DroppedCapturesAt60FpsAreFoundFromTheMotion) {
  for (int seed : {1, 2}) {
    const fs::path clip = RenderBall("drops-60-", "--fps 60 --drop-frames 1", seed);
    const auto plain = Track(clip);
    EXPECT_EQ(plain.results["frame_timing"]["source"], "frame_index") << seed;
    EXPECT_TRUE(plain.results["frame_timing"]["dropped_captures"].empty()) << seed;
    const auto t = Track(clip, "--drops-from-motion");
    const auto& j = t.results;
    ASSERT_TRUE(j["success"]) << j["error"];
    EXPECT_EQ(j["frame_timing"]["source"], "motion");
    EXPECT_EQ(Ints(j["frame_timing"]["dropped_captures"]), Ints(t.truth["dropped_captures"]))
        << seed;
    EXPECT_NEAR(j["e"].get<double>(), t.truth["e"].get<double>(), 0.03) << seed;
  }
}

// A CINE clip's time stamps show the gap of a dropped capture.
TEST(TrackFrameTimingTest, ACineClipsTimeStampsShowADroppedCapture) {
  const auto t = Track(RenderBall("cine-", "--fps 60 --frame-format cine --drop-frames 2", 1));
  const auto& j = t.results;
  EXPECT_EQ(j["frame_timing"]["source"], "time_stamps");
  EXPECT_EQ(Ints(j["frame_timing"]["dropped_captures"]), Ints(t.truth["dropped_captures"]));
}

// The same when trial.json takes a range of the CINE (frames.first 1): the range keeps the
// file's time stamps, counted from its own first frame, so every capture slot moves by one.
TEST(TrackFrameTimingTest, ARangeOfACineClipKeepsItsTimeStamps) {
  const fs::path dir = RenderBall("cine-range-", "--fps 60 --frame-format cine --drop-frames 2", 1);
  nlohmann::json trial = nlohmann::json::parse(std::ifstream(dir / "trial.json"));
  ASSERT_TRUE(trial["frames"].contains("camera_file")) << trial["frames"].dump();
  trial["frames"]["first"] = 1;
  trial["frames"].erase("count");  // the rest of the clip
  std::ofstream(dir / "trial.json") << trial.dump(2);
  const auto t = Track(dir);
  const auto& j = t.results;
  EXPECT_EQ(j["frame_timing"]["source"], "time_stamps");
  std::vector<int> expected = Ints(t.truth["dropped_captures"]);
  ASSERT_EQ(expected.size(), 2u);
  for (int& slot : expected) {
    ASSERT_GE(slot, 2);  // a drop after frame 1: the range's slots are the file's less one
    --slot;
  }
  EXPECT_EQ(Ints(j["frame_timing"]["dropped_captures"]), expected);
}

// A clip without faults reports none (measured: no false report in 20 seeds at 60 fps).
TEST(TrackFrameTimingTest, AClipWithoutFaultsReportsNone) {
  for (int seed : {4, 5}) {
    const auto t = Track(RenderBall("clean-", "--fps 60", seed));
    EXPECT_TRUE(t.results["frame_timing"]["repeated_frames"].empty()) << seed;
    EXPECT_TRUE(t.results["frame_timing"]["dropped_captures"].empty()) << seed;
  }
}

}  // namespace
