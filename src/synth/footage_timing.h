#pragma once
/// @file
/// Which capture each delivered frame of an everyday clip shows, and when
/// (docs/synthetic-trials.md, "Everyday footage", Timing). Capture k is exposed around t_k
/// (mid-exposure, scene seconds since capture 0): t_k = k / capture_fps, or, for a screen
/// recording, that plus a seeded irregularity. Plain data.

#include <cstdint>
#include <vector>

#include "synth/footage_options.h"

namespace hoof::synth {

/// A fault of a delivered frame.
enum class FrameFault {
  kNone,
  kRepeat,     ///< A seeded repeat: shows the previous frame's capture again (its own is lost).
  kAfterDrop,  ///< The first frame after a capture that was left out.
};
/// "", "repeat" or "after_drop".
const char* ToString(FrameFault fault);

/// One frame of the file.
struct DeliveredFrame {
  int index = 0;                  ///< In the file, from 0.
  double container_time_s = 0.0;  ///< index / container_fps: its time in the file.
  int capture_index = 0;          ///< The capture it shows.
  double t_s = 0.0;               ///< That capture's mid-exposure time (scene seconds).
  bool repeated = false;          ///< Shows the same capture as the frame before.
  FrameFault fault = FrameFault::kNone;
};

/// The capture times and the delivered frames of a clip.
struct FrameSchedule {
  double capture_fps = 0.0, container_fps = 0.0, exposure_s = 0.0;
  FrameDelivery delivery = FrameDelivery::kEachCapture;
  std::vector<double> capture_times_s;  ///< t_k of every capture k.
  std::vector<DeliveredFrame> frames;
  std::vector<int> dropped_captures;  ///< Captures no frame shows (drops and lost repeats).
};

/// The schedule of `timing` (validated): kEachCapture delivers round(duration * capture_fps)
/// captures less the drops, one frame each; kLatestCapture delivers
/// max(1, round(duration * container_fps)) frames, frame j showing the latest capture with
/// t_k <= j / container_fps. Then `repeat_frames` seeded frames (never frame 0) show the
/// capture of the frame before them.
FrameSchedule PlanFrameSchedule(const FootageTimingOptions& timing, std::uint64_t seed);

}  // namespace hoof::synth
