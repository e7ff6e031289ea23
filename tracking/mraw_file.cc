// Photron MRAW: headerless frames one after another, described by a .cihx (XML) or .cih
// ("Key : Value") file of the same stem (docs/camera-files.md).

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>

#include "tracking/camera_file.h"
#include "tracking/camera_file_internal.h"

namespace hoof::tracking {
namespace {

namespace fs = std::filesystem;
using detail::Packing;

/// Largest header file read (bytes); real ones are tens of kilobytes.
constexpr std::uintmax_t kMaxHeaderBytes = 16u << 20;

std::string_view Trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

std::string Lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

/// The text of the element at `path` (each step searched within the previous one), or nullopt.
/// Enough for Photron's flat, attribute-free XML; written here because tracking has no XML
/// library and the fields needed are few.
std::optional<std::string_view> XmlValue(std::string_view xml,
                                         std::initializer_list<std::string_view> path) {
  std::string_view scope = xml;
  for (const std::string_view name : path) {
    std::string open(1, '<'), close("</");
    open.append(name).push_back('>');
    close.append(name).push_back('>');
    const std::size_t a = scope.find(open);
    if (a == std::string_view::npos) return std::nullopt;
    const std::size_t from = a + open.size();
    const std::size_t b = scope.find(close, from);
    if (b == std::string_view::npos) return std::nullopt;
    scope = scope.substr(from, b - from);
  }
  return Trim(scope);
}

[[noreturn]] void Bad(const std::string& name, const std::string& field, const std::string& why) {
  throw std::runtime_error(name + ": " + field + " " + why);
}

std::int64_t ToInt(std::string_view text, const std::string& name, const std::string& field) {
  text = Trim(text);
  std::int64_t v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size())
    Bad(name, field, "is not an integer: \"" + std::string(text.substr(0, 40)) + "\"");
  return v;
}

double ToDouble(std::string_view text, const std::string& name, const std::string& field) {
  text = Trim(text);
  double v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v))
    Bad(name, field, "is not a number: \"" + std::string(text.substr(0, 40)) + "\"");
  return v;
}

/// A shutter time written "1/50000" or "0.00002" (seconds).
double ShutterSeconds(std::string_view text, const std::string& name, const std::string& field) {
  text = Trim(text);
  if (const std::size_t slash = text.find('/'); slash != std::string_view::npos) {
    const double num = ToDouble(text.substr(0, slash), name, field);
    const double den = ToDouble(text.substr(slash + 1), name, field);
    if (!(den > 0)) Bad(name, field, "has a zero denominator");
    return num / den;
  }
  return ToDouble(text, name, field);
}

/// Checks the facts every header must give sensibly.
void Validate(PhotronHeader& h, const std::string& name) {
  if (h.width < 1 || h.width > detail::kMaxSide || h.height < 1 || h.height > detail::kMaxSide)
    Bad(name, "image size",
        std::to_string(h.width) + " x " + std::to_string(h.height) + " is not within 1 to " +
            std::to_string(detail::kMaxSide) + " pixels a side");
  if (static_cast<std::int64_t>(h.width) * h.height > detail::kMaxFramePixels)
    Bad(name, "image size", "has more than 2^30 pixels");
  if (h.color_bit != 8 && h.color_bit != 12 && h.color_bit != 16)
    Bad(name, "bit depth",
        std::to_string(h.color_bit) + " is not one this reader knows (8, 12 packed or 16)");
  if (h.color_bit == 12 && h.width % 2 != 0)
    Bad(name, "image width", std::to_string(h.width) + " is odd: 12-bit packed rows need pairs");
  if (h.effective_bit == 0) h.effective_bit = h.color_bit;
  if (h.effective_bit < 1 || h.effective_bit > h.color_bit)
    Bad(name, "effective bit depth",
        std::to_string(h.effective_bit) + " is not within 1 to the bit depth " +
            std::to_string(h.color_bit));
  if (h.frame_count < 1) Bad(name, "frame count", "must be at least 1");
  if (const auto why = FpsOutOfRange(h.fps)) Bad(name, "frame rate", *why);
  if (h.shutter_s && !(*h.shutter_s > 0)) h.shutter_s.reset();
}

