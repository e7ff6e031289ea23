// The frame-timing detector (tracking/frame_timing.h) on frames and tracks made here with
// known repeats and drops: repeats found from the images (exact copies and copies within a
// tenth of the sensor noise, under flicker, and a compressed clip's re-encoded copies), which
// copy of a repeated image is the sample from the motion, copies coded again found from the
// body's motion where the images cannot tell them (a screen recording), slots from time
// stamps, and dropped captures from a bouncing body's track sampled at whole slots.
#include "tracking/frame_timing.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <random>
#include <set>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "tracking/frame_differences.h"
#include "tracking/silhouette_tracker.h"

namespace hoof::tracking {
namespace {

/// Frames held in memory.
class MemorySource : public FrameSource {
 public:
  explicit MemorySource(std::vector<cv::Mat> frames) : frames_(std::move(frames)) {}
  int count() const override { return static_cast<int>(frames_.size()); }
  cv::Mat Read(int index) override {
    ++reads;
    return frames_[static_cast<std::size_t>(index)];
  }
  std::string Describe(int index) const override { return "frame " + std::to_string(index); }
  std::atomic<int> reads{0};

 private:
  std::vector<cv::Mat> frames_;
};

/// A 16-bit 120 x 100 frame: a bright disc at (20 + 3 i, 50) on a grey ramp, with Gaussian noise
/// of `noise` (DN) and the brightness multiplied by `light`.
cv::Mat Frame(int i, double noise, double light, std::mt19937_64& rng) {
  cv::Mat f(100, 120, CV_64F);
  for (int y = 0; y < f.rows; ++y)
    for (int x = 0; x < f.cols; ++x) f.at<double>(y, x) = 8000 + 40 * x;
  cv::circle(f, cv::Point(20 + 3 * i, 50), 8, cv::Scalar(40000), cv::FILLED, cv::LINE_AA);
  std::normal_distribution<double> n(0, noise);
  for (auto it = f.begin<double>(); it != f.end<double>(); ++it) *it = *it * light + n(rng);
  cv::Mat out;
  f.convertTo(out, CV_16U);
  return out;
}

TEST(FrameTimingTest, RepeatsAreFoundFromTheImagesUnderNoiseAndFlicker) {
  std::mt19937_64 rng(7);
  std::vector<cv::Mat> frames;
  for (int i = 0; i < 20; ++i) {
    // Mains flicker: the brightness swings by +-10 % from frame to frame.
    const double light = 1 + 0.1 * std::sin(1.3 * i);
    frames.push_back(Frame(i, 200.0, light, rng));
  }
  frames[4] = frames[3].clone();  // the buffer re-sent byte for byte
  // A copy within a tenth of the sensor noise (re-encoded on its way).
  cv::Mat reencoded;
  frames[11].convertTo(reencoded, CV_64F);
  std::normal_distribution<double> n(0, 20.0);
  for (auto it = reencoded.begin<double>(); it != reencoded.end<double>(); ++it) *it += n(rng);
  reencoded.convertTo(frames[12], CV_16U);
  frames[15] = frames[14].clone();
  frames[16] = frames[14].clone();  // two repeats in a row

  MemorySource source(frames);
  const ImageDifferences d = DifferenceFrames(source);
  const std::vector<bool> repeat = FindRepeats(d, 0.5);
  std::set<int> found;
  for (int i = 0; i < 20; ++i)
    if (repeat[static_cast<std::size_t>(i)]) found.insert(i);
  EXPECT_EQ(found, (std::set<int>{4, 12, 15, 16}));
  EXPECT_EQ(d.mean_abs_difference[4], 0.0);
}

TEST(FrameTimingTest, TheNoiseOnlyDifferenceIsMeasuredFromTheClip) {
  std::mt19937_64 rng(5);
  std::vector<cv::Mat> frames;
  for (int i = 0; i < 12; ++i) frames.push_back(Frame(i, 200.0, 1.0, rng));
  MemorySource source(frames);
  // Two captures differ by noise of s.d. 200 sqrt(2) DN: a mean |difference| of
  // 200 sqrt(2) sqrt(2 / pi) = 226 DN, 0.00344 of full scale. Tolerance 3 %: the median
  // absolute deviation of 12000 pixels scatters by about 1 %, the upper quartile of 11 such
  // estimates lies about 0.7 of that above their mean, and the moving disc's edge is in a few
  // per cent of the pixels.
  const ImageDifferences d = DifferenceFrames(source);
  EXPECT_NEAR(d.noise_mean_abs_difference, 400 / std::sqrt(M_PI) / 65535, 0.03 * 0.00344);
}

TEST(FrameTimingTest, ANoiseFreeClipTakesOnlyExactCopiesAsRepeats) {
  std::mt19937_64 rng(1);
  std::vector<cv::Mat> frames;
  for (int i = 0; i < 8; ++i) frames.push_back(Frame(i, 0.0, 1.0, rng));
  frames[5] = frames[4].clone();
  MemorySource source(frames);
  const ImageDifferences d = DifferenceFrames(source);
  EXPECT_EQ(d.noise_mean_abs_difference, 0.0);
  const auto repeat = FindRepeats(d, 0.5);
  for (int i = 0; i < 8; ++i) EXPECT_EQ(repeat[static_cast<std::size_t>(i)], i == 5) << i;
}

// An H.264 clip: the encoder copies the still background to the bit, so two captures agree in
// most pixels and the noise-only difference reads 0; a repeated image re-encoded differs only
// in a few blocks. It is found against the frames' own differences.
TEST(FrameTimingTest, ACompressedClipsReEncodedCopiesAreRepeats) {
  std::mt19937_64 rng(1);
  std::vector<cv::Mat> frames;
  for (int i = 0; i < 12; ++i) frames.push_back(Frame(i, 0.0, 1.0, rng));
  for (int copy : {4, 9}) {
    frames[static_cast<std::size_t>(copy)] = frames[static_cast<std::size_t>(copy - 1)].clone();
    // One 8 x 8 block coded again, 3 DN off.
    frames[static_cast<std::size_t>(copy)](cv::Rect(40, 40, 8, 8)) += cv::Scalar(3);
  }
  MemorySource source(frames);
  const ImageDifferences d = DifferenceFrames(source);
  EXPECT_EQ(d.noise_mean_abs_difference, 0.0);
  const auto repeat = FindRepeats(d, 0.5);
  for (int i = 0; i < 12; ++i)
    EXPECT_EQ(repeat[static_cast<std::size_t>(i)], i == 4 || i == 9) << i;
  // A still scene, every other frame coded again in more blocks or by more (as where a small
  // body moves in a large frame): differences of 20, 60, 150, 900, 1500 and 2100 (block x DN)
  // do not fall apart into copies and new captures, and none is taken for a repeat.
  const cv::Mat base = Frame(0, 0.0, 1.0, rng);
  std::vector<cv::Mat> recoded{base};
  const std::vector<std::pair<int, int>> recode{{5, 4},   {15, 4},  {50, 3},
                                                {30, 30}, {50, 30}, {70, 30}};
  for (const auto& [blocks, dn] : recode) {
    recoded.push_back(base.clone());
    for (int b = 0; b < blocks; ++b)  // of the frame's 15 x 12
      recoded.back()(cv::Rect(8 * (b % 15), 8 * (b / 15), 8, 8)) += cv::Scalar(dn);
    recoded.push_back(base.clone());
  }
  recoded.pop_back();
  MemorySource still(recoded);
  const auto none = FindRepeats(DifferenceFrames(still), 0.5);
  for (int i = 0; i < 12; ++i) EXPECT_FALSE(none[static_cast<std::size_t>(i)]) << i;
}

TEST(FrameTimingTest, SlotsFromStampsShowAGapAndRejectStampsThatGoBack) {
  const double fps = 1000;
  const auto slots = SlotsFromStamps({0.0, 0.001, 0.002, 0.004, 0.0050000001, 0.008}, fps);
  ASSERT_TRUE(slots);
  EXPECT_EQ(*slots, (std::vector<int>{0, 1, 2, 4, 5, 8}));
  EXPECT_FALSE(SlotsFromStamps({0.0, 0.002, 0.001}, fps));
}

/// A ball's centre (px, y up) at capture slot s: dropped from rest at slot 0 with gravity
/// `a` px/slot^2 and drifting at 0.7 px/slot, bouncing at slot 10.4 with e = 0.8, then flying
/// up and slowing.
Eigen::Vector2d Ball(double s) {
  const double a = 5.0, t_touch = 10.4;
  const double v_touch = a * t_touch;
  const double y = s < t_touch ? 600 - 0.5 * a * s * s
                               : 600 - 0.5 * a * t_touch * t_touch + 0.8 * v_touch * (s - t_touch) -
                                     0.5 * a * (s - t_touch) * (s - t_touch);
  return {100 + 0.7 * s, y};
}

TEST(FrameTimingTest, DroppedCapturesAreFoundFromABouncingTrack) {
  // Captures 0..24; 3, 7 (before the bounce), 15 and 16 (two in a row, after it) never reach
  // the file; the frame after capture 19 repeats it.
  const std::set<int> dropped{3, 7, 15, 16};
  std::vector<int> true_slot;
  for (int s = 0; s <= 24; ++s) {
    if (dropped.count(s)) continue;
    true_slot.push_back(s);
  }
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n(0, 0.05);
  std::vector<std::optional<Eigen::Vector2d>> p;
  std::vector<bool> repeat;
  std::vector<int> expected;
  for (int s : true_slot) {
    p.emplace_back(Ball(s) + Eigen::Vector2d(n(rng), n(rng)));
    repeat.push_back(false);
    expected.push_back(s);
    if (s == 19) {  // the repeat takes slot 20, whose capture is lost; 21 follows
      p.push_back(p.back());
      repeat.push_back(true);
      expected.push_back(20);
    }
  }
  // The repeat took capture 20's slot: the next frame shows 21.
  std::vector<std::optional<Eigen::Vector2d>> q;
  std::vector<bool> rq;
  std::vector<int> eq;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (expected[i] == 20 && !repeat[i]) continue;
    q.push_back(p[i]);
    rq.push_back(repeat[i]);
    eq.push_back(expected[i]);
  }
  q[1] = std::nullopt;  // the body not found in frame 1
  FrameTimingOptions options;
  const auto slots = SlotsFromMotion(q, rq, Eigen::Vector2d(0, -1), options);
  EXPECT_EQ(slots, eq);

