#include "synth/footage_timing.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>

#include <opencv2/core.hpp>

namespace hoof::synth {
namespace {

/// `count` distinct values of [lo, hi], seeded, in increasing order.
std::vector<int> Pick(int count, int lo, int hi, cv::RNG& rng) {
  std::vector<int> all(static_cast<std::size_t>(std::max(0, hi - lo + 1)));
  std::iota(all.begin(), all.end(), lo);
  for (std::size_t i = 0; i + 1 < all.size(); ++i)  // Fisher-Yates on cv::RNG (portable)
    std::swap(all[i], all[i + rng.uniform(0, static_cast<int>(all.size() - i))]);
  all.resize(std::min(all.size(), static_cast<std::size_t>(std::max(0, count))));
  std::sort(all.begin(), all.end());
  return all;
}

void EachCapture(const FootageTimingOptions& t, FrameSchedule& s, cv::RNG& rng) {
  const int captures = std::max(1, static_cast<int>(std::lround(t.duration_s * t.capture_fps)));
  for (int k = 0; k < captures; ++k) s.capture_times_s.push_back(k / t.capture_fps);
  const std::vector<int> drops = Pick(t.drop_frames, 1, captures - 2, rng);
  const std::set<int> dropped(drops.begin(), drops.end());
  for (int k = 0; k < captures; ++k) {
    if (dropped.count(k)) continue;
    DeliveredFrame f;
    f.capture_index = k;
    f.t_s = s.capture_times_s[static_cast<std::size_t>(k)];
    if (dropped.count(k - 1)) f.fault = FrameFault::kAfterDrop;
    s.frames.push_back(f);
  }
}

void LatestCapture(const FootageTimingOptions& t, FrameSchedule& s, cv::RNG& rng) {
  const int frames = std::max(1, static_cast<int>(std::lround(t.duration_s * s.container_fps)));
  const int captures = static_cast<int>(std::ceil(t.duration_s * t.capture_fps)) + 2;
  for (int k = 0; k < captures; ++k) {
    const double jitter =
        k == 0 ? 0.0 : std::clamp(t.capture_jitter_fraction * rng.gaussian(1.0), -0.45, 0.45);
    s.capture_times_s.push_back((k + jitter) / t.capture_fps);
  }
  std::size_t k = 0;
  for (int j = 0; j < frames; ++j) {
    const double tau = j / s.container_fps;
    while (k + 1 < s.capture_times_s.size() && s.capture_times_s[k + 1] <= tau + 1e-12) ++k;
    DeliveredFrame f;
    f.capture_index = static_cast<int>(k);
    f.t_s = s.capture_times_s[k];
    s.frames.push_back(f);
  }
}

}  // namespace

const char* ToString(FrameFault fault) {
  switch (fault) {
    case FrameFault::kNone:
      return "";
    case FrameFault::kRepeat:
      return "repeat";
    case FrameFault::kAfterDrop:
      return "after_drop";
  }
  return "";
}

FrameSchedule PlanFrameSchedule(const FootageTimingOptions& timing, std::uint64_t seed) {
  FrameSchedule s;
  s.capture_fps = timing.capture_fps;
  s.container_fps = ContainerFps(timing);
  s.exposure_s = ExposureSeconds(timing);
  s.delivery = timing.delivery;
  cv::RNG rng(seed * 0xC2B2AE3D27D4EB4Full + 0x71);
  if (timing.delivery == FrameDelivery::kEachCapture)
    EachCapture(timing, s, rng);
  else
    LatestCapture(timing, s, rng);
  const int n = static_cast<int>(s.frames.size());
  const int last_capture = s.frames.back().capture_index;  // before repeats replace any
  for (int j : Pick(timing.repeat_frames, 1, n - 1, rng)) {
    DeliveredFrame& f = s.frames[static_cast<std::size_t>(j)];
    f.capture_index = s.frames[static_cast<std::size_t>(j - 1)].capture_index;
    f.t_s = s.frames[static_cast<std::size_t>(j - 1)].t_s;
    f.fault = FrameFault::kRepeat;
  }
  std::set<int> shown;
  for (int j = 0; j < n; ++j) {
    DeliveredFrame& f = s.frames[static_cast<std::size_t>(j)];
    f.index = j;
    f.container_time_s = j / s.container_fps;
    f.repeated =
        j > 0 && f.capture_index == s.frames[static_cast<std::size_t>(j - 1)].capture_index;
    shown.insert(f.capture_index);
  }
  for (int k = 0; k <= last_capture; ++k)
    if (!shown.count(k)) s.dropped_captures.push_back(k);
  return s;
}

}  // namespace hoof::synth
