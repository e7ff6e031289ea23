// Multi-page TIFF through libtiff, one page (directory) at a time.

#include <tiffio.h>

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

#include "tracking/camera_file.h"
#include "tracking/camera_file_internal.h"

namespace hoof::tracking {
namespace {

namespace fs = std::filesystem;

/// The layout of one page.
struct Page {
  std::uint32_t width = 0, height = 0;
  std::uint16_t bits = 0, samples = 1, planar = PLANARCONFIG_CONTIG, format = SAMPLEFORMAT_UINT;
  bool tiled = false;
  bool operator==(const Page& o) const {
    return width == o.width && height == o.height && bits == o.bits && samples == o.samples;
  }
  std::string Text() const {
    return std::to_string(width) + " x " + std::to_string(height) + ", " + std::to_string(bits) +
           " bits, " + std::to_string(samples) + (samples == 1 ? " channel" : " channels");
  }
};

class TiffSource : public CameraFileSource {
 public:
  explicit TiffSource(fs::path path) : path_(std::move(path)) {
    if (!fs::exists(path_)) throw std::runtime_error(path_.string() + ": file is missing");
    if (!fs::is_regular_file(path_))
      throw std::runtime_error(path_.string() + ": is not a regular file");
    file_size_ = fs::file_size(path_);
    TIFFOpenOptions* opts = TIFFOpenOptionsAlloc();
    TIFFOpenOptionsSetErrorHandlerExtR(opts, &TiffSource::OnError, this);
    TIFFOpenOptionsSetWarningHandlerExtR(opts, &TiffSource::OnWarning, this);
    // libtiff's own bound on a single allocation, against hostile tag values.
    TIFFOpenOptionsSetMaxSingleMemAlloc(opts, static_cast<tmsize_t>(1) << 31);
    tif_ = TIFFOpenExt(path_.c_str(), "r", opts);
    TIFFOpenOptionsFree(opts);
    if (!tif_) throw std::runtime_error(path_.string() + ": not a readable TIFF file" + Why());
    const tdir_t pages = TIFFNumberOfDirectories(tif_);
    if (pages < 1) {
      Close();
      throw std::runtime_error(path_.string() + ": holds no pages");
    }
    if (!TIFFSetDirectory(tif_, 0)) {
      const std::string why = Why();
      Close();
      throw std::runtime_error(path_.string() + ": page 0 cannot be read" + why);
    }
    try {
      first_ = Layout(0);
    } catch (...) {
      Close();
      throw;
    }
    info_.format = "tiff";
    info_.width = static_cast<int>(first_.width);
    info_.height = static_cast<int>(first_.height);
    info_.frame_count = static_cast<int>(
        std::min<tdir_t>(pages, static_cast<tdir_t>(std::numeric_limits<int>::max())));
    info_.bit_depth = first_.bits;
    info_.storage_bits = first_.bits;
    info_.camera = "";
    info_.header = path_.string();
    info_.data = path_.string();
  }
  ~TiffSource() override { Close(); }
  TiffSource(const TiffSource&) = delete;
  TiffSource& operator=(const TiffSource&) = delete;

  int count() const override { return info_.frame_count; }
  const CameraFileInfo& info() const override { return info_; }
  std::string Describe(int index) const override {
    return path_.string() + " page " + std::to_string(index);
  }

  cv::Mat Read(int index) override {
    if (index < 0 || index >= info_.frame_count)
      throw std::out_of_range(path_.string() + ": page " + std::to_string(index) +
                              " is outside the file (" + std::to_string(info_.frame_count) +
                              " pages)");
    errors_.clear();
    if (!TIFFSetDirectory(tif_, static_cast<tdir_t>(index)))
      throw std::runtime_error(Describe(index) + " (frame " + std::to_string(index) +
                               ") cannot be read" + Why());
    const Page p = Layout(index);
    if (!(p == first_))
      throw std::runtime_error(Describe(index) + " (frame " + std::to_string(index) + ") is " +
                               p.Text() + " but page 0 is " + first_.Text() +
                               ": every page must have the same size");
    const int type = CV_MAKETYPE(p.bits == 8 ? CV_8U : CV_16U, p.samples);
    if (!frame_.empty() && frame_.u != nullptr && frame_.u->refcount > 1) frame_.release();
    frame_.create(static_cast<int>(p.height), static_cast<int>(p.width), type);
    const tmsize_t line = TIFFScanlineSize(tif_);
    if (line != static_cast<tmsize_t>(frame_.step[0]))
      throw std::runtime_error(Describe(index) + ": unexpected row size");
    for (std::uint32_t y = 0; y < p.height; ++y)
      if (TIFFReadScanline(tif_, frame_.ptr(static_cast<int>(y)), y, 0) < 0)
        throw std::runtime_error(Describe(index) + " (frame " + std::to_string(index) +
                                 ") cannot be decoded at row " + std::to_string(y) + Why());
    if (p.samples == 1) return frame_;
    cv::Mat rgb = frame_;
    if (p.samples == 3 || p.samples == 4) {
      // TIFF stores RGB; ToGrey expects OpenCV's BGR order.
      cv::Mat bgr;
      cv::cvtColor(rgb, bgr, p.samples == 3 ? cv::COLOR_RGB2BGR : cv::COLOR_RGBA2BGRA);
      return ToGrey(bgr, Describe(index));
    }
    return ToGrey(rgb, Describe(index));
  }