  // Without drops or repeats no slot is added (a false alarm would show as a slot > index).
  std::vector<std::optional<Eigen::Vector2d>> clean;
  for (int s = 0; s <= 24; ++s) clean.emplace_back(Ball(s) + Eigen::Vector2d(n(rng), n(rng)));
  const auto none =
      SlotsFromMotion(clean, std::vector<bool>(25, false), Eigen::Vector2d(0, -1), options);
  for (int s = 0; s <= 24; ++s) EXPECT_EQ(none[static_cast<std::size_t>(s)], s);
}

/// Frames of a bouncing ball (Ball) shown at capture slots `slot`, one per frame; a frame whose
/// slot equals the one before or after it shows that capture's image again.
struct Shown {
  std::vector<std::optional<Eigen::Vector2d>> p;
  ImageDifferences d;
};
Shown ShownAt(const std::vector<int>& slot, std::mt19937_64& rng) {
  std::normal_distribution<double> n(0, 0.3);
  Shown out;
  for (std::size_t i = 0; i < slot.size(); ++i) {
    const bool copy = i > 0 && slot[i] == slot[i - 1];
    out.p.emplace_back(copy ? *out.p.back() : Ball(slot[i]) + Eigen::Vector2d(n(rng), n(rng)));
    out.d.mean_abs_difference.push_back(i == 0 ? std::nan("") : copy ? 0.0 : 0.01);
  }
  out.d.noise_mean_abs_difference = 0.0;
  return out;
}

// A frame-rate conversion that leaves one capture in three out and shows the next one in its
// place and again (captures 0, 2, 2, 3, 5, 5, ...: the body steps two periods into the
// repeated image and one out of it) has its repeated images early: the last copy is the sample.
// A camera that re-sends its buffer in place of a lost capture (0, 1, 1, 3, 4, 4, ...) has them
// late: the first copy is.
TEST(FrameTimingTest, WhichCopyOfARepeatedImageIsTheSampleIsToldByTheMotion) {
  std::mt19937_64 rng(8);
  std::vector<int> early, late;
  for (int k = 0; k < 8; ++k) {
    early.insert(early.end(), {3 * k, 3 * k + 2, 3 * k + 2});
    late.insert(late.end(), {3 * k, 3 * k + 1, 3 * k + 1});
  }
  for (const auto& [slot, held] :
       {std::pair{early, HeldImage::kLast}, std::pair{late, HeldImage::kFirst}}) {
    const Shown shown = ShownAt(slot, rng);
    const FrameTiming t = AnalyzeFrameTiming(shown.d, 1.0, std::nullopt, shown.p,
                                             Eigen::Vector2d(0, -1), FrameTimingOptions{});
    EXPECT_EQ(t.held, held);
    // Every sample left is shown at its own capture's time (frame index = slot, one per
    // period), and one frame of each repeated image is left out.
    int samples = 0;
    for (std::size_t i = 0; i < slot.size(); ++i) {
      if (t.repeat[i]) continue;
      ++samples;
      EXPECT_EQ(t.t_s[i], slot[i])
          << "frame " << i << (held == HeldImage::kLast ? " (early)" : " (late)");
    }
    EXPECT_EQ(samples, 16);
  }
  // Where the body does not move between the copies and the samples round them there is no
  // evidence: the camera's model (the first copy) holds.
  std::vector<std::optional<Eigen::Vector2d>> still(early.size(), Eigen::Vector2d(5, 5));
  std::vector<bool> repeat(early.size(), false);
  for (std::size_t i = 1; i < early.size(); ++i) repeat[i] = early[i] == early[i - 1];
  const HeldImageEvidence none = HeldImageFromMotion(still, repeat);
  EXPECT_EQ(none.held, HeldImage::kFirst);
  EXPECT_EQ(none.runs, 0);
}

/// A screen recording: captures every 2 frames with a jitter of 0.3 frames (s.d.), each frame
/// showing the latest capture, its copies coded again (0.05 px of noise on each frame's centre)
/// and no exact copy among them, so that the images tell no copy apart. `copy` marks the frames
/// that show the same capture as the frame before.
struct Recording {
  std::vector<std::optional<Eigen::Vector2d>> p;
  std::vector<bool> copy;
  ImageDifferences d;
};
Recording ScreenRecording(int frames, std::mt19937_64& rng) {
  std::normal_distribution<double> jitter(0, 0.3), n(0, 0.05);
  std::vector<double> tau;  // capture times, in frames
  for (int k = 0; 2 * k < frames + 2; ++k)
    tau.push_back(k == 0 ? 0.0 : 2 * k + std::clamp(jitter(rng), -0.9, 0.9));
  Recording r;
  int shown = -1;
  for (int i = 0; i < frames; ++i) {
    int k = 0;
    while (k + 1 < static_cast<int>(tau.size()) && tau[static_cast<std::size_t>(k + 1)] <= i) ++k;
    r.copy.push_back(k == shown);
    shown = k;
    // Ball() is in capture periods of 2 frames.
    r.p.emplace_back(Ball(tau[static_cast<std::size_t>(k)] / 2) + Eigen::Vector2d(n(rng), n(rng)));
    r.d.mean_abs_difference.push_back(i == 0 ? std::nan("") : 0.01);
  }
  r.d.noise_mean_abs_difference = 0.0;
  return r;
}

// A small body in a large compressed frame changes it as little as a copy coded again does, so
// the images find no repeat; the body's own motion does: it stands still for a frame while it
// moves. Such a clip holds its images, and each sample's time carries a period's uncertainty.
TEST(FrameTimingTest, AScreenRecordingsCopiesAreFoundFromTheMotion) {
  std::mt19937_64 rng(21);
  int missed = 0, false_marks = 0, copies = 0;
  for (int clip = 0; clip < 10; ++clip) {
    const Recording r = ScreenRecording(44, rng);
    const std::vector<bool> from_images = FindRepeats(r.d, 0.5);
    ASSERT_EQ(std::count(from_images.begin(), from_images.end(), true), 0);
    const FrameTiming t = AnalyzeFrameTiming(r.d, 60.0, std::nullopt, r.p, Eigen::Vector2d(0, 1),
                                             FrameTimingOptions{});
    for (std::size_t i = 1; i < r.copy.size(); ++i) {
      copies += r.copy[i] ? 1 : 0;
      if (r.copy[i] && !t.repeat[i]) ++missed;
      if (!r.copy[i] && t.repeat[i]) ++false_marks;
    }
    EXPECT_EQ(t.held, HeldImage::kFirst);
    EXPECT_NEAR(t.capture_time_sd_s, 1.0 / (60.0 * std::sqrt(12.0)), 1e-15) << "clip " << clip;
  }
  // Missed: only copies where the body hardly moves (its turn at the top, or the bounce's
  // frames); marked wrongly: new captures in which it hardly moved.
  EXPECT_GT(copies, 180);
  EXPECT_LE(missed, 10) << "of " << copies << " copies";
  EXPECT_LE(false_marks, 3);
}

// Without copies, the motion finds none: a camera sampling every frame (its apexes and
// bounces included), and a body held still before it falls.
TEST(FrameTimingTest, AClipWithoutCopiesHasNoneFromTheMotion) {
  std::mt19937_64 rng(22);
  std::normal_distribution<double> n(0, 0.05);
  for (int clip = 0; clip < 10; ++clip) {
    std::vector<std::optional<Eigen::Vector2d>> every, held;
    ImageDifferences d;
    for (int i = 0; i < 44; ++i) {
      const double s = 0.5 * i + 0.1 * clip;
      every.emplace_back(Ball(s) + Eigen::Vector2d(n(rng), n(rng)));
      held.emplace_back((i < 12 ? Ball(0) : Ball(0.5 * (i - 12))) +
                        Eigen::Vector2d(n(rng), n(rng)));
      d.mean_abs_difference.push_back(i == 0 ? std::nan("") : 0.01);
    }
    for (const auto* p : {&every, &held}) {
      int candidates = -1, moving = -1;
      const std::vector<bool> r = RepeatsFromMotion(*p, FrameTimingOptions{}, &candidates, &moving);
      EXPECT_EQ(std::count(r.begin(), r.end(), true), 0) << "clip " << clip;
      EXPECT_LT(candidates, 4);
      EXPECT_GT(moving, 25);
      const FrameTiming t = AnalyzeFrameTiming(d, 60.0, std::nullopt, *p, Eigen::Vector2d(0, 1),
                                               FrameTimingOptions{});
      EXPECT_TRUE(t.repeated_frames.empty());
      EXPECT_EQ(t.capture_time_sd_s, 0.0);
    }
  }
}

// `track` compares the images while the tracker reads them (tracking/frame_differences.h):
// the clip is read once, and the comparison is the one a second pass over it makes.
TEST(FrameTimingTest, TheComparisonMadeWhileTheTrackerReadsEqualsASecondPass) {
  std::mt19937_64 rng(11);
  std::vector<cv::Mat> frames;
  for (int i = 0; i < 24; ++i) frames.push_back(Frame(i, 150.0, 1 + 0.08 * std::sin(0.9 * i), rng));
  frames[7] = frames[6].clone();
  frames[19] = frames[18].clone();

  for (int read_ahead : {0, 2}) {
    MemorySource clip(frames);
    DifferencingSource source(clip, FrameTimingOptions{}.max_grid_pixels);
    SilhouetteOptions options;
    options.read_ahead_frames = read_ahead;
    const SilhouetteTrack track = TrackSilhouette(source, options);
    ASSERT_EQ(track.frame_count(), 24);
    EXPECT_EQ(clip.reads.load(), 24) << "read_ahead " << read_ahead;  // every frame once
    const std::optional<ImageDifferences> during = source.Differences();
    ASSERT_TRUE(during.has_value());

    MemorySource again(frames);
    const ImageDifferences second = DifferenceFrames(again);
    ASSERT_EQ(during->mean_abs_difference.size(), second.mean_abs_difference.size());
    EXPECT_TRUE(std::isnan(during->mean_abs_difference[0]));
    for (std::size_t i = 1; i < second.mean_abs_difference.size(); ++i) {
      EXPECT_EQ(during->mean_abs_difference[i], second.mean_abs_difference[i]) << i;
      EXPECT_EQ(during->noise_sd[i], second.noise_sd[i]) << i;
    }
    EXPECT_EQ(during->noise_mean_abs_difference, second.noise_mean_abs_difference);

    const FrameTimingOptions o;
    const FrameTiming from_pass = AnalyzeFrameTiming(*during, 1000.0, std::nullopt, {}, {0, 1}, o);
    EXPECT_EQ(from_pass.repeated_frames, (std::vector<int>{7, 19}));
    EXPECT_EQ(from_pass.frame_count(), 24);
    EXPECT_DOUBLE_EQ(from_pass.t_s[23], 23 / 1000.0);
  }
}

// Frames read out of order (a re-read, a jump) are not compared: the comparison is then
// incomplete and the caller reads the clip again.
TEST(FrameTimingTest, AnIncompleteInOrderPassGivesNoComparison) {
  std::mt19937_64 rng(12);
  std::vector<cv::Mat> frames;
  for (int i = 0; i < 6; ++i) frames.push_back(Frame(i, 100.0, 1.0, rng));
  MemorySource clip(frames);
  DifferencingSource source(clip, FrameTimingOptions{}.max_grid_pixels);
  source.Read(0);
  source.Read(1);
  source.Read(3);  // frame 2 skipped: 3 is not compared with 1
  source.Read(0);  // a re-read
  EXPECT_FALSE(source.Differences().has_value());
  source.Read(2);
  for (int i = 3; i < 6; ++i) source.Read(i);
  EXPECT_TRUE(source.Differences().has_value());
  EXPECT_EQ(source.count(), 6);
  EXPECT_EQ(source.Describe(4), "frame 4");
}

TEST(FrameTimingTest, OptionsOutOfRangeAreRefusedByName) {
  FrameTimingOptions o;
  o.repeat_fraction_of_noise = 1.5;
  EXPECT_THROW(o.Validate(), std::invalid_argument);
  o = {};
  o.drop_significance = 0;
  EXPECT_THROW(o.Validate(), std::invalid_argument);
  o = {};
  o.repeat_step_ratio = 1.0;
  EXPECT_THROW(o.Validate(), std::invalid_argument);
  o = {};
  o.repeat_min_motion_px = 0;
  EXPECT_THROW(o.Validate(), std::invalid_argument);
  o = {};
  o.repeat_motion_fraction = 0;
  EXPECT_THROW(o.Validate(), std::invalid_argument);
  o = {};
  EXPECT_NO_THROW(o.Validate());
}

}  // namespace
}  // namespace hoof::tracking
