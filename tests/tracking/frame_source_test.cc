#include "tracking/frame_source.h"

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "support/test_util.h"

namespace hoof::tracking {
namespace {

namespace fs = std::filesystem;

fs::path FreshDir(const std::string& name) {
  const fs::path dir = hoof::testing::FreshDir(name);
  fs::create_directories(dir / "frames");
  return dir;
}

const auto ExpectError = [](auto fn, const std::string& needle) {
  hoof::testing::ExpectErrorContaining(fn, needle);
};

TEST(FrameSourceTest, ReadsEightAndSixteenBitGreyAndColour) {
  const fs::path dir = FreshDir("frames_depths");
  cv::imwrite((dir / "frames/000000.png").string(), cv::Mat(4, 5, CV_8U, cv::Scalar(51)));
  cv::imwrite((dir / "frames/000001.png").string(), cv::Mat(4, 5, CV_16U, cv::Scalar(13107)));
  cv::imwrite((dir / "frames/000002.png").string(), cv::Mat(4, 5, CV_8UC3, cv::Scalar(51, 51, 51)));
  ImageSequenceSource src(dir, "frames/%06d.png", 0, 3);
  for (int i = 0; i < 3; ++i) {
    const cv::Mat f = ToUnitFloat(src.Read(i));
    EXPECT_EQ(f.channels(), 1);
    EXPECT_NEAR(f.at<float>(2, 3), 0.2f, 1e-6) << "frame " << i;
  }
}

TEST(FrameSourceTest, MissingAndCorruptFramesNameTheFile) {
  const fs::path dir = FreshDir("frames_bad");
  cv::imwrite((dir / "frames/000000.png").string(), cv::Mat(4, 5, CV_8U, cv::Scalar(51)));
  {
    std::ofstream bad(dir / "frames/000001.png");
    bad << "this is not a PNG";
  }
  ImageSequenceSource src(dir, "frames/%06d.png", 0, 3);
  ExpectError([&] { src.Read(1); }, "000001.png: frame 1 cannot be decoded");
  ExpectError([&] { src.Read(2); }, "000002.png: frame 2 is missing");
  // A 40000 x 40000 PNG (200 KB on disk) is refused naming the frame, not with OpenCV's assertion.
  {
    std::string png = "\x89PNG\r\n\x1a\n";
    auto chunk = [&png](const std::string& type, const std::string& data) {
      const auto be = [](std::uint32_t v) {
        return std::string{static_cast<char>(v >> 24), static_cast<char>(v >> 16),
                           static_cast<char>(v >> 8), static_cast<char>(v)};
      };
      png += be(static_cast<std::uint32_t>(data.size())) + type + data;
      const std::string crc_in = type + data;
      std::uint32_t crc = 0xffffffffu;  // PNG's CRC-32, bit by bit
      for (unsigned char c : crc_in) {
        crc ^= c;
        for (int b = 0; b < 8; ++b) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
      }
      png += be(crc ^ 0xffffffffu);
    };
    const std::uint32_t side = 40000;
    std::string ihdr;
    for (int k = 3; k >= 0; --k) ihdr += static_cast<char>(side >> (8 * k));
    ihdr += ihdr;
    ihdr += std::string{1, 0, 0, 0, 0};  // 1-bit grey
    chunk("IHDR", ihdr);
    chunk("IDAT",
          std::string("\x78\x01\x01\x00\x00\xff\xff\x00\x00\x00\x01", 11));  // an empty zlib stream
    chunk("IEND", "");
    std::ofstream(dir / "frames/000000.png", std::ios::binary) << png;
    ImageSequenceSource huge(dir, "frames/%06d.png", 0, 1);
    ExpectError([&] { huge.Read(0); }, "000000.png: frame 0 has more pixels than OpenCV decodes");
  }
  // A PNG cut short (half of a good one) is named as such, and libpng prints nothing.
  {
    const fs::path good = dir / "frames/000003.png";
    cv::imwrite(good.string(), cv::Mat(64, 80, CV_8U, cv::Scalar(120)));
    std::ifstream in(good, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(dir / "frames/000004.png", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    ImageSequenceSource cut(dir, "frames/%06d.png", 3, 2);
    EXPECT_NO_THROW(cut.Read(0));
    ::testing::internal::CaptureStderr();
    ExpectError([&] { cut.Read(1); }, "000004.png: frame 1 is cut short: a PNG");
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
    // Damaged in the middle (bytes of the image data flipped): named by the chunk whose CRC
    // fails, and again libpng prints nothing.
    std::string damaged = bytes;
    for (std::size_t i = 60; i < 90 && i < damaged.size() - 12; ++i)
      damaged[i] = static_cast<char>(damaged[i] ^ 0x5a);
    std::ofstream(dir / "frames/000004.png", std::ios::binary | std::ios::trunc) << damaged;
    ::testing::internal::CaptureStderr();
    ExpectError([&] { cut.Read(1); }, "000004.png: frame 1 is damaged: its PNG chunk");
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  }
  // A JPEG cut short decodes without complaint in libjpeg (the missing rows grey); it is named.
  // A TIFF cut short does not decode, and is named too, with nothing from libtiff on stderr.
  for (const std::string ext : {"jpg", "tif"}) {
    const fs::path good = dir / ("frames/000005." + ext);
    cv::Mat image(64, 80, CV_8U);
    cv::RNG(12345).fill(image, cv::RNG::UNIFORM, 0, 255);  // noise: a long file to cut
    ASSERT_TRUE(cv::imwrite(good.string(), image));
    std::ifstream in(good, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(dir / ("frames/000006." + ext), std::ios::binary)
        << bytes.substr(0, bytes.size() / 2);
    ImageSequenceSource cut(dir, "frames/%06d." + ext, 5, 2);
    EXPECT_NO_THROW(cut.Read(0)) << ext;
    ::testing::internal::CaptureStderr();
    ExpectError([&] { cut.Read(1); },
                "000006." + ext + ": frame 1 " +
                    (ext == "jpg" ? "is cut short: a JPEG" : "cannot be decoded"));
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), "") << ext;
  }
  EXPECT_THROW(ImageSequenceSource(dir, "frames/x.png", 0, 3), std::invalid_argument);
  EXPECT_THROW(ImageSequenceSource(dir, "frames/%d_%d.png", 0, 3), std::invalid_argument);
}

TEST(FrameSourceTest, PatternsHoldExactlyOneIntegerConversion) {
  EXPECT_TRUE(IsFramePattern("frames/%06d.png"));
  EXPECT_TRUE(IsFramePattern("%d"));
  EXPECT_TRUE(IsFramePattern("100%%/f%4d.tif"));
  EXPECT_FALSE(IsFramePattern("frames/x.png"));
  EXPECT_FALSE(IsFramePattern("%d_%d.png"));
  EXPECT_FALSE(IsFramePattern("%s.png"));
  EXPECT_FALSE(IsFramePattern("%123d.png"));  // a width of 123 characters is no file name
  EXPECT_FALSE(IsFramePattern("%06d.png%"));
  EXPECT_FALSE(IsFramePattern(""));
  // A 200 000-character pattern is refused, not scanned into a stack overflow (a std::regex did).
  const std::string huge = "frames/%06d" + std::string(200000, 'A') + ".png";
  EXPECT_FALSE(IsFramePattern(huge));
  EXPECT_THROW(ImageSequenceSource(".", huge, 0, 3), std::invalid_argument);
  // Frame numbers beyond int are refused before any is read.
  EXPECT_THROW(ImageSequenceSource(".", "%d.png", 2000000000, 2000000000), std::invalid_argument);
}

TEST(FrameSourceTest, ReadsAVideoFile) {
  const fs::path dir = FreshDir("frames_video");
  const fs::path path = dir / "clip.avi";
  cv::VideoWriter writer(path.string(), cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 25.0,
                         cv::Size(64, 48), false);
  if (!writer.isOpened()) GTEST_SKIP() << "no MJPG encoder in this OpenCV build";
  for (int i = 0; i < 5; ++i) writer.write(cv::Mat(48, 64, CV_8U, cv::Scalar(40 * i + 20)));
  writer.release();
  VideoSource src(path);
  EXPECT_EQ(src.count(), 5);
  for (int i : {0, 3, 1, 4}) {  // backwards reads reopen the file
    const cv::Mat f = ToUnitFloat(src.Read(i));
    EXPECT_NEAR(f.at<float>(24, 32), (40 * i + 20) / 255.0, 3.0 / 255) << "frame " << i;
  }
  ExpectError([&] { VideoSource(dir / "missing.avi"); }, "missing.avi");
}

}  // namespace
}  // namespace hoof::tracking
