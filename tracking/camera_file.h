#pragma once
/// @file
/// Camera files, streamed frame by frame: Photron MRAW (with its .cihx or .cih header), Phantom
/// CINE and multi-page TIFF (docs/camera-files.md). A source holds one frame buffer and seeks to
/// the frame asked for, so memory does not grow with the clip. Values are returned as recorded:
/// CV_8U for 8-bit data, CV_16U otherwise (12-bit data gives 0..4095, not rescaled). Errors throw
/// std::runtime_error naming the file and, where it applies, the frame.

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <opencv2/core.hpp>

#include "tracking/frame_source.h"

namespace hoof::tracking {

/// What a camera file's header says about its frames.
struct CameraFileInfo {
  std::string format;  ///< "photron-mraw", "phantom-cine", "tiff"
  int width = 0, height = 0, frame_count = 0;
  int bit_depth = 0;     ///< significant bits as recorded (8, 10, 12, 14, 16)
  int storage_bits = 0;  ///< bits each pixel takes in the file (8, 12 packed, 16)
  /// Frames per second of the file (a CINE saved with decimation: the recording rate over the
  /// decimation); NaN where the file does not record it (most TIFF).
  double fps = std::numeric_limits<double>::quiet_NaN();
  double recording_fps = std::numeric_limits<double>::quiet_NaN();  ///< the camera's own rate
  int decimation = 1;  ///< frames recorded per frame saved (CINE, from its time stamps)
  std::optional<double> shutter_s;
  /// Number of frame 0 relative to the trigger (the trigger frame is 0; Photron's start frame,
  /// CINE's first image number); 0 where not recorded.
  std::int64_t first_frame_number = 0;
  /// Time of the trigger in seconds after frame 0 (negative: frame 0 came after it).
  std::optional<double> trigger_time_s;
  std::string camera;  ///< camera model where recorded
  std::string header;  ///< the file the facts above come from (.cihx, .cih, or the file)
  std::string data;    ///< the file the pixels come from
};

/// A camera file as a FrameSource.
class CameraFileSource : public FrameSource {
 public:
  virtual const CameraFileInfo& info() const = 0;
};

/// True for the extensions of camera files: .mraw .cih .cihx .cine .tif .tiff (any case).
bool IsCameraFile(const std::filesystem::path& path);

/// Opens a camera file by its extension. An .mraw finds its header beside it (same stem, .cihx
/// or .cih); a .cihx or .cih finds the .mraw. Throws std::runtime_error naming the file.
std::unique_ptr<CameraFileSource> OpenCameraFile(const std::filesystem::path& path);

/// Frames [first, first + count) of another source, renumbered from 0, with their time stamps
/// (if the source has them) counted from the range's first frame. Throws std::invalid_argument
/// when the range does not lie within the source.
class FrameRangeSource : public FrameSource {
 public:
  FrameRangeSource(std::unique_ptr<FrameSource> source, int first, int count);
  int count() const override { return count_; }
  cv::Mat Read(int index) override;
  cv::Mat ReadColour(int index) override;
  std::string Describe(int index) const override;
  std::optional<double> TimeOf(int index) const override;

 private:
  std::unique_ptr<FrameSource> source_;
  int first_;
  int count_;
};

// --- Headers, parsed from bytes (exposed for tests and the fuzzers) --------------------------

/// The facts of a Photron .cihx (XML) or .cih ("Key : Value" lines) header.
struct PhotronHeader {
  int width = 0, height = 0, frame_count = 0;
  int color_bit = 0;      ///< bits per pixel in the .mraw: 8, 12 (packed) or 16
  int effective_bit = 0;  ///< significant bits (the header's effective bit depth; else color_bit)
  double fps = std::numeric_limits<double>::quiet_NaN();
  std::optional<double> shutter_s;
  std::optional<std::int64_t> start_frame;
  std::string file_format;  ///< "Mraw" for an .mraw; other values name image sequences
  std::string color_type;   ///< "Mono", "Raw", "Color", ...
  std::string camera;
};

/// Parses a Photron header's text (XML if it holds "<cih>", else "Key : Value" lines). `name`
/// names the file in messages. Throws std::runtime_error naming it and the missing or bad field.
PhotronHeader ParsePhotronHeader(std::string_view text, const std::string& name);

/// Reads `size` bytes at `offset` into `out`; false when the file ends first.
using ReadAt = std::function<bool(std::uint64_t offset, std::size_t size, void* out)>;

/// What a CINE file's headers say, and where its images are.
struct CineLayout {
  CameraFileInfo info;
  int stride = 0;                      ///< bytes per stored row
  int packing = 0;                     ///< 0: 8-bit, 1: 16-bit little-endian, 2: 12-bit packed
  bool bottom_up = true;               ///< rows stored bottom first
  std::vector<std::uint64_t> offsets;  ///< file offset of each image's annotation
  std::vector<double> times_s;         ///< per-image time stamps after image 0 (empty if none)
};

/// Parses the CINE headers of a file of `file_size` bytes read through `read`. Throws
/// std::runtime_error naming `name` for a wrong magic, a layout it cannot read, offsets past
/// the end; allocations are bounded by the file size.
CineLayout ParseCineLayout(const ReadAt& read, std::uint64_t file_size, const std::string& name);

// --- Writers ----------------------------------------------------------------------------------

/// What a writer records.
struct CameraFileSpec {
  int width = 0, height = 0, frame_count = 0;
  int bits = 16;           ///< MRAW: 8, 12 (packed) or 16; CINE: 8 or 16
  int effective_bits = 0;  ///< significant bits written in the header (0: `bits`)
  double fps = 0;
  std::optional<double> shutter_s;
  std::int64_t first_frame_number = 0;  ///< MRAW start frame, CINE first image number
  std::string camera = "hoofimpact";
  /// CINE: per-frame time stamps in seconds after frame 0 (empty: none written).
  std::vector<double> times_s;
};

/// Writes a Photron .mraw and its .cihx (same stem) frame by frame. Both are written to
/// temporary files beside them and renamed by Finish(); a writer destroyed before Finish()
/// removes them.
class MrawWriter {
 public:
  /// `mraw` ends in .mraw. Throws std::invalid_argument for a bad spec.
  MrawWriter(std::filesystem::path mraw, CameraFileSpec spec);
  ~MrawWriter();
  MrawWriter(const MrawWriter&) = delete;
  MrawWriter& operator=(const MrawWriter&) = delete;
  /// Appends one frame: one channel, width x height, CV_8U for 8 bits else CV_16U with values
  /// below 2^bits.
  void Write(const cv::Mat& frame);
  /// Writes the header, checks the frame count, renames both files into place.
  void Finish();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Writes a Phantom .cine (8- or 16-bit, uncompressed, with per-image time stamps when the spec
/// has them) frame by frame, to a temporary file renamed by Finish().
class CineWriter {
 public:
  CineWriter(std::filesystem::path cine, CameraFileSpec spec);
  ~CineWriter();
  CineWriter(const CineWriter&) = delete;
  CineWriter& operator=(const CineWriter&) = delete;
  void Write(const cv::Mat& frame);
  void Finish();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hoof::tracking
