// Phantom CINE (Vision Research's "cine file format", docs/camera-files.md): a 44-byte file
// header, a BITMAPINFOHEADER, the SETUP block, optional tagged blocks (per-image time stamps),
// a table of 64-bit offsets, and per image an annotation followed by its pixels.

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "tracking/camera_file.h"
#include "tracking/camera_file_internal.h"

namespace hoof::tracking {
namespace {

namespace fs = std::filesystem;
using detail::Packing;

constexpr std::uint32_t kHeaderSize = 44;
constexpr std::uint32_t kBitmapSize = 40;
constexpr std::uint16_t kSetupLength = 10412;  // the SETUP length current software writes
constexpr std::uint32_t kBiRgb = 0, kBiPacked10 = 256, kBiPacked12 = 1024;
constexpr std::uint16_t kTagTimeOnly = 1002;
constexpr double kTime64 = 4294967296.0;              // TIME64 fractions of a second: 2^32
constexpr std::uint32_t kEpochSeconds = 1000000000u;  // the writer's image 0 (2001-09-09)

// SETUP fields used (byte offsets from the start of SETUP; the block is packed to 1 byte).
constexpr std::size_t kFrameRate16 = 0, kMark = 140, kLength = 142, kImWidth = 737, kImHeight = 739,
                      kFlipV = 760, kFrameRate = 768, kShutterUs = 772, kRealBpp = 896,
                      kShutterNs = 1568, kCameraModel = 10128, kDecimation = 10388,
                      kFrameRateDouble = 10400;

template <class T>
T Get(const std::uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof v);  // the file is little-endian, as is every supported host
  return v;
}

template <class T>
void Put(std::uint8_t* p, T v) {
  std::memcpy(p, &v, sizeof v);
}

/// Seconds of a TIME64 (the two low bits of the fractions are flags, not time).
struct Time64 {
  std::uint32_t fractions = 0, seconds = 0;
  double Since(const Time64& o) const {
    return (static_cast<double>(seconds) - static_cast<double>(o.seconds)) +
           (static_cast<double>(fractions & ~3u) - static_cast<double>(o.fractions & ~3u)) /
               kTime64;
  }
};

}  // namespace

