#pragma once
/// @file
/// What the camera file readers and writers share (not part of the module's interface).

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "tracking/camera_file.h"

namespace hoof::tracking::detail {

/// Largest frame accepted (pixels), as for image files (OpenCV's limit).
inline constexpr std::int64_t kMaxFramePixels = std::int64_t{1} << 30;
/// Largest width or height accepted.
inline constexpr int kMaxSide = 1 << 16;
/// How pixels are stored.
enum class Packing {
  k8,          ///< one byte per pixel
  k16Le,       ///< two bytes, little-endian
  k12PackedBe  ///< two pixels in three bytes, most significant bits first
};

/// Bytes of `pixels` pixels stored with `packing` (pixels is even for 12-bit packing).
std::int64_t PackedBytes(std::int64_t pixels, Packing packing);

/// Unpacks one row of `width` pixels from `in` into `out` (CV_8U row for k8, CV_16U otherwise).
void UnpackRow(const std::uint8_t* in, int width, Packing packing, void* out);

/// Packs one row (the inverse of UnpackRow).
void PackRow(const void* in, int width, Packing packing, std::uint8_t* out);

/// A file opened for reading at offsets (pread); closed on destruction.
class InputFile {
 public:
  /// Throws std::runtime_error naming the file when it cannot be opened.
  explicit InputFile(std::filesystem::path path);
  ~InputFile();
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;
  std::uint64_t size() const { return size_; }
  /// False when the file ends before `size` bytes.
  bool ReadAt(std::uint64_t offset, std::size_t size, void* out) const;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  int fd_ = -1;
  std::uint64_t size_ = 0;
};

/// A file written to `<path>.tmp-<pid>` and renamed onto `path` by Commit(); removed on
/// destruction when not committed. (The io module's atomic_file.h does the same; tracking does
/// not depend on io.)
class OutputFile {
 public:
  explicit OutputFile(std::filesystem::path path);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  void Write(const void* data, std::size_t size);
  void WriteAt(std::uint64_t offset, const void* data, std::size_t size);
  /// Flushes and closes; the file stays under its temporary name until Rename().
  void Close();
  void Rename();
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_, tmp_;
  std::FILE* file_ = nullptr;
  bool renamed_ = false;
};

/// A frame source over raw pixels at known offsets: the MRAW and CINE readers. Holds one frame
/// buffer, reused when the caller no longer holds the frame last returned.
class RawFrameSource : public CameraFileSource {
 public:
  RawFrameSource(std::unique_ptr<InputFile> file, CameraFileInfo info, Packing packing, int stride,
                 bool bottom_up);
  int count() const override { return info_.frame_count; }
  cv::Mat Read(int index) override;
  std::string Describe(int index) const override;
  const CameraFileInfo& info() const override { return info_; }

 protected:
  /// Offset of frame `index`'s first stored row (its pixels are stride x height bytes).
  virtual std::uint64_t PixelOffset(int index) = 0;
  const InputFile& file() const { return *file_; }

 private:
  std::unique_ptr<InputFile> file_;
  CameraFileInfo info_;
  Packing packing_;
  int stride_;
  bool bottom_up_;
  cv::Mat frame_;                    ///< the one frame buffer
  std::vector<std::uint8_t> bytes_;  ///< one frame's stored bytes (packed data only)
};

std::unique_ptr<CameraFileSource> OpenMraw(const std::filesystem::path& path);
std::unique_ptr<CameraFileSource> OpenCine(const std::filesystem::path& path);
std::unique_ptr<CameraFileSource> OpenTiff(const std::filesystem::path& path);

/// Lower-case extension with its dot (".mraw").
std::string LowerExtension(const std::filesystem::path& path);

}  // namespace hoof::tracking::detail
