#include "tracking/frame_source.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <zlib.h>
#include <opencv2/core/version.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

namespace hoof::tracking {

std::optional<std::string> FpsOutOfRange(double fps) {
  if (fps >= kMinFps && fps <= kMaxFps) return std::nullopt;
  std::ostringstream s;
  s << fps << " fps is not within " << kMinFps << " to " << kMaxFps;
  return s.str();
}

cv::Mat ToGrey(const cv::Mat& image, const std::string& what) {
  if (image.empty()) throw std::runtime_error(what + ": empty or unreadable image");
  const int depth = image.depth();
  if (depth != CV_8U && depth != CV_16U && depth != CV_32F && depth != CV_64F)
    throw std::runtime_error(what + ": unsupported pixel depth");
  switch (image.channels()) {
    case 1:
      return image;
    case 3: {
      cv::Mat grey;
      cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
      return grey;
    }
    case 4: {
      cv::Mat grey;
      cv::cvtColor(image, grey, cv::COLOR_BGRA2GRAY);
      return grey;
    }
    default:
      throw std::runtime_error(what + ": unsupported number of channels " +
                               std::to_string(image.channels()));
  }
}

cv::Mat ToUnitFloat(const cv::Mat& grey) {
  cv::Mat out;
  switch (grey.depth()) {
    case CV_8U:
      grey.convertTo(out, CV_32F, 1.0 / 255.0);
      break;
    case CV_16U:
      grey.convertTo(out, CV_32F, 1.0 / 65535.0);
      break;
    default:
      grey.convertTo(out, CV_32F);
      break;
  }
  return out;
}

bool IsFramePattern(const std::string& pattern) {
  // A linear scan (a std::regex recurses per character and overflows the stack on long input).
  if (pattern.empty() || pattern.size() > kMaxFramePatternLength) return false;
  int conversions = 0;
  for (std::size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '%') continue;
    if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
      ++i;
      continue;
    }
    std::size_t j = i + 1;
    if (j < pattern.size() && pattern[j] == '0') ++j;
    const std::size_t digits = j;
    while (j < pattern.size() && std::isdigit(static_cast<unsigned char>(pattern[j]))) ++j;
    if (j - digits > 2 || j >= pattern.size() || pattern[j] != 'd') return false;
    ++conversions;
    i = j;
  }
  return conversions == 1;
}

ImageSequenceSource::ImageSequenceSource(std::filesystem::path dir, std::string pattern, int first,
                                         int count)
    : dir_(std::move(dir)), pattern_(std::move(pattern)), first_(first), count_(count) {
  if (!IsFramePattern(pattern_))
    throw std::invalid_argument("frames.pattern \"" + pattern_ +
                                "\" must hold exactly one integer conversion such as %06d");
  if (count_ < 1) throw std::invalid_argument("frames.count must be >= 1");
  if (first_ < 0 || first_ > std::numeric_limits<int>::max() - (count_ - 1))
    throw std::invalid_argument("frames.first + frames.count is beyond the largest frame number");
}

std::filesystem::path ImageSequenceSource::PathOf(int index) const {
  std::vector<char> buf(pattern_.size() + 32);
  std::snprintf(buf.data(), buf.size(), pattern_.c_str(), first_ + index);
  const std::filesystem::path rel(buf.data());
  return rel.is_absolute() ? rel : dir_ / rel;
}

std::string ImageSequenceSource::Describe(int index) const { return PathOf(index).string(); }

