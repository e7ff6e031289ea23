#pragma once
/// @file
/// The frame-timing image comparison (tracking/frame_timing.h, DifferenceFrames) done while a
/// tracker reads the clip, so that `track` reads a camera file once, not twice: a FrameSource
/// that hands every frame on unchanged and, for the frames read in order from frame 0,
/// compares each with the one before (docs/tracking.md, "Frame timing").

#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "tracking/frame_source.h"
#include "tracking/frame_timing.h"

namespace hoof::tracking {

/// Compares each frame with the one before as the frames are given to it, in order (what
/// DifferenceFrames does for a whole source; DifferenceFrames uses it).
class FrameDifferencer {
 public:
  /// `max_grid_pixels` as in DifferenceFrames; >= 1.
  explicit FrameDifferencer(int max_grid_pixels = 16384);
  /// Frame `frames_added()` of the clip. Throws std::runtime_error naming `what` when its size
  /// differs from the frame before, or its depth is not 8/16-bit or float.
  void Add(const cv::Mat& image, const std::string& what);
  int frames_added() const { return frames_; }
  /// The differences of the `frames_added()` frames, and the clip's noise-only difference.
  ImageDifferences Finish() const;

 private:
  int max_grid_pixels_;
  int step_ = 1;
  int frames_ = 0;
  std::vector<double> previous_, grid_, some_,
      scratch_;  // grid samples; reused from frame to frame
  ImageDifferences d_;
};

/// A FrameSource passing another's frames through, comparing each with the one before while
/// the frames are read in order from frame 0 (a tracker's pass). A read out of that order
/// (frame 0 again for the surface check, a re-read) is passed through and not compared.
/// Read may be called from another thread than the one calling Differences (a tracker's
/// read-ahead reader), one call at a time.
class DifferencingSource : public FrameSource {
 public:
  /// With `compare` false the frames only pass through (Differences gives nullopt).
  DifferencingSource(FrameSource& inner, int max_grid_pixels, bool compare = true);
  int count() const override { return inner_.count(); }
  cv::Mat Read(int index) override;
  /// The inner source's colour frame; compared (as grey) like Read's.
  cv::Mat ReadColour(int index) override;
  std::string Describe(int index) const override { return inner_.Describe(index); }
  std::optional<double> TimeOf(int index) const override { return inner_.TimeOf(index); }
  /// The comparison of every frame of the clip when each was read in order, else nullopt (then
  /// DifferenceFrames reads the clip again).
  std::optional<ImageDifferences> Differences() const;

 private:
  FrameSource& inner_;
  bool compare_;
  mutable std::mutex mutex_;
  FrameDifferencer differencer_;
};

/// AnalyzeFrameTiming with the images' comparison already made (`differences`, one entry per
/// frame of the clip): the same result without reading the clip.
FrameTiming AnalyzeFrameTiming(const ImageDifferences& differences, double fps,
                               const std::optional<std::vector<double>>& stamps_s,
                               const std::vector<std::optional<Eigen::Vector2d>>& p,
                               const Eigen::Vector2d& down, const FrameTimingOptions& options);

}  // namespace hoof::tracking
