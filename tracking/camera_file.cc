#include "tracking/camera_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "tracking/camera_file_internal.h"

namespace hoof::tracking {
namespace detail {

namespace fs = std::filesystem;

std::string LowerExtension(const fs::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

std::int64_t PackedBytes(std::int64_t pixels, Packing packing) {
  switch (packing) {
    case Packing::k8:
      return pixels;
    case Packing::k16Le:
      return 2 * pixels;
    case Packing::k12PackedBe:
      return pixels / 2 * 3;
  }
  return 0;
}

void UnpackRow(const std::uint8_t* in, int width, Packing packing, void* out) {
  switch (packing) {
    case Packing::k8:
      std::memcpy(out, in, static_cast<std::size_t>(width));
      return;
    case Packing::k16Le: {
      auto* o = static_cast<std::uint16_t*>(out);
      if constexpr (std::endian::native == std::endian::little) {
        std::memcpy(o, in, 2 * static_cast<std::size_t>(width));
      } else {
        for (int x = 0; x < width; ++x)
          o[x] = static_cast<std::uint16_t>(in[2 * x] | (in[2 * x + 1] << 8));
      }
      return;
    }
    case Packing::k12PackedBe: {
      // Bytes a b c hold two pixels: aaaaaaaa bbbb | bbbb cccccccc. Four pixels (six bytes)
      // at a time from one 8-byte big-endian load while two more bytes lie within the row.
      auto* o = static_cast<std::uint16_t*>(out);
      const int pairs = width / 2;
      int k = 0;
      for (; 3 * k + 8 <= 3 * pairs; k += 2, in += 6, o += 4) {
        std::uint64_t v;
        std::memcpy(&v, in, 8);
        if constexpr (std::endian::native == std::endian::little) v = __builtin_bswap64(v);
        o[0] = static_cast<std::uint16_t>(v >> 52);
        o[1] = static_cast<std::uint16_t>((v >> 40) & 0xfff);
        o[2] = static_cast<std::uint16_t>((v >> 28) & 0xfff);
        o[3] = static_cast<std::uint16_t>((v >> 16) & 0xfff);
      }
      o -= 2 * k;
      for (; k < pairs; ++k, in += 3) {
        o[2 * k] = static_cast<std::uint16_t>((in[0] << 4) | (in[1] >> 4));
        o[2 * k + 1] = static_cast<std::uint16_t>(((in[1] & 0x0f) << 8) | in[2]);
      }
      return;
    }
  }
}

void PackRow(const void* in, int width, Packing packing, std::uint8_t* out) {
  switch (packing) {
    case Packing::k8:
      std::memcpy(out, in, static_cast<std::size_t>(width));
      return;
    case Packing::k16Le: {
      const auto* v = static_cast<const std::uint16_t*>(in);
      for (int x = 0; x < width; ++x) {
        out[2 * x] = static_cast<std::uint8_t>(v[x] & 0xff);
        out[2 * x + 1] = static_cast<std::uint8_t>(v[x] >> 8);
      }
      return;
    }
    case Packing::k12PackedBe: {
      const auto* v = static_cast<const std::uint16_t*>(in);
      for (int k = 0; k < width / 2; ++k, out += 3) {
        const unsigned p0 = v[2 * k] & 0xfffu, p1 = v[2 * k + 1] & 0xfffu;
        out[0] = static_cast<std::uint8_t>(p0 >> 4);
        out[1] = static_cast<std::uint8_t>(((p0 & 0x0fu) << 4) | (p1 >> 8));
        out[2] = static_cast<std::uint8_t>(p1 & 0xffu);
      }
      return;
    }
  }
}

InputFile::InputFile(fs::path path) : path_(std::move(path)) {
  fd_ = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0)
    throw std::runtime_error(path_.string() +
                             ": cannot be opened: " + std::system_category().message(errno));
  struct stat st {};
  if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd_);
    fd_ = -1;
    throw std::runtime_error(path_.string() + ": is not a regular file");
  }
  size_ = static_cast<std::uint64_t>(st.st_size);
}

InputFile::~InputFile() {
  if (fd_ >= 0) ::close(fd_);
}

bool InputFile::ReadAt(std::uint64_t offset, std::size_t size, void* out) const {
  if (offset > size_ || size > size_ - offset) return false;
  auto* p = static_cast<char*>(out);
  while (size > 0) {
    const ssize_t n = ::pread(fd_, p, size, static_cast<off_t>(offset));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n;
    size -= static_cast<std::size_t>(n);
    offset += static_cast<std::uint64_t>(n);
  }
  return true;
}

OutputFile::OutputFile(fs::path path) : path_(std::move(path)) {
  tmp_ = path_;
  tmp_ += ".tmp-" + std::to_string(::getpid());
  file_ = std::fopen(tmp_.c_str(), "w+b");
  if (!file_)
    throw std::runtime_error(tmp_.string() +
                             ": cannot be written: " + std::system_category().message(errno));
}

OutputFile::~OutputFile() {
  if (file_) std::fclose(file_);
  if (!renamed_) {
    std::error_code ec;
    fs::remove(tmp_, ec);
  }
}

void OutputFile::Write(const void* data, std::size_t size) {
  if (!file_ || std::fwrite(data, 1, size, file_) != size)
    throw std::runtime_error(tmp_.string() + ": write failed (disk full?)");
}

