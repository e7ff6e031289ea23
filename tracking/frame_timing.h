#pragma once
/// @file
/// When each frame was captured (docs/tracking.md, "Frame timing"): frames that repeat the
/// previous image (a frame grabber re-sending its last buffer, a frame-rate conversion) are
/// found from the images, and captures that never reached the file are found from the camera's
/// time stamps where the file has them (CINE), otherwise from the body's motion. Every frame is
/// given its capture slot, so that its time is slot / fps instead of index / fps.
///
/// The model (that of a camera with a fixed frame period): capture slot s is taken at s / fps.
/// A repeated frame takes a slot of its own, but shows the previous frame's image (its own
/// capture was lost); a dropped capture leaves its slot out, so every later frame shows a
/// capture one slot later than its index.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "tracking/frame_source.h"

namespace hoof::tracking {

/// Settings of the frame-timing analysis.
struct FrameTimingOptions {
  /// false: every frame is a new capture at index / fps (the detection is skipped).
  bool enabled = true;
  /// A frame repeats the previous one when the mean absolute difference of the two images is
  /// below this fraction of what two captures of a still scene differ by through sensor noise
  /// alone (estimated from the clip), or is exactly 0. In (0, 1).
  double repeat_fraction_of_noise = 0.5;
  /// The image difference is taken on a grid of at most this many pixels (every k-th row and
  /// column; a 1024 x 1024 frame's every 8th): its mean absolute difference then has a relative
  /// s.e. under 1 %, while the comparison stays a fraction of the frame's reading time; >= 1000.
  int max_grid_pixels = 16384;
  /// Look for dropped captures in the motion where the file has no time stamps. Off by
  /// default: a contact's frames, which leave the free-flight parabola, can be taken for a
  /// drop (a marked specimen at 8000 fps got a false drop that moved its v by 6 %), while a
  /// drop the motion misses costs little at high frame rates. Without it and without stamps,
  /// frame i is capture i (repeats are still found from the images).
  bool drops_from_motion = false;
  /// A dropped capture is accepted from the motion when putting it in lowers the residual sum
  /// of squares of the flight's parabola by more than this many times the residual variance
  /// (with the variance at least position_noise_floor_px^2); > 0.
  double drop_significance = 50.0;
  /// Smallest position noise assumed (px) when judging a dropped capture from the motion; > 0.
  double position_noise_floor_px = 0.05;
  /// Repeats from the motion (RepeatsFromMotion): a frame whose body moved less than this
  /// fraction of its larger neighbouring step since the frame before; in (0, 1).
  double repeat_step_ratio = 0.1;
  /// ... where that neighbouring step is at least this many px (the body is moving); > 0.
  double repeat_min_motion_px = 1.0;
  /// ... taken only where at least this fraction of the frames in which the body moves are such
  /// frames (at least 4 of them): a clip that holds its images, not an apex; in (0, 1).
  double repeat_motion_fraction = 0.15;