CineLayout ParseCineLayout(const ReadAt& read, std::uint64_t file_size, const std::string& name) {
  const auto fail = [&](const std::string& why) { throw std::runtime_error(name + ": " + why); };
  std::uint8_t h[kHeaderSize];
  if (file_size < kHeaderSize || !read(0, kHeaderSize, h) || h[0] != 'C' || h[1] != 'I')
    fail("not a Phantom CINE file (it does not begin with the \"CI\" file header)");
  const auto header_size = Get<std::uint16_t>(h + 2);
  const auto compression = Get<std::uint16_t>(h + 4);
  const auto first_image = Get<std::int32_t>(h + 16);
  const auto image_count = Get<std::uint32_t>(h + 20);
  const auto off_bitmap = Get<std::uint32_t>(h + 24);
  const auto off_setup = Get<std::uint32_t>(h + 28);
  const auto off_offsets = Get<std::uint32_t>(h + 32);
  const Time64 trigger{Get<std::uint32_t>(h + 36), Get<std::uint32_t>(h + 40)};
  if (header_size < kHeaderSize)
    fail("its file header says it is " + std::to_string(header_size) + " bytes, not 44");
  if (compression == 1) fail("holds JPEG-compressed images, which are not read");
  if (compression == 2) fail("holds uninterpolated colour (Bayer) images, which are not read");
  if (compression != 0) fail("has an unknown compression code " + std::to_string(compression));
  if (image_count < 1) fail("holds no images");
  if (image_count > static_cast<std::uint32_t>(std::numeric_limits<int>::max()))
    fail("says it holds " + std::to_string(image_count) + " images, more than are read");

  std::uint8_t bi[kBitmapSize];
  if (!read(off_bitmap, kBitmapSize, bi))
    fail("its image header (at byte " + std::to_string(off_bitmap) + ") lies past the end");
  const auto width = Get<std::int32_t>(bi + 4);
  const auto raw_height = Get<std::int32_t>(bi + 8);
  const auto bit_count = Get<std::uint16_t>(bi + 14);
  const auto bi_compression = Get<std::uint32_t>(bi + 16);
  const auto size_image = Get<std::uint32_t>(bi + 20);
  const std::int64_t height = raw_height < 0 ? -static_cast<std::int64_t>(raw_height) : raw_height;
  if (width < 1 || width > detail::kMaxSide || height < 1 || height > detail::kMaxSide)
    fail("image size " + std::to_string(width) + " x " + std::to_string(height) +
         " is not within 1 to 65536 pixels a side");
  if (static_cast<std::int64_t>(width) * height > detail::kMaxFramePixels)
    fail("image size has more than 2^30 pixels");

  CineLayout out;
  Packing packing = Packing::k16Le;
  int stored_bits = 16;
  if (bi_compression == kBiRgb && bit_count == 8) {
    packing = Packing::k8;
    stored_bits = 8;
  } else if (bi_compression == kBiRgb && bit_count == 16) {
    packing = Packing::k16Le;
  } else if (bi_compression == kBiPacked12) {
    packing = Packing::k12PackedBe;
    stored_bits = 12;
    if (width % 2 != 0) fail("12-bit packed images of odd width " + std::to_string(width));
  } else if (bi_compression == kBiPacked10) {
    fail(
        "holds 10-bit packed images (biCompression 256), whose codes the camera maps to "
        "12-bit values through a table the public file format does not give; save the clip "
        "as 16-bit");
  } else if (bi_compression == kBiRgb && (bit_count == 24 || bit_count == 48)) {
    fail("holds colour images (" + std::to_string(bit_count) + " bits per pixel), not grey");
  } else {
    fail("has a pixel format that is not read (biBitCount " + std::to_string(bit_count) +
         ", biCompression " + std::to_string(bi_compression) + ")");
  }
  const std::int64_t min_stride = (static_cast<std::int64_t>(width) * stored_bits + 7) / 8;
  std::int64_t stride = min_stride;
  if (size_image != 0 && size_image % height == 0 &&
      static_cast<std::int64_t>(size_image) / height >= min_stride)
    stride = static_cast<std::int64_t>(size_image) / height;  // rows padded by the writer
  if (stride > 8 * min_stride + 64) fail("image header's row size is implausible");

  // SETUP: its "ST" mark and length, then the fields that lie within that length.
  std::uint8_t mark[4];
  if (!read(static_cast<std::uint64_t>(off_setup) + kMark, 4, mark) || mark[0] != 'S' ||
      mark[1] != 'T')
    fail("its setup block (at byte " + std::to_string(off_setup) + ") lacks its \"ST\" mark");
  const auto setup_length = Get<std::uint16_t>(mark + 2);
  if (setup_length < kMark + 4) fail("its setup block is too short");
  std::vector<std::uint8_t> setup(setup_length);  // at most 65535 bytes
  if (!read(off_setup, setup.size(), setup.data()))
    fail("its setup block runs past the end of the file");
  const auto has = [&](std::size_t at, std::size_t size) { return at + size <= setup.size(); };
  double fps = Get<std::uint16_t>(setup.data() + kFrameRate16);
  if (has(kFrameRate, 4) && Get<std::uint32_t>(setup.data() + kFrameRate) > 0)
    fps = Get<std::uint32_t>(setup.data() + kFrameRate);
  if (has(kFrameRateDouble, 8)) {
    const auto d = Get<double>(setup.data() + kFrameRateDouble);
    if (std::isfinite(d) && d > 0) fps = d;
  }
  double decimation = 1;
  if (has(kDecimation, 4)) {
    const auto d = Get<float>(setup.data() + kDecimation);
    if (std::isfinite(d) && d >= 1 && d <= 1e6) decimation = d;
  }
  if (!(fps > 0)) fail("its setup block gives no frame rate");
  std::optional<double> shutter;
  if (has(kShutterNs, 4) && Get<std::uint32_t>(setup.data() + kShutterNs) > 0)
    shutter = Get<std::uint32_t>(setup.data() + kShutterNs) * 1e-9;
  else if (has(kShutterUs, 4) && Get<std::uint32_t>(setup.data() + kShutterUs) > 0)
    shutter = Get<std::uint32_t>(setup.data() + kShutterUs) * 1e-6;
  int real_bits = stored_bits;
  if (has(kRealBpp, 4)) {
    const auto r = Get<std::uint32_t>(setup.data() + kRealBpp);
    if (r >= 1 && static_cast<int>(r) <= (stored_bits == 8 ? 8 : 16))
      real_bits = static_cast<int>(r);
  }
  const bool flip_v = has(kFlipV, 4) && Get<std::int32_t>(setup.data() + kFlipV) != 0;
  std::string camera = "Phantom";
  if (has(kCameraModel, 256)) {
    const char* s = reinterpret_cast<const char*>(setup.data() + kCameraModel);
    const std::string model(s, strnlen(s, 256));
    if (!model.empty() &&
        std::all_of(model.begin(), model.end(), [](char c) { return c >= 32 && c < 127; }))
      camera = "Phantom " + model;
  }

  // The offsets table, bounded by the file before anything is allocated.
  const std::uint64_t table_bytes = 8ull * image_count;
  if (off_offsets > file_size || table_bytes > file_size - off_offsets)
    fail("its table of " + std::to_string(image_count) + " image offsets (at byte " +
         std::to_string(off_offsets) + ") runs past the end of the file (" +
         std::to_string(file_size) + " bytes)");
  std::vector<std::uint8_t> table(table_bytes);
  if (!read(off_offsets, table.size(), table.data())) fail("its offsets table cannot be read");
  out.offsets.resize(image_count);
  const std::uint64_t image_bytes = static_cast<std::uint64_t>(stride) * height;
  for (std::uint32_t i = 0; i < image_count; ++i) {
    const auto o = Get<std::int64_t>(table.data() + 8ull * i);
    if (o < 0 || static_cast<std::uint64_t>(o) > file_size ||
        image_bytes + 8 > file_size - static_cast<std::uint64_t>(o))
      fail("image " + std::to_string(i) + " (frame " + std::to_string(i) + ") lies at byte " +
           std::to_string(o) + ", past the end of the file (" + std::to_string(file_size) +
           " bytes)");
    out.offsets[i] = static_cast<std::uint64_t>(o);
  }

  // Tagged blocks between SETUP and the offsets table: per-image time stamps (tag 1002).
  std::optional<Time64> first_stamp;
  for (std::uint64_t at = static_cast<std::uint64_t>(off_setup) + setup_length;
       at + 8 <= off_offsets;) {
    std::uint8_t tag[8];
    if (!read(at, 8, tag)) break;
    const auto size = Get<std::uint32_t>(tag);
    const auto type = Get<std::uint16_t>(tag + 4);
    if (size < 8 || size > off_offsets - at) break;
    if (type == kTagTimeOnly && size - 8 >= table_bytes) {
      std::vector<std::uint8_t> stamps(table_bytes);
      if (read(at + 8, stamps.size(), stamps.data())) {
        out.times_s.resize(image_count);
        const Time64 t0{Get<std::uint32_t>(stamps.data()), Get<std::uint32_t>(stamps.data() + 4)};
        for (std::uint32_t i = 0; i < image_count; ++i)
          out.times_s[i] = Time64{Get<std::uint32_t>(stamps.data() + 8ull * i),
                                  Get<std::uint32_t>(stamps.data() + 8ull * i + 4)}
                               .Since(t0);
        first_stamp = t0;
      }
    }
    at += size;
  }

  CameraFileInfo& info = out.info;
  info.format = "phantom-cine";
  info.width = width;
  info.height = static_cast<int>(height);
  info.frame_count = static_cast<int>(image_count);
  info.bit_depth = real_bits;
  info.storage_bits = stored_bits;
  info.recording_fps = fps;
  info.decimation = static_cast<int>(std::lround(decimation));
  info.fps = fps / decimation;
  if (const auto why = FpsOutOfRange(info.fps)) {
    std::ostringstream recorded;  // what the rate of the saved images came from
    if (info.decimation != 1)
      recorded << " (recorded at " << fps << " fps, one image in " << decimation << " kept)";
    fail("its setup block's frame rate: " + *why + recorded.str());
  }
  info.shutter_s = shutter;
  info.first_frame_number = first_image;
  if (first_stamp && (trigger.seconds != 0 || trigger.fractions != 0))
    info.trigger_time_s = trigger.Since(*first_stamp);
  else
    info.trigger_time_s = -static_cast<double>(first_image) / info.fps;
  info.camera = camera;
  info.header = name;
  info.data = name;
  out.stride = static_cast<int>(stride);
  out.packing = packing == Packing::k8 ? 0 : packing == Packing::k16Le ? 1 : 2;
  // Uncompressed rows are stored bottom first (as in a Windows bitmap), packed ones top first;
  // the setup's vertical flip and a negative bitmap height each turn that over.
  out.bottom_up = (packing != Packing::k12PackedBe) != flip_v;
  if (raw_height < 0) out.bottom_up = !out.bottom_up;
  return out;
}