int ToSide(std::int64_t v) {
  return static_cast<int>(std::clamp<std::int64_t>(v, -1, std::numeric_limits<int>::max()));
}

PhotronHeader ParseCihx(std::string_view text, const std::string& name) {
  const std::size_t a = text.find("<cih>");
  const std::size_t b = text.rfind("</cih>");
  if (a == std::string_view::npos || b == std::string_view::npos || b < a)
    throw std::runtime_error(name + ": not a Photron XML header (no <cih> element)");
  const std::string_view xml = text.substr(a, b - a);
  const auto need = [&](std::initializer_list<std::string_view> path, const std::string& field) {
    const auto v = XmlValue(xml, path);
    if (!v) Bad(name, field, "is missing");
    return *v;
  };
  PhotronHeader h;
  h.width =
      ToSide(ToInt(need({"imageDataInfo", "resolution", "width"}, "imageDataInfo/resolution/width"),
                   name, "width"));
  h.height = ToSide(
      ToInt(need({"imageDataInfo", "resolution", "height"}, "imageDataInfo/resolution/height"),
            name, "height"));
  h.color_bit =
      ToSide(ToInt(need({"imageDataInfo", "colorInfo", "bit"}, "imageDataInfo/colorInfo/bit"), name,
                   "imageDataInfo/colorInfo/bit"));
  if (const auto v = XmlValue(xml, {"imageDataInfo", "colorInfo", "type"})) h.color_type = *v;
  if (const auto v = XmlValue(xml, {"imageDataInfo", "effectiveBit", "depth"}))
    h.effective_bit = ToSide(ToInt(*v, name, "imageDataInfo/effectiveBit/depth"));
  h.frame_count = ToSide(ToInt(need({"frameInfo", "totalFrame"}, "frameInfo/totalFrame"), name,
                               "frameInfo/totalFrame"));
  if (const auto v = XmlValue(xml, {"frameInfo", "startFrame"}))
    h.start_frame = ToInt(*v, name, "frameInfo/startFrame");
  h.fps = ToDouble(need({"recordInfo", "recordRate"}, "recordInfo/recordRate"), name,
                   "recordInfo/recordRate");
  if (const auto v = XmlValue(xml, {"recordInfo", "shutterSpeedNsec"}))
    h.shutter_s = ToDouble(*v, name, "recordInfo/shutterSpeedNsec") * 1e-9;
  else if (const auto s = XmlValue(xml, {"recordInfo", "shutterSpeed"}))
    h.shutter_s = 1.0 / ToDouble(*s, name, "recordInfo/shutterSpeed");  // written as 1/x s
  if (const auto v = XmlValue(xml, {"imageFileInfo", "fileFormat"})) h.file_format = *v;
  if (const auto v = XmlValue(xml, {"deviceInfo", "deviceName"})) h.camera = *v;
  Validate(h, name);
  return h;
}

PhotronHeader ParseCih(std::string_view text, const std::string& name) {
  std::map<std::string, std::string, std::less<>> kv;
  std::size_t at = 0;
  while (at < text.size()) {
    std::size_t end = text.find('\n', at);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = text.substr(at, end - at);
    at = end + 1;
    if (line.empty() || line.front() == '#') continue;
    const std::size_t colon = line.find(" : ");
    if (colon == std::string_view::npos) continue;
    kv.emplace(std::string(Trim(line.substr(0, colon))), std::string(Trim(line.substr(colon + 3))));
  }
  const auto need = [&](const std::string& key) -> const std::string& {
    const auto it = kv.find(key);
    if (it == kv.end()) Bad(name, "\"" + key + "\"", "is missing");
    return it->second;
  };
  const auto maybe = [&](const std::string& key) -> const std::string* {
    const auto it = kv.find(key);
    return it == kv.end() ? nullptr : &it->second;
  };
  PhotronHeader h;
  h.width = ToSide(ToInt(need("Image Width"), name, "\"Image Width\""));
  h.height = ToSide(ToInt(need("Image Height"), name, "\"Image Height\""));
  h.color_bit = ToSide(ToInt(need("Color Bit"), name, "\"Color Bit\""));
  if (const auto* v = maybe("Color Type")) h.color_type = *v;
  if (const auto* v = maybe("EffectiveBit Depth"))
    h.effective_bit = ToSide(ToInt(*v, name, "\"EffectiveBit Depth\""));
  h.frame_count = ToSide(ToInt(need("Total Frame"), name, "\"Total Frame\""));
  if (const auto* v = maybe("Start Frame")) h.start_frame = ToInt(*v, name, "\"Start Frame\"");
  h.fps = ToDouble(need("Record Rate(fps)"), name, "\"Record Rate(fps)\"");
  if (const auto* v = maybe("Shutter Speed(s)"))
    h.shutter_s = ShutterSeconds(*v, name, "\"Shutter Speed(s)\"");
  if (const auto* v = maybe("File Format")) h.file_format = *v;
  if (const auto* v = maybe("Camera Type")) h.camera = *v;
  Validate(h, name);
  return h;
}