namespace {

/// Why the bytes of a PNG file would not decode, or "" (also for a file that is not a PNG: the
/// decoder judges that). Every chunk's length and CRC-32 is checked, up to the end chunk, so a
/// file cut short or damaged is named here instead of by libpng, which prints its own message
/// on stderr ("libpng error: Read Error", "bad adaptive filter value").
std::string PngProblem(const std::vector<unsigned char>& bytes) {
  static constexpr unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (bytes.size() < 8 || !std::equal(kSignature, kSignature + 8, bytes.begin())) return "";
  const auto be32 = [&](std::size_t at) {
    return (std::uint32_t{bytes[at]} << 24) | (std::uint32_t{bytes[at + 1]} << 16) |
           (std::uint32_t{bytes[at + 2]} << 8) | std::uint32_t{bytes[at + 3]};
  };
  const std::string size = " (" + std::to_string(bytes.size()) + " bytes)";
  for (std::size_t at = 8;;) {
    if (bytes.size() - at < 12) return "is cut short: a PNG file without its end chunk" + size;
    const std::uint32_t length = be32(at);
    if (length > bytes.size() - at - 12)
      return "is cut short: a PNG chunk runs past the end of the file" + size;
    const std::string type(bytes.begin() + static_cast<std::ptrdiff_t>(at + 4),
                           bytes.begin() + static_cast<std::ptrdiff_t>(at + 8));
    const uLong crc =
        crc32(crc32(0L, Z_NULL, 0), bytes.data() + at + 4, static_cast<uInt>(length + 4));
    if (crc != be32(at + 8 + length))
      return "is damaged: its PNG chunk " + type + " at byte " + std::to_string(at) +
             " fails its CRC check" + size;
    if (type == "IEND") return "";
    at += 12 + length;
  }
}

/// Why the bytes of a JPEG file would not decode whole, or "". libjpeg decodes a file cut short
/// without complaint, filling the missing rows with grey, and a tracker then misses its markers
/// in that frame with no hint why. A JPEG ends with its EOI marker (FF D9); a few bytes of
/// padding after it are allowed, as some cameras write them.
std::string JpegProblem(const std::vector<unsigned char>& bytes) {
  if (bytes.size() < 3 || bytes[0] != 0xff || bytes[1] != 0xd8 || bytes[2] != 0xff) return "";
  const std::size_t from = bytes.size() > 64 ? bytes.size() - 64 : 2;
  for (std::size_t at = bytes.size() - 1; at > from; --at)
    if (bytes[at - 1] == 0xff && bytes[at] == 0xd9) return "";
  return "is cut short: a JPEG file without its end marker (" + std::to_string(bytes.size()) +
         " bytes)";
}

}  // namespace

cv::Mat ImageSequenceSource::Read(int index) {
  return ToGrey(ReadColour(index), PathOf(index).string());
}

cv::Mat ImageSequenceSource::ReadColour(int index) {
  if (index < 0 || index >= count_)
    throw std::out_of_range("frame " + std::to_string(index) + " is outside the sequence");
  const auto path = PathOf(index);
  if (!std::filesystem::exists(path))
    throw std::runtime_error(path.string() + ": frame " + std::to_string(index) + " is missing");
  // The file's bytes first: a PNG or JPEG cut short (a copy that stopped) is named here, before
  // the decoder sees it (libpng prints its own "Read Error"; libjpeg decodes the rest as grey).
  std::vector<unsigned char> bytes;
  {
    // One read of the known size (this runs for every frame of every trial).
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    std::ifstream in(path, std::ios::binary);
    if (!ec) bytes.resize(static_cast<std::size_t>(size));
    if (ec ||
        !in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size())))
      throw std::runtime_error(path.string() + ": frame " + std::to_string(index) +
                               " cannot be read");
  }
  if (std::string problem = PngProblem(bytes);
      !problem.empty() || !(problem = JpegProblem(bytes)).empty())
    throw std::runtime_error(path.string() + ": frame " + std::to_string(index) + " " + problem);
  cv::Mat image;
  try {
    image = cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {  // e.g. an image beyond OpenCV's pixel limit
    const bool too_large = e.msg.find("CV_IO_MAX_IMAGE_PIXELS") != std::string::npos;
    throw std::runtime_error(
        path.string() + ": frame " + std::to_string(index) +
        (too_large ? " has more pixels than OpenCV decodes (2^30; CV_IO_MAX_IMAGE_PIXELS)"
                   : " cannot be decoded: " + e.msg));
  }
  if (image.empty())
    throw std::runtime_error(path.string() + ": frame " + std::to_string(index) +
                             " cannot be decoded (corrupt or not an image)");
  return image;
}

namespace {

/// The clockwise turn (deg, in [0, 360)) that shows a video's stored frames upright, from
/// OpenCV's CAP_PROP_ORIENTATION_META. The container's display matrix says how a player turns
/// the frames; OpenCV 4.6's FFmpeg backend reports that matrix's counter-clockwise angle
/// (opencv/opencv#22088: a phone's portrait clip, which players turn 90 deg clockwise, reads
/// 270) and, with CAP_PROP_ORIENTATION_AUTO, turns the frames the wrong way; 4.5.5 reported
/// the clockwise turn. The project builds against Debian's 4.6, and
/// tests/tracking/frame_source_test.cc holds the frames turned here against ffmpeg's own
/// display rotation, so a version that reports the tag otherwise fails that test.
double DisplayRotationDeg(double orientation_meta) {
#if CV_VERSION_MAJOR == 4 && CV_VERSION_MINOR == 6
  orientation_meta = -orientation_meta;
#endif
  return std::fmod(std::fmod(orientation_meta, 360.0) + 360.0, 360.0);
}

}  // namespace