  /// Throws std::invalid_argument naming the field that is out of range.
  void Validate() const;
};

/// How the capture slots were assigned.
enum class TimingSource {
  kFrameIndex,  ///< slot = index (the detection is off)
  kTimeStamps,  ///< from the file's per-frame time stamps
  kMotion,      ///< from the body's motion (free-flight parabolas at whole slots)
};

/// "frame_index", "time_stamps", "motion".
std::string TimingSourceName(TimingSource source);

/// Mean absolute difference of each frame from the one before (the first frame's is NaN), in
/// units of the file's full scale (8-bit / 255, 16-bit / 65535, float as is), and what two
/// captures of a still scene differ by through noise alone.
struct ImageDifferences {
  std::vector<double> mean_abs_difference;
  /// Per pair: 1.4826 x the median absolute deviation of the difference (a robust s.d.).
  std::vector<double> noise_sd;
  /// The clip's noise-only mean absolute difference: sqrt(2 / pi) times the upper quartile of
  /// noise_sd (robust while fewer than three quarters of the frames are repeats); 0 for a
  /// noise-free or coarsely quantized clip, where only exact repeats are taken.
  double noise_mean_abs_difference = 0.0;
};

/// Reads every frame of `source` once, in order, and compares each with the one before on a
/// grid of at most `max_grid_pixels` pixels. The previous frame is first scaled by the median
/// ratio of the two and the difference's median taken out, so that a change of overall
/// brightness (mains flicker multiplies the image) is not taken for motion.
ImageDifferences DifferenceFrames(FrameSource& source, int max_grid_pixels = 16384);

/// Which frames repeat the previous one: a difference of exactly 0, or below `fraction` of the
/// clip's noise-only difference. Where that is 0 (a compressed clip whose encoder copies the
/// still background exactly, so that most pixels agree to the bit), below a tenth of `fraction`
/// of the upper quartile of the clip's differences instead (a re-encoded copy differs in a few
/// blocks, a new capture wherever the body moved), where those below stand apart from the rest
/// (the smallest above at least 3 times the largest below); otherwise only exact copies. Frame
/// 0 never does.
std::vector<bool> FindRepeats(const ImageDifferences& d, double fraction);

/// Which frames repeat the previous one by the body's motion `p` (per frame, any unit such as
/// px; nullopt where not found), for a clip whose copies the images cannot tell apart (a small
/// body in a large compressed frame, where a copy coded again changes the frame as much as a
/// new capture does): frame i when the body moved from frame i - 1 by less than
/// `options.repeat_step_ratio` of the larger of its steps into frame i - 1 and out of frame i,
/// and that step is at least `options.repeat_min_motion_px`. They are taken only where they
/// are at least `options.repeat_motion_fraction` of the frames in which the body moves, and
/// at least 4; otherwise none (a still body, or a body that turns at an apex, also stops for a
/// frame). `candidates` and `moving`, when given, are set to those counts.
std::vector<bool> RepeatsFromMotion(const std::vector<std::optional<Eigen::Vector2d>>& p,
                                    const FrameTimingOptions& options, int* candidates = nullptr,
                                    int* moving = nullptr);

/// How AddRepeatsFromMotion decided.
struct MotionRepeats {
  int candidates = 0;  ///< frames in which the body stands still for a frame while it moves
  int moving = 0;      ///< frames in which it moves
  int taken = 0;       ///< RepeatsFromMotion's repeats
  int shown = 0;       ///< of those, the ones the images found too
  int added = 0;       ///< repeats added to the images'
  bool used = false;   ///< the motion's repeats were added
};

/// Adds RepeatsFromMotion's repeats to `repeat` (the images', FindRepeats) where the images
/// found fewer than half of them; where they found most, they found the copies, and the rest are
/// the body turning at an apex, so the images decide. `p` as in RepeatsFromMotion, one per frame
/// of `repeat` (shorter: not found).
MotionRepeats AddRepeatsFromMotion(const std::vector<std::optional<Eigen::Vector2d>>& p,
                                   const FrameTimingOptions& options, std::vector<bool>& repeat);

/// Which frame of a run of repeated images shows it at its own capture time: the first (a
/// frame grabber re-sending its last buffer: the copies come late) or the last (a frame-rate
/// conversion that shows a capture early, in place of one it left out, and then again).
enum class HeldImage { kFirst, kLast };

/// How HeldImageFromMotion decided.
struct HeldImageEvidence {
  HeldImage held = HeldImage::kFirst;
  int runs = 0;  ///< single repeats with a moving sample before and after, the evidence
  /// The median over those runs of log2(step out / step in), where the step in is from the
  /// sample before the image to it and the step out from it to the sample after its copy: +1
  /// when the copy comes late (the step out spans two periods), -1 when the image is early.
  double log2_step_ratio = 0.0;
};

/// Decides HeldImage from the motion `p` (per frame, nullopt where not found) at the repeats
/// `repeat` (FindRepeats): kLast where at least 3 runs give a median log2 ratio below -0.5,
/// kFirst otherwise (the copy late, the model of a camera that re-sends its buffer).
HeldImageEvidence HeldImageFromMotion(const std::vector<std::optional<Eigen::Vector2d>>& p,
                                      const std::vector<bool>& repeat);

/// `repeat` with each run's sample moved to its last frame: the frame before a run becomes a
/// repeat (its image is shown again in time), the run's last frame the sample. The clip's last
/// frame, unless it is a copy, is no sample either: it may be shown early, its copy cut off.
std::vector<bool> SampleAtLastCopy(const std::vector<bool>& repeat);

/// The timing of a clip.
struct FrameTiming {
  TimingSource source = TimingSource::kFrameIndex;
  double fps = 0.0;
  std::vector<int> slot;    ///< per frame: its capture slot (slot 0 is frame 0's)
  std::vector<double> t_s;  ///< per frame: slot / fps (s)
  /// The s.d. of a sample's capture time about t_s (s): 0 for a camera with a fixed period.
  /// A clip that holds its images (a screen recording, which shows each image until the next
  /// one comes: at least a quarter of its frames repeat, each at its first copy) shows an image
  /// first at some time in the frame period after its capture: 1 / (fps sqrt(12)). A camera
  /// that re-sends its buffer in place of a lost capture loses far fewer captures than that.
  double capture_time_sd_s = 0.0;
  /// per frame: it is a copy of an image that another frame shows at its capture time (not a
  /// sample): the later copies, or where `held` is kLast the earlier ones
  std::vector<bool> repeat;
  std::vector<int> repeated_frames;    ///< indices of the frames `repeat` marks
  HeldImage held = HeldImage::kFirst;  ///< which copy of a repeated image is the sample
  std::vector<int> dropped_captures;   ///< slots no frame of the file holds (not repeats)
  ImageDifferences differences;        ///< empty when the images were not compared
  std::vector<std::string> notes;      ///< how it was decided, for people