std::string ReadHeaderText(const fs::path& path) {
  std::error_code ec;
  const auto size = fs::file_size(path, ec);
  if (ec) throw std::runtime_error(path.string() + ": cannot be read: " + ec.message());
  if (size > kMaxHeaderBytes)
    throw std::runtime_error(path.string() + ": is " + std::to_string(size) +
                             " bytes, too large for a Photron header");
  std::ifstream in(path, std::ios::binary);
  std::string text(static_cast<std::size_t>(size), '\0');
  if (!in.read(text.data(), static_cast<std::streamsize>(text.size())))
    throw std::runtime_error(path.string() + ": cannot be read");
  return text;
}

Packing PackingOf(int bits) {
  return bits == 8 ? Packing::k8 : bits == 12 ? Packing::k12PackedBe : Packing::k16Le;
}

class MrawSource : public detail::RawFrameSource {
 public:
  MrawSource(std::unique_ptr<detail::InputFile> file, CameraFileInfo info, Packing packing,
             int stride, std::uint64_t frame_bytes)
      : RawFrameSource(std::move(file), std::move(info), packing, stride, false),
        frame_bytes_(frame_bytes) {}

 protected:
  std::uint64_t PixelOffset(int index) override {
    return static_cast<std::uint64_t>(index) * frame_bytes_;
  }

 private:
  std::uint64_t frame_bytes_;
};

/// "the size is that of 15 frames at 16 bits" where another depth explains the data size.
std::string SizeHint(std::uint64_t size, const PhotronHeader& h) {
  const std::uint64_t pixels = static_cast<std::uint64_t>(h.width) * h.height;
  for (const int bits : {8, 12, 16}) {
    if (bits == h.color_bit) continue;
    const auto frame = static_cast<std::uint64_t>(
        detail::PackedBytes(static_cast<std::int64_t>(pixels), PackingOf(bits)));
    if (frame > 0 && size == frame * static_cast<std::uint64_t>(h.frame_count))
      return " (the size is exactly that of " + std::to_string(h.frame_count) + " frames at " +
             std::to_string(bits) + " bits: is the header's bit depth right?)";
  }
  return "";
}

}  // namespace

PhotronHeader ParsePhotronHeader(std::string_view text, const std::string& name) {
  if (text.find("<cih>") != std::string_view::npos) return ParseCihx(text, name);
  return ParseCih(text, name);
}

