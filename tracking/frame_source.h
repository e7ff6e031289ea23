#pragma once
/// @file
/// Frame sources: image sequences (8- or 16-bit, grey or colour, any format OpenCV reads) and
/// video files. Frames stream one at a time, so memory does not grow with the sequence length.
/// Camera files (Photron MRAW, Phantom CINE, multi-page TIFF) are sources too:
/// tracking/camera_file.h.

#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>

#include <opencv2/core.hpp>

namespace cv {
class VideoCapture;
}

namespace hoof::tracking {

/// A sequence of frames. Read() gives a single-channel image in the file's own depth (8-bit,
/// 16-bit or float); colour is converted to grey. Detection converts only the windows it looks
/// at to [0, 1] floats (ToUnitFloat), so full frames are never copied as floats. Errors throw
/// std::runtime_error naming the file and the frame.
class FrameSource {
 public:
  virtual ~FrameSource() = default;
  /// Number of frames.
  virtual int count() const = 0;
  /// Frame `index` (0-based within the sequence). Video sources read forward; reading an
  /// earlier frame reopens the file.
  virtual cv::Mat Read(int index) = 0;
  /// Frame `index` as decoded, before the conversion to grey: 8-bit BGR for a video, the file's
  /// own channels and depth for an image. Sources without colour give Read's image. Finding a
  /// body by its motion and colour (tracking/motion_blobs.h) reads this.
  virtual cv::Mat ReadColour(int index) { return Read(index); }
  /// Where frame `index` comes from, for messages ("frames/000012.png", "clip.avi frame 12").
  virtual std::string Describe(int index) const = 0;
  /// Recorded time of frame `index` in seconds after frame 0, where the source has per-frame
  /// time stamps (a CINE file, or a range of one); nullopt otherwise.
  virtual std::optional<double> TimeOf(int index) const {
    (void)index;
    return std::nullopt;
  }
};

/// Frame rates accepted (frames per second), from a camera file's header or a trial.json: from
/// one frame in 1000 s (time-lapse) to 10^9 (beyond the fastest camera). A rate outside, such
/// as a vanishing one that a CINE header's decimation divides to nothing, would make the times
/// of the frames infinite.
inline constexpr double kMinFps = 1e-3, kMaxFps = 1e9;

/// Why a frame rate is refused ("1e-06 fps is not within 0.001 to 1e+09"), or nothing when it
/// lies within kMinFps to kMaxFps.
std::optional<std::string> FpsOutOfRange(double fps);

/// Longest frame file pattern accepted (characters).
inline constexpr std::size_t kMaxFramePatternLength = 4096;

/// True when `pattern` holds exactly one integer conversion (%d, %6d or %06d, width at most two
/// digits) and otherwise only literal text and %%, and is at most kMaxFramePatternLength long.
bool IsFramePattern(const std::string& pattern);

/// Image files named by a printf pattern, e.g. "frames/%06d.png" with first = 0.
class ImageSequenceSource : public FrameSource {
 public:
  /// `pattern` is relative to `dir` (or absolute). Throws std::invalid_argument for a pattern
  /// without exactly one integer conversion, or count < 1.
  ImageSequenceSource(std::filesystem::path dir, std::string pattern, int first, int count);
  int count() const override { return count_; }
  cv::Mat Read(int index) override;
  cv::Mat ReadColour(int index) override;
  std::string Describe(int index) const override;
  /// Path of frame `index`.
  std::filesystem::path PathOf(int index) const;

 private:
  std::filesystem::path dir_;
  std::string pattern_;
  int first_;
  int count_;
};

/// What a video container records of its frames, as OpenCV's FFmpeg backend reads it.
struct VideoInfo {
  /// The container's frame rate (CAP_PROP_FPS): the rate it plays at, which a slow-motion file
  /// records instead of its capture rate (a phone stores 240 captures a second at 30 fps); NaN
  /// where the container records none.
  double fps = std::numeric_limits<double>::quiet_NaN();
  /// The display rotation tag (CAP_PROP_ORIENTATION_META), clockwise degrees in [0, 360): a
  /// phone held sideways stores its frames sideways and tags them. 0 without a tag.
  int rotation_deg = 0;
  /// The frames are delivered turned by the tag (CAP_PROP_ORIENTATION_AUTO), so that they look
  /// as a player shows them; width and height are the delivered frames'.
  bool rotation_applied = false;
  int width = 0, height = 0;
  std::string codec;  ///< the stream's FOURCC ("avc1", "MJPG", ...), "" where unknown
};

/// A video file read through cv::VideoCapture, its frames turned upright by its rotation tag.
class VideoSource : public FrameSource {
 public:
  /// Throws std::runtime_error naming the file when it cannot be opened, holds no frames, or
  /// carries a rotation tag that is not a multiple of 90 degrees (no upright frame exists).
  explicit VideoSource(std::filesystem::path path);
  ~VideoSource() override;
  int count() const override { return count_; }
  cv::Mat Read(int index) override;
  cv::Mat ReadColour(int index) override;
  std::string Describe(int index) const override;
  const VideoInfo& info() const { return info_; }

 private:
  void Open();
  std::filesystem::path path_;
  std::unique_ptr<cv::VideoCapture> capture_;
  VideoInfo info_;
  int next_ = 0;
  int count_ = 0;
};

/// Converts any OpenCV image (8/16-bit or float, 1/3/4 channels) to one channel in its own
/// depth. Throws std::runtime_error mentioning `what` for an empty or unsupported image.
cv::Mat ToGrey(const cv::Mat& image, const std::string& what);

/// A single-channel image (or window) as CV_32F in [0, 1]: 8-bit / 255, 16-bit / 65535.
cv::Mat ToUnitFloat(const cv::Mat& grey);

}  // namespace hoof::tracking