namespace {

class CineSource : public detail::RawFrameSource {
 public:
  CineSource(std::unique_ptr<detail::InputFile> file, CineLayout layout)
      : RawFrameSource(std::move(file), layout.info,
                       layout.packing == 0   ? Packing::k8
                       : layout.packing == 1 ? Packing::k16Le
                                             : Packing::k12PackedBe,
                       layout.stride, layout.bottom_up),
        offsets_(std::move(layout.offsets)),
        times_(std::move(layout.times_s)),
        image_bytes_(static_cast<std::uint64_t>(layout.stride) * layout.info.height) {}

  std::optional<double> TimeOf(int index) const override {
    if (index < 0 || static_cast<std::size_t>(index) >= times_.size()) return std::nullopt;
    return times_[static_cast<std::size_t>(index)];
  }

 protected:
  std::uint64_t PixelOffset(int index) override {
    // Each image: its annotation size (which counts itself and the image size after it), the
    // annotation, the image size, the pixels.
    const std::uint64_t at = offsets_[static_cast<std::size_t>(index)];
    std::uint32_t annotation = 0;
    if (!file().ReadAt(at, 4, &annotation))
      throw std::runtime_error(Describe(index) + ": its image header lies past the end");
    if (annotation < 8 || annotation > file().size() - at ||
        image_bytes_ > file().size() - at - annotation)
      throw std::runtime_error(file().path().string() + ": frame " + std::to_string(index) +
                               " has an annotation of " + std::to_string(annotation) +
                               " bytes that leaves no room for its pixels (cut short?)");
    return at + annotation;
  }