namespace detail {

std::unique_ptr<CameraFileSource> OpenMraw(const fs::path& path) {
  const std::string ext = LowerExtension(path);
  fs::path mraw = path, header;
  const auto beside = [&](const char* lower, const char* upper) {
    fs::path p = path;
    p.replace_extension(lower);
    if (fs::exists(p)) return p;
    p.replace_extension(upper);
    return fs::exists(p) ? p : fs::path();
  };
  if (ext == ".mraw") {
    header = beside(".cihx", ".CIHX");
    if (header.empty()) header = beside(".cih", ".CIH");
    if (!fs::exists(mraw)) throw std::runtime_error(mraw.string() + ": file is missing");
    if (header.empty()) {
      fs::path x = path, t = path;
      x.replace_extension(".cihx");
      t.replace_extension(".cih");
      throw std::runtime_error(mraw.string() + ": its camera header is missing (looked for " +
                               x.filename().string() + " and " + t.filename().string() +
                               " beside it)");
    }
  } else {
    header = path;
    if (!fs::exists(header)) throw std::runtime_error(header.string() + ": file is missing");
    mraw = beside(".mraw", ".MRAW");
    if (mraw.empty()) {
      fs::path m = path;
      m.replace_extension(".mraw");
      throw std::runtime_error(header.string() + ": its frames are missing (no " +
                               m.filename().string() + " beside it)");
    }
  }
  PhotronHeader h = ParsePhotronHeader(ReadHeaderText(header), header.string());
  if (!h.file_format.empty() && Lower(h.file_format) != "mraw")
    throw std::runtime_error(header.string() + ": describes frames saved as \"" + h.file_format +
                             "\", not as an .mraw file");
  auto file = std::make_unique<InputFile>(mraw);
  const Packing packing = PackingOf(h.color_bit);
  const auto pixels = static_cast<std::int64_t>(h.width) * h.height;
  const auto frame_bytes = static_cast<std::uint64_t>(PackedBytes(pixels, packing));
  const std::uint64_t expected = frame_bytes * static_cast<std::uint64_t>(h.frame_count);
  const std::uint64_t size = file->size();
  const std::string says = "the header (" + header.filename().string() + ") says " +
                           std::to_string(h.frame_count) + " frames of " + std::to_string(h.width) +
                           " x " + std::to_string(h.height) + " at " + std::to_string(h.color_bit) +
                           " bits (" + std::to_string(frame_bytes) + " bytes each, " +
                           std::to_string(expected) + " in all)";
  if (size < expected)
    throw std::runtime_error(mraw.string() + ": cut short: " + says + " but the file holds " +
                             std::to_string(size) + " bytes: frame " +
                             std::to_string(size / frame_bytes) + " is incomplete" +
                             SizeHint(size, h));
  if (size > expected)
    throw std::runtime_error(
        mraw.string() + ": " + says + " but the file holds " + std::to_string(size) +
        " bytes: the header's size or bit depth disagrees with the data" + SizeHint(size, h));
  CameraFileInfo info;
  info.format = "photron-mraw";
  info.width = h.width;
  info.height = h.height;
  info.frame_count = h.frame_count;
  info.bit_depth = h.effective_bit;
  info.storage_bits = h.color_bit;
  info.fps = h.fps;
  info.recording_fps = h.fps;
  info.shutter_s = h.shutter_s;
  if (h.start_frame) {
    info.first_frame_number = *h.start_frame;
    info.trigger_time_s = -static_cast<double>(*h.start_frame) / h.fps;
  }
  info.camera = h.camera;
  info.header = header.string();
  info.data = mraw.string();
  const int stride = static_cast<int>(PackedBytes(h.width, packing));
  return std::make_unique<MrawSource>(std::move(file), std::move(info), packing, stride,
                                      frame_bytes);
}

}  // namespace detail

// --- Writer -------------------------------------------------------------------------------------

struct MrawWriter::Impl {
  Impl(fs::path m, CameraFileSpec s)
      : mraw(std::move(m)), spec(std::move(s)), packing(PackingOf(spec.bits)), out(mraw) {}
  fs::path mraw;
  CameraFileSpec spec;
  Packing packing;
  detail::OutputFile out;
  std::vector<std::uint8_t> row;
  int written = 0;
};

