#include "tracking/frame_source.h"

#include <cstdio>
#include <regex>
#include <stdexcept>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

namespace hoof::tracking {

cv::Mat ToGrey(const cv::Mat& image, const std::string& what) {
  if (image.empty()) throw std::runtime_error(what + ": empty or unreadable image");
  const int depth = image.depth();
  if (depth != CV_8U && depth != CV_16U && depth != CV_32F && depth != CV_64F)
    throw std::runtime_error(what + ": unsupported pixel depth");
  switch (image.channels()) {
    case 1: return image;
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
    case CV_8U: grey.convertTo(out, CV_32F, 1.0 / 255.0); break;
    case CV_16U: grey.convertTo(out, CV_32F, 1.0 / 65535.0); break;
    default: grey.convertTo(out, CV_32F); break;
  }
  return out;
}

ImageSequenceSource::ImageSequenceSource(std::filesystem::path dir, std::string pattern,
                                         int first, int count)
    : dir_(std::move(dir)), pattern_(std::move(pattern)), first_(first), count_(count) {
  static const std::regex one_int(R"(^[^%]*(%%[^%]*)*%0?\d*d([^%]|%%)*$)");
  if (!std::regex_match(pattern_, one_int))
    throw std::invalid_argument("frames.pattern \"" + pattern_ +
                                "\" must hold exactly one integer conversion such as %06d");
  if (count_ < 1) throw std::invalid_argument("frames.count must be >= 1");
}

std::filesystem::path ImageSequenceSource::PathOf(int index) const {
  std::vector<char> buf(pattern_.size() + 32);
  std::snprintf(buf.data(), buf.size(), pattern_.c_str(), first_ + index);
  const std::filesystem::path rel(buf.data());
  return rel.is_absolute() ? rel : dir_ / rel;
}

std::string ImageSequenceSource::Describe(int index) const { return PathOf(index).string(); }

cv::Mat ImageSequenceSource::Read(int index) {
  if (index < 0 || index >= count_)
    throw std::out_of_range("frame " + std::to_string(index) + " is outside the sequence");
  const auto path = PathOf(index);
  if (!std::filesystem::exists(path))
    throw std::runtime_error(path.string() + ": frame " + std::to_string(index) + " is missing");
  const cv::Mat image = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
  if (image.empty())
    throw std::runtime_error(path.string() + ": frame " + std::to_string(index) +
                             " cannot be decoded (corrupt or not an image)");
  return ToGrey(image, path.string());
}

VideoSource::VideoSource(std::filesystem::path path) : path_(std::move(path)) {
  if (!std::filesystem::exists(path_))
    throw std::runtime_error(path_.string() + ": video file is missing");
  Open();
  count_ = static_cast<int>(capture_->get(cv::CAP_PROP_FRAME_COUNT));
  if (count_ <= 0) throw std::runtime_error(path_.string() + ": video has no frames");
}

VideoSource::~VideoSource() = default;

void VideoSource::Open() {
  capture_ = std::make_unique<cv::VideoCapture>(path_.string());
  if (!capture_->isOpened())
    throw std::runtime_error(path_.string() + ": cannot open video (unsupported codec?)");
  next_ = 0;
}

std::string VideoSource::Describe(int index) const {
  return path_.string() + " frame " + std::to_string(index);
}

cv::Mat VideoSource::Read(int index) {
  if (index < 0 || index >= count_)
    throw std::out_of_range("frame " + std::to_string(index) + " is outside the video");
  if (index < next_) Open();
  cv::Mat frame;
  while (next_ <= index) {
    if (!capture_->read(frame))
      throw std::runtime_error(Describe(next_) + ": cannot be decoded");
    ++next_;
  }
  return ToGrey(frame, Describe(index));
}

}  // namespace hoof::tracking