 private:
  std::vector<std::uint64_t> offsets_;
  std::vector<double> times_;
  std::uint64_t image_bytes_;
};

}  // namespace

namespace detail {

std::unique_ptr<CameraFileSource> OpenCine(const fs::path& path) {
  if (!fs::exists(path)) throw std::runtime_error(path.string() + ": file is missing");
  auto file = std::make_unique<InputFile>(path);
  const InputFile& f = *file;
  CineLayout layout = ParseCineLayout([&f](std::uint64_t offset, std::size_t size,
                                           void* out) { return f.ReadAt(offset, size, out); },
                                      f.size(), path.string());
  return std::make_unique<CineSource>(std::move(file), std::move(layout));
}

}  // namespace detail

// --- Writer -------------------------------------------------------------------------------------

struct CineWriter::Impl {
  Impl(fs::path c, CameraFileSpec s) : cine(std::move(c)), spec(std::move(s)), out(cine) {}
  fs::path cine;
  CameraFileSpec spec;
  detail::OutputFile out;
  Packing packing = Packing::k16Le;
  std::uint64_t table_at = 0;
  std::uint64_t next_at = 0;  ///< where the next image goes
  std::vector<std::uint64_t> offsets;
  std::vector<std::uint8_t> row;
};

CineWriter::CineWriter(fs::path cine, CameraFileSpec spec) {
  const std::string what = cine.string();
  if (spec.width < 1 || spec.height < 1 || spec.width > detail::kMaxSide ||
      spec.height > detail::kMaxSide)
    throw std::invalid_argument(what + ": image size must be 1 to 65536 pixels a side");
  if (spec.bits != 8 && spec.bits != 12 && spec.bits != 16)
    throw std::invalid_argument(what + ": cannot write " + std::to_string(spec.bits) +
                                "-bit CINE images");
  if (spec.bits == 12 && spec.width % 2 != 0)
    throw std::invalid_argument(what + ": 12-bit packed rows need an even width");
  if (spec.frame_count < 1) throw std::invalid_argument(what + ": frame count must be at least 1");
  if (!(spec.fps > 0) || !std::isfinite(spec.fps))
    throw std::invalid_argument(what + ": frame rate must be positive");
  if (!spec.times_s.empty() && spec.times_s.size() != static_cast<std::size_t>(spec.frame_count))
    throw std::invalid_argument(what + ": one time stamp per frame, or none");
  impl_ = std::make_unique<Impl>(std::move(cine), std::move(spec));
  Impl& m = *impl_;
  const CameraFileSpec& s = m.spec;
  m.packing = s.bits == 8 ? Packing::k8 : s.bits == 12 ? Packing::k12PackedBe : Packing::k16Le;
  const auto stride = static_cast<std::uint32_t>(detail::PackedBytes(s.width, m.packing));
  m.row.resize(stride);
  const auto n = static_cast<std::uint32_t>(s.frame_count);
  const std::uint32_t off_setup = kHeaderSize + kBitmapSize;
  const std::uint32_t times_block = s.times_s.empty() ? 0 : 8 + 8 * n;
  const std::uint32_t off_table = off_setup + kSetupLength + times_block;
  m.table_at = off_table;
  m.next_at = off_table + 8ull * n;

  // Time stamps count from an arbitrary epoch (2001-09-09, image 0); `t` seconds after it is
  // split into whole seconds and 2^-32 fractions without losing precision to the epoch.
  const auto time64 = [](double t) {
    const double sec = std::floor(t);
    const double frac = std::min(std::round((t - sec) * kTime64 / 4) * 4, kTime64 - 4);
    return Time64{static_cast<std::uint32_t>(frac),
                  static_cast<std::uint32_t>(static_cast<std::int64_t>(kEpochSeconds) +
                                             static_cast<std::int64_t>(sec))};
  };
  const double frame0 = 0;
  // Image 0 is the trigger: image number n is n / fps after it.
  const Time64 trigger = time64(frame0 - static_cast<double>(s.first_frame_number) / s.fps);

  std::vector<std::uint8_t> head(off_table, 0);
  std::uint8_t* h = head.data();
  h[0] = 'C';
  h[1] = 'I';
  Put<std::uint16_t>(h + 2, kHeaderSize);
  Put<std::uint16_t>(h + 4, 0);  // grey, uncompressed
  Put<std::uint16_t>(h + 6, 1);  // version
  Put<std::int32_t>(h + 8, static_cast<std::int32_t>(s.first_frame_number));
  Put<std::uint32_t>(h + 12, n);
  Put<std::int32_t>(h + 16, static_cast<std::int32_t>(s.first_frame_number));
  Put<std::uint32_t>(h + 20, n);
  Put<std::uint32_t>(h + 24, kHeaderSize);
  Put<std::uint32_t>(h + 28, off_setup);
  Put<std::uint32_t>(h + 32, off_table);
  Put<std::uint32_t>(h + 36, trigger.fractions);
  Put<std::uint32_t>(h + 40, trigger.seconds);
  std::uint8_t* b = h + kHeaderSize;
  Put<std::uint32_t>(b, kBitmapSize);
  Put<std::int32_t>(b + 4, s.width);
  Put<std::int32_t>(b + 8, s.height);
  Put<std::uint16_t>(b + 12, 1);
  Put<std::uint16_t>(b + 14, static_cast<std::uint16_t>(s.bits == 8 ? 8 : 16));
  Put<std::uint32_t>(b + 16, s.bits == 12 ? kBiPacked12 : kBiRgb);
  Put<std::uint32_t>(b + 20, stride * static_cast<std::uint32_t>(s.height));
  const int effective = s.effective_bits > 0 ? s.effective_bits : s.bits;
  Put<std::uint32_t>(b + 36, 1u << effective);  // biClrImportant: largest value + 1
  std::uint8_t* st = h + off_setup;
  Put<std::uint16_t>(st + kFrameRate16, static_cast<std::uint16_t>(std::min(s.fps, 65535.0)));
  st[kMark] = 'S';
  st[kMark + 1] = 'T';
  Put<std::uint16_t>(st + kLength, kSetupLength);
  Put<std::uint16_t>(st + kImWidth, static_cast<std::uint16_t>(std::min(s.width, 65535)));
  Put<std::uint16_t>(st + kImHeight, static_cast<std::uint16_t>(std::min(s.height, 65535)));
  Put<std::uint32_t>(st + kFrameRate, static_cast<std::uint32_t>(std::lround(s.fps)));
  if (s.shutter_s) {
    Put<std::uint32_t>(st + kShutterUs,
                       static_cast<std::uint32_t>(std::lround(*s.shutter_s * 1e6)));
    Put<std::uint32_t>(st + kShutterNs,
                       static_cast<std::uint32_t>(std::lround(*s.shutter_s * 1e9)));
  }
  Put<std::uint32_t>(st + kRealBpp, static_cast<std::uint32_t>(effective));
  const std::string model = s.camera.substr(0, 255);
  std::memcpy(st + kCameraModel, model.data(), model.size());
  Put<float>(st + kDecimation, 1.0f);
  Put<double>(st + kFrameRateDouble, s.fps);
  if (!s.times_s.empty()) {
    std::uint8_t* t = st + kSetupLength;
    Put<std::uint32_t>(t, times_block);
    Put<std::uint16_t>(t + 4, kTagTimeOnly);
    for (std::uint32_t i = 0; i < n; ++i) {
      const Time64 v = time64(frame0 + s.times_s[i]);
      Put<std::uint32_t>(t + 8 + 8 * i, v.fractions);
      Put<std::uint32_t>(t + 12 + 8 * i, v.seconds);
    }
  }
  m.out.Write(head.data(), head.size());
  const std::vector<std::uint8_t> table(8ull * n, 0);  // filled in by Finish()
  m.out.Write(table.data(), table.size());
  m.offsets.reserve(n);
}