namespace {

void CheckSpec(const CameraFileSpec& s, const std::string& what, std::initializer_list<int> bits) {
  if (s.width < 1 || s.height < 1 || s.width > detail::kMaxSide || s.height > detail::kMaxSide)
    throw std::invalid_argument(what + ": image size must be 1 to 65536 pixels a side");
  if (std::find(bits.begin(), bits.end(), s.bits) == bits.end())
    throw std::invalid_argument(what + ": cannot write " + std::to_string(s.bits) + "-bit data");
  if (s.bits == 12 && s.width % 2 != 0)
    throw std::invalid_argument(what + ": 12-bit packed rows need an even width");
  if (s.frame_count < 1) throw std::invalid_argument(what + ": frame count must be at least 1");
  if (!(s.fps > 0) || !std::isfinite(s.fps))
    throw std::invalid_argument(what + ": frame rate must be positive");
  if (s.effective_bits < 0 || s.effective_bits > s.bits)
    throw std::invalid_argument(what + ": effective bits must be within 0 to bits");
}

void CheckFrame(const cv::Mat& f, const CameraFileSpec& s, const std::string& what) {
  const int type = s.bits == 8 ? CV_8UC1 : CV_16UC1;
  if (f.type() != type || f.cols != s.width || f.rows != s.height)
    throw std::invalid_argument(what + ": a frame must be " + std::to_string(s.width) + " x " +
                                std::to_string(s.height) + (s.bits == 8 ? " CV_8U" : " CV_16U"));
  if (s.bits == 12) {
    double hi = 0;
    cv::minMaxLoc(f, nullptr, &hi);
    if (hi > 4095) throw std::invalid_argument(what + ": a 12-bit frame holds a value over 4095");
  }
}

std::string CihxText(const CameraFileSpec& s) {
  std::ostringstream x;
  x.precision(17);
  const int effective = s.effective_bits > 0 ? s.effective_bits : s.bits;
  x << "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<cih>\n"
    << "    <fileInfo>\n        <version>1.0</version>\n    </fileInfo>\n"
    << "    <imageFileInfo>\n        <fileFormat>Mraw</fileFormat>\n        <resolution>\n"
    << "            <width>" << s.width << "</width>\n            <height>" << s.height
    << "</height>\n        </resolution>\n    </imageFileInfo>\n"
    << "    <imageDataInfo>\n        <resolution>\n            <width>" << s.width
    << "</width>\n            <height>" << s.height << "</height>\n        </resolution>\n"
    << "        <colorInfo>\n            <type>Mono</type>\n            <bit>" << s.bits
    << "</bit>\n        </colorInfo>\n        <effectiveBit>\n            <depth>" << effective
    << "</depth>\n            <side>Lower</side>\n        </effectiveBit>\n    </imageDataInfo>\n"
    << "    <frameInfo>\n        <totalFrame>" << s.frame_count
    << "</totalFrame>\n        <startFrame>" << s.first_frame_number
    << "</startFrame>\n    </frameInfo>\n"
    << "    <recordInfo>\n        <recordRate>" << s.fps << "</recordRate>\n";
  if (s.shutter_s)
    x << "        <shutterSpeedNsec>" << std::llround(*s.shutter_s * 1e9)
      << "</shutterSpeedNsec>\n";
  x << "    </recordInfo>\n    <deviceInfo>\n        <deviceName>" << s.camera
    << "</deviceName>\n    </deviceInfo>\n</cih>\n";
  return x.str();
}

}  // namespace

MrawWriter::MrawWriter(fs::path mraw, CameraFileSpec spec) {
  CheckSpec(spec, mraw.string(), {8, 12, 16});
  impl_ = std::make_unique<Impl>(std::move(mraw), std::move(spec));
  impl_->row.resize(
      static_cast<std::size_t>(detail::PackedBytes(impl_->spec.width, impl_->packing)));
}

MrawWriter::~MrawWriter() = default;

void MrawWriter::Write(const cv::Mat& frame) {
  Impl& m = *impl_;
  CheckFrame(frame, m.spec, m.mraw.string());
  if (m.written >= m.spec.frame_count)
    throw std::invalid_argument(m.mraw.string() + ": more frames than the " +
                                std::to_string(m.spec.frame_count) + " announced");
  for (int y = 0; y < frame.rows; ++y) {
    detail::PackRow(frame.ptr(y), frame.cols, m.packing, m.row.data());
    m.out.Write(m.row.data(), m.row.size());
  }
  ++m.written;
}

void MrawWriter::Finish() {
  Impl& m = *impl_;
  if (m.written != m.spec.frame_count)
    throw std::invalid_argument(m.mraw.string() + ": " + std::to_string(m.written) +
                                " frames written, " + std::to_string(m.spec.frame_count) +
                                " announced");
  fs::path cihx = m.mraw;
  cihx.replace_extension(".cihx");
  detail::OutputFile header(cihx);
  const std::string text = CihxText(m.spec);
  header.Write(text.data(), text.size());
  m.out.Rename();
  header.Rename();
}

}  // namespace hoof::tracking