 private:
  static int OnError(TIFF*, void* self, const char* module, const char* fmt, va_list ap) {
    char buf[512];
    std::vsnprintf(buf, sizeof buf, fmt, ap);
    auto* s = static_cast<TiffSource*>(self);
    if (s->errors_.size() < 2000)
      s->errors_ += std::string(s->errors_.empty() ? "" : "; ") + (module ? module : "") +
                    (module ? ": " : "") + buf;
    return 1;
  }
  static int OnWarning(TIFF*, void*, const char*, const char*, va_list) { return 1; }

  std::string Why() const { return errors_.empty() ? "" : " (libtiff: " + errors_ + ")"; }

  Page Layout(int index) {
    Page p;
    TIFFGetField(tif_, TIFFTAG_IMAGEWIDTH, &p.width);
    TIFFGetField(tif_, TIFFTAG_IMAGELENGTH, &p.height);
    TIFFGetFieldDefaulted(tif_, TIFFTAG_BITSPERSAMPLE, &p.bits);
    TIFFGetFieldDefaulted(tif_, TIFFTAG_SAMPLESPERPIXEL, &p.samples);
    TIFFGetFieldDefaulted(tif_, TIFFTAG_PLANARCONFIG, &p.planar);
    TIFFGetFieldDefaulted(tif_, TIFFTAG_SAMPLEFORMAT, &p.format);
    p.tiled = TIFFIsTiled(tif_) != 0;
    const std::string where = Describe(index) + " (frame " + std::to_string(index) + ")";
    if (p.width < 1 || p.height < 1 || p.width > static_cast<std::uint32_t>(detail::kMaxSide) ||
        p.height > static_cast<std::uint32_t>(detail::kMaxSide))
      throw std::runtime_error(where + ": size " + std::to_string(p.width) + " x " +
                               std::to_string(p.height) + " is not within 1 to 65536 a side");
    if (static_cast<std::int64_t>(p.width) * p.height > detail::kMaxFramePixels)
      throw std::runtime_error(where + ": has more than 2^30 pixels");
    // A frame is allocated before libtiff decodes it: a page may not claim far more than the
    // file could hold even at the best compression ratio (deflate's is about 1032:1).
    const std::uint64_t frame_bytes =
        std::uint64_t{p.width} * p.height * (p.bits / 8u) * std::max<std::uint16_t>(p.samples, 1);
    if (frame_bytes > (std::uint64_t{64} << 20) && frame_bytes / 4096 > file_size_)
      throw std::runtime_error(where + ": claims " + std::to_string(p.width) + " x " +
                               std::to_string(p.height) + " pixels, far more than its " +
                               std::to_string(file_size_) + " bytes can hold");
    if (p.bits != 8 && p.bits != 16)
      throw std::runtime_error(where + ": " + std::to_string(p.bits) +
                               " bits per sample; 8 and 16 are read");
    if (p.format != SAMPLEFORMAT_UINT)
      throw std::runtime_error(where + ": samples are not unsigned integers");
    if (p.samples != 1 && p.samples != 3 && p.samples != 4)
      throw std::runtime_error(where + ": " + std::to_string(p.samples) +
                               " samples per pixel; 1, 3 or 4 are read");
    if (p.samples > 1 && p.planar != PLANARCONFIG_CONTIG)
      throw std::runtime_error(where + ": colour planes stored separately are not read");
    if (p.tiled) throw std::runtime_error(where + ": tiled TIFF pages are not read");
    return p;
  }

  void Close() {
    if (tif_) TIFFClose(tif_);
    tif_ = nullptr;
  }

  fs::path path_;
  std::uint64_t file_size_ = 0;
  TIFF* tif_ = nullptr;
  std::string errors_;
  Page first_;
  CameraFileInfo info_;
  cv::Mat frame_;  ///< the one frame buffer
};

}  // namespace

namespace detail {

std::unique_ptr<CameraFileSource> OpenTiff(const fs::path& path) {
  return std::make_unique<TiffSource>(path);
}

}  // namespace detail
}  // namespace hoof::tracking