void OutputFile::WriteAt(std::uint64_t offset, const void* data, std::size_t size) {
  if (!file_ || ::fseeko(file_, static_cast<off_t>(offset), SEEK_SET) != 0)
    throw std::runtime_error(tmp_.string() + ": seek failed");
  Write(data, size);
  if (::fseeko(file_, 0, SEEK_END) != 0) throw std::runtime_error(tmp_.string() + ": seek failed");
}

void OutputFile::Close() {
  if (!file_) return;
  const bool ok = std::fflush(file_) == 0 && ::fsync(::fileno(file_)) == 0;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!ok || !closed) throw std::runtime_error(tmp_.string() + ": write failed (disk full?)");
}

void OutputFile::Rename() {
  Close();
  std::error_code ec;
  fs::rename(tmp_, path_, ec);
  if (ec)
    throw std::runtime_error(path_.string() + ": cannot be written (rename from " + tmp_.string() +
                             "): " + ec.message());
  renamed_ = true;
}

RawFrameSource::RawFrameSource(std::unique_ptr<InputFile> file, CameraFileInfo info,
                               Packing packing, int stride, bool bottom_up)
    : file_(std::move(file)),
      info_(std::move(info)),
      packing_(packing),
      stride_(stride),
      bottom_up_(bottom_up) {}

std::string RawFrameSource::Describe(int index) const {
  return file_->path().string() + " frame " + std::to_string(index);
}

cv::Mat RawFrameSource::Read(int index) {
  if (index < 0 || index >= info_.frame_count)
    throw std::out_of_range(file_->path().string() + ": frame " + std::to_string(index) +
                            " is outside the clip (" + std::to_string(info_.frame_count) +
                            " frames)");
  const std::uint64_t at = PixelOffset(index);
  const int w = info_.width, h = info_.height;
  // The one frame buffer: reused unless the caller still holds the frame returned last.
  if (!frame_.empty() && frame_.u != nullptr && frame_.u->refcount > 1) frame_.release();
  frame_.create(h, w, packing_ == Packing::k8 ? CV_8U : CV_16U);
  const std::size_t bytes = static_cast<std::size_t>(stride_) * static_cast<std::size_t>(h);
  const auto cut_short = [&] {
    return std::runtime_error(file_->path().string() + ": frame " + std::to_string(index) +
                              " is cut short (the file ends inside it)");
  };
  const bool direct = !bottom_up_ && packing_ != Packing::k12PackedBe &&
                      static_cast<std::size_t>(stride_) == frame_.step[0] &&
                      (packing_ == Packing::k8 || std::endian::native == std::endian::little);
  if (direct) {
    if (!file_->ReadAt(at, bytes, frame_.data)) throw cut_short();
    return frame_;
  }
  bytes_.resize(bytes);
  if (!file_->ReadAt(at, bytes, bytes_.data())) throw cut_short();
  for (int y = 0; y < h; ++y) {
    const int stored = bottom_up_ ? h - 1 - y : y;
    UnpackRow(bytes_.data() + static_cast<std::size_t>(stored) * static_cast<std::size_t>(stride_),
              w, packing_, frame_.ptr(y));
  }
  return frame_;
}

}  // namespace detail

bool IsCameraFile(const std::filesystem::path& path) {
  const std::string ext = detail::LowerExtension(path);
  return ext == ".mraw" || ext == ".cih" || ext == ".cihx" || ext == ".cine" || ext == ".tif" ||
         ext == ".tiff";
}

std::unique_ptr<CameraFileSource> OpenCameraFile(const std::filesystem::path& path) {
  const std::string ext = detail::LowerExtension(path);
  if (ext == ".mraw" || ext == ".cih" || ext == ".cihx") return detail::OpenMraw(path);
  if (ext == ".cine") return detail::OpenCine(path);
  if (ext == ".tif" || ext == ".tiff") return detail::OpenTiff(path);
  throw std::runtime_error(path.string() +
                           ": not a camera file (expected .mraw, .cih, .cihx, .cine, .tif or "
                           ".tiff)");
}

FrameRangeSource::FrameRangeSource(std::unique_ptr<FrameSource> source, int first, int count)
    : source_(std::move(source)), first_(first), count_(count) {
  const int total = source_->count();
  if (first_ < 0 || count_ < 1 || first_ >= total || count_ > total - first_)
    throw std::invalid_argument("frames " + std::to_string(first_) + " to " +
                                std::to_string(static_cast<long long>(first_) + count_ - 1) +
                                " are not within the " + std::to_string(total) +
                                " frames of the clip");
}

cv::Mat FrameRangeSource::Read(int index) {
  if (index < 0 || index >= count_)
    throw std::out_of_range("frame " + std::to_string(index) + " is outside the range");
  return source_->Read(first_ + index);
}

cv::Mat FrameRangeSource::ReadColour(int index) {
  if (index < 0 || index >= count_)
    throw std::out_of_range("frame " + std::to_string(index) + " is outside the range");
  return source_->ReadColour(first_ + index);
}

std::string FrameRangeSource::Describe(int index) const {
  return source_->Describe(first_ + index);
}

std::optional<double> FrameRangeSource::TimeOf(int index) const {
  if (index < 0 || index >= count_) return std::nullopt;
  const auto t = source_->TimeOf(first_ + index), t0 = source_->TimeOf(first_);
  if (!t || !t0) return std::nullopt;
  return *t - *t0;
}

}  // namespace hoof::tracking
