// Which capture each frame of an everyday clip shows (synth/footage_timing.h): a slow-motion
// file, a screen recording, and seeded repeats and drops.
#include "synth/footage_timing.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <gtest/gtest.h>

namespace hoof::synth {
namespace {

TEST(FootageTimingTest, SlowMotionStores240CapturesASecondAt30Fps) {
  FootageTimingOptions t = TimingOf(TimingPreset::kSlowMotion);
  t.duration_s = 0.25;
  const FrameSchedule s = PlanFrameSchedule(t, 1);
  ASSERT_EQ(s.frames.size(), 60u);
  EXPECT_EQ(s.container_fps, 30);
  EXPECT_NEAR(s.exposure_s, 1.0 / 480, 1e-15);
  for (const DeliveredFrame& f : s.frames) {
    EXPECT_EQ(f.capture_index, f.index);
    EXPECT_NEAR(f.t_s, f.index / 240.0, 1e-15);
    EXPECT_NEAR(f.container_time_s, f.index / 30.0, 1e-15);
    EXPECT_FALSE(f.repeated);
  }
  EXPECT_TRUE(s.dropped_captures.empty());
}

TEST(FootageTimingTest, AScreenRecordingShowsTheLatestCaptureAtEachFrame) {
  const FootageTimingOptions t = TimingOf(TimingPreset::kScreenRecording);
  const FrameSchedule s = PlanFrameSchedule(t, 5);
  ASSERT_EQ(s.frames.size(), 120u);  // 2 s at 60 fps
  int repeated = 0;
  for (const DeliveredFrame& f : s.frames) {
    const double tau = f.index / 60.0;
    EXPECT_NEAR(f.container_time_s, tau, 1e-15);
    const auto k = static_cast<std::size_t>(f.capture_index);
    EXPECT_LE(s.capture_times_s[k], tau + 1e-12);  // taken by then ...
    EXPECT_GT(s.capture_times_s[k + 1], tau);      // ... and the latest so taken
    EXPECT_EQ(f.t_s, s.capture_times_s[k]);
    const bool same = f.index > 0 && f.capture_index == s.frames[f.index - 1].capture_index;
    EXPECT_EQ(f.repeated, same) << f.index;
    repeated += f.repeated ? 1 : 0;
  }
  // About 30 distinct images a second: half the frames repeat, irregularly.
  EXPECT_NEAR(repeated, 60, 10);
  for (std::size_t k = 1; k < s.capture_times_s.size(); ++k) {
    EXPECT_NEAR(s.capture_times_s[k], static_cast<double>(k) / 30.0, 0.45 / 30 + 1e-12);
    EXPECT_GT(s.capture_times_s[k], s.capture_times_s[k - 1]);
  }
  std::set<double> gaps;
  for (std::size_t k = 1; k < 10; ++k) gaps.insert(s.capture_times_s[k] - s.capture_times_s[k - 1]);
  EXPECT_GT(gaps.size(), 5u);  // not a regular clock
}

TEST(FootageTimingTest, RepeatsAndDropsFallAtSeededPlaces) {
  FootageTimingOptions t;
  t.repeat_frames = 3;
  t.drop_frames = 2;
  const FrameSchedule s = PlanFrameSchedule(t, 9);
  ASSERT_EQ(s.frames.size(), 58u);  // 60 captures less 2 dropped
  int repeats = 0, after_drop = 0;
  std::set<int> shown;
  for (const DeliveredFrame& f : s.frames) {
    shown.insert(f.capture_index);
    EXPECT_NEAR(f.t_s, f.capture_index / 30.0, 1e-15);
    if (f.fault == FrameFault::kRepeat) {
      ++repeats;
      ASSERT_GT(f.index, 0);
      EXPECT_TRUE(f.repeated);
      EXPECT_EQ(f.capture_index, s.frames[f.index - 1].capture_index);
    } else if (f.index > 0) {
      EXPECT_GT(f.capture_index, s.frames[f.index - 1].capture_index);
      EXPECT_FALSE(f.repeated);
    }
    after_drop += f.fault == FrameFault::kAfterDrop ? 1 : 0;
  }
  EXPECT_EQ(repeats, 3);
  EXPECT_LE(after_drop, 2);
  // The captures no frame shows: the 2 drops and the 3 that the repeats replaced.
  EXPECT_EQ(s.dropped_captures.size(), 5u);
  for (int k : s.dropped_captures) EXPECT_FALSE(shown.count(k));
  // The same seed gives the same places; another seed others.
  const FrameSchedule again = PlanFrameSchedule(t, 9), other = PlanFrameSchedule(t, 10);
  EXPECT_EQ(again.dropped_captures, s.dropped_captures);
  EXPECT_NE(other.dropped_captures, s.dropped_captures);
}

}  // namespace
}  // namespace hoof::synth