  int frame_count() const { return static_cast<int>(slot.size()); }
};

/// Capture slots from per-frame time stamps (s after frame 0): round(t fps). nullopt when the
/// stamps do not increase strictly (they cannot be slots of one clock).
std::optional<std::vector<int>> SlotsFromStamps(const std::vector<double>& stamps_s, double fps);

/// Capture slots from the motion: `p` is a point of the body per frame (any unit, e.g. px;
/// nullopt where it was not found), `repeat` the repeated frames (not samples, but each takes
/// a slot), `down` the direction of gravity in p's frame. The clip is cut into free flights at
/// the impacts (deep minima of the height along -down); in each flight of 5 or more samples,
/// dropped captures are added one at a time, where one lowers the residual of a parabola in
/// the slot (per coordinate) the most, while it does so by more than drop_significance times the
/// noise variance (from the flight's third differences, at least position_noise_floor_px^2);
/// a drop placed may then move to another gap that explains the track better. A drop across
/// an impact, or before the first or after the last sample, cannot be seen this way.
std::vector<int> SlotsFromMotion(const std::vector<std::optional<Eigen::Vector2d>>& p,
                                 const std::vector<bool>& repeat, const Eigen::Vector2d& down,
                                 const FrameTimingOptions& options);

/// The whole analysis: repeats from the images of `source` (read once more), which copy of each
/// is the sample from the motion `p` (HeldImageFromMotion), slots from
/// `stamps_s` when given (one per frame), else from the motion `p` (as SlotsFromMotion) when
/// options.drops_from_motion, else frame i at slot i.
FrameTiming AnalyzeFrameTiming(FrameSource& source, double fps,
                               const std::optional<std::vector<double>>& stamps_s,
                               const std::vector<std::optional<Eigen::Vector2d>>& p,
                               const Eigen::Vector2d& down, const FrameTimingOptions& options);

/// Every frame a new capture at index / fps (the analysis switched off).
FrameTiming UniformTiming(int frame_count, double fps);

/// The per-frame time stamps of `source` (a camera file that records them, CINE, or a range of
/// one), nullopt otherwise.
std::optional<std::vector<double>> TimeStamps(const FrameSource& source);

}  // namespace hoof::tracking