VideoSource::VideoSource(std::filesystem::path path) : path_(std::move(path)) {
  if (!std::filesystem::exists(path_))
    throw std::runtime_error(path_.string() + ": video file is missing");
  Open();
  count_ = static_cast<int>(capture_->get(cv::CAP_PROP_FRAME_COUNT));
  if (count_ <= 0) throw std::runtime_error(path_.string() + ": video has no frames");
  const double fps = capture_->get(cv::CAP_PROP_FPS);
  if (std::isfinite(fps) && fps > 0 && !FpsOutOfRange(fps)) info_.fps = fps;
  const double tag = capture_->get(cv::CAP_PROP_ORIENTATION_META);
  if (std::isfinite(tag) && tag != 0) {
    const double turned = DisplayRotationDeg(tag);
    if (std::abs(turned - 90 * std::round(turned / 90)) > 1e-6) {
      std::ostringstream os;
      os << path_.string() << ": its rotation tag turns the frames by " << turned
         << " deg, which is not a multiple of 90: no frame can be shown upright (rotate or "
            "re-encode the video upright, or remove the tag)";
      throw std::runtime_error(os.str());
    }
    info_.rotation_deg = static_cast<int>(std::lround(turned)) % 360;
  }
  info_.rotation_applied = info_.rotation_deg != 0;
  const int stored_w = static_cast<int>(capture_->get(cv::CAP_PROP_FRAME_WIDTH));
  const int stored_h = static_cast<int>(capture_->get(cv::CAP_PROP_FRAME_HEIGHT));
  const bool sideways = info_.rotation_deg == 90 || info_.rotation_deg == 270;
  info_.width = sideways ? stored_h : stored_w;
  info_.height = sideways ? stored_w : stored_h;
  const auto fourcc = static_cast<std::uint32_t>(capture_->get(cv::CAP_PROP_FOURCC));
  for (int i = 0; i < 4 && fourcc != 0; ++i) {
    const char c = static_cast<char>((fourcc >> (8 * i)) & 0xff);
    if (std::isprint(static_cast<unsigned char>(c))) info_.codec += c;
  }
}

VideoSource::~VideoSource() = default;

void VideoSource::Open() {
  // FFmpeg first; the other backends only if it cannot (hoofimpact silences OpenCV's log, so a
  // file that no backend reads gets only our message naming it).
  capture_ = std::make_unique<cv::VideoCapture>(path_.string(), cv::CAP_FFMPEG);
  // The frames are turned upright here, not by the backend (see DisplayRotationDeg).
  if (capture_->isOpened()) capture_->set(cv::CAP_PROP_ORIENTATION_AUTO, 0);
  if (!capture_->isOpened())
    capture_ = std::make_unique<cv::VideoCapture>(path_.string(), cv::CAP_ANY);
  if (!capture_->isOpened())
    throw std::runtime_error(path_.string() + ": cannot open video (unsupported codec?)");
  next_ = 0;
}

std::string VideoSource::Describe(int index) const {
  return path_.string() + " frame " + std::to_string(index);
}

cv::Mat VideoSource::Read(int index) { return ToGrey(ReadColour(index), Describe(index)); }

cv::Mat VideoSource::ReadColour(int index) {
  if (index < 0 || index >= count_)
    throw std::out_of_range("frame " + std::to_string(index) + " is outside the video");
  if (index < next_) Open();
  // The frames before the one asked for are decoded (a video's frames depend on those before)
  // but not converted to BGR.
  for (; next_ < index; ++next_)
    if (!capture_->grab()) throw std::runtime_error(Describe(next_) + ": cannot be decoded");
  cv::Mat frame;
  if (!capture_->read(frame)) throw std::runtime_error(Describe(next_) + ": cannot be decoded");
  ++next_;
  if (info_.rotation_deg == 0) return frame;
  cv::Mat upright;
  cv::rotate(frame, upright,
             info_.rotation_deg == 90    ? cv::ROTATE_90_CLOCKWISE
             : info_.rotation_deg == 180 ? cv::ROTATE_180
                                         : cv::ROTATE_90_COUNTERCLOCKWISE);
  return upright;
}

}  // namespace hoof::tracking