CineWriter::~CineWriter() = default;

void CineWriter::Write(const cv::Mat& frame) {
  Impl& m = *impl_;
  const CameraFileSpec& s = m.spec;
  const int type = s.bits == 8 ? CV_8UC1 : CV_16UC1;
  if (frame.type() != type || frame.cols != s.width || frame.rows != s.height)
    throw std::invalid_argument(m.cine.string() + ": a frame must be " + std::to_string(s.width) +
                                " x " + std::to_string(s.height) +
                                (s.bits == 8 ? " CV_8U" : " CV_16U"));
  if (m.offsets.size() >= static_cast<std::size_t>(s.frame_count))
    throw std::invalid_argument(m.cine.string() + ": more frames than the " +
                                std::to_string(s.frame_count) + " announced");
  m.offsets.push_back(m.next_at);
  m.next_at += 8 + m.row.size() * static_cast<std::size_t>(s.height);
  std::uint8_t image_head[8];
  Put<std::uint32_t>(image_head, 8);  // no annotation
  Put<std::uint32_t>(image_head + 4, static_cast<std::uint32_t>(m.row.size()) *
                                         static_cast<std::uint32_t>(s.height));
  m.out.Write(image_head, 8);
  const bool bottom_up = m.packing != Packing::k12PackedBe;
  for (int r = 0; r < s.height; ++r) {
    const int y = bottom_up ? s.height - 1 - r : r;
    detail::PackRow(frame.ptr(y), s.width, m.packing, m.row.data());
    m.out.Write(m.row.data(), m.row.size());
  }
}

void CineWriter::Finish() {
  Impl& m = *impl_;
  if (m.offsets.size() != static_cast<std::size_t>(m.spec.frame_count))
    throw std::invalid_argument(m.cine.string() + ": " + std::to_string(m.offsets.size()) +
                                " frames written, " + std::to_string(m.spec.frame_count) +
                                " announced");
  std::vector<std::uint8_t> table(8 * m.offsets.size());
  for (std::size_t i = 0; i < m.offsets.size(); ++i)
    Put<std::int64_t>(table.data() + 8 * i, static_cast<std::int64_t>(m.offsets[i]));
  m.out.WriteAt(m.table_at, table.data(), table.size());
  m.out.Rename();
}

}  // namespace hoof::tracking
