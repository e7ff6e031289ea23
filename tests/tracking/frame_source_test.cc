#include "tracking/frame_source.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
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

/// An H.264 clip of 64 x 48 frames, grey 200 with a black block in the top-left corner (the
/// stored orientation), at `fps`.
void WriteCornerClip(const fs::path& path, double fps, int frames = 4) {
  cv::VideoWriter writer(path.string(), cv::CAP_FFMPEG, cv::VideoWriter::fourcc('a', 'v', 'c', '1'),
                         fps, cv::Size(64, 48));
  ASSERT_TRUE(writer.isOpened()) << "no H.264 encoder in this OpenCV build";
  cv::Mat f(48, 64, CV_8UC3, cv::Scalar(200, 200, 200));
  f(cv::Rect(0, 0, 16, 12)).setTo(cv::Scalar(0, 0, 0));
  for (int i = 0; i < frames; ++i) writer.write(f);
}

/// Runs a shell command; false when it fails.
bool Shell(const std::string& command) {
  return std::system((command + " 2>/dev/null").c_str()) == 0;
}

/// Centre of the dark pixels (< 100) of a grey image.
cv::Point2d DarkCentre(const cv::Mat& grey) {
  cv::Mat dark;
  cv::threshold(grey, dark, 100, 255, cv::THRESH_BINARY_INV);
  const cv::Moments m = cv::moments(dark, true);
  return {m.m10 / m.m00, m.m01 / m.m00};
}

TEST(FrameSourceTest, AVideoGivesItsContainerRateAndCodec) {
  const fs::path dir = FreshDir("frames_video_rate");
  WriteCornerClip(dir / "clip.mp4", 30000.0 / 1001);
  VideoSource src(dir / "clip.mp4");
  EXPECT_NEAR(src.info().fps, 30000.0 / 1001, 1e-3);
  EXPECT_EQ(src.info().codec, "avc1");
  EXPECT_EQ(src.info().rotation_deg, 0);
  EXPECT_EQ(src.info().width, 64);
  EXPECT_EQ(src.info().height, 48);
}

// A phone held sideways stores its frames sideways and tags them; a player (here ffmpeg, which
// turns the frames by the container's display matrix when it decodes them) shows them turned.
// The frames read must be the ones the player shows, for every tag.
TEST(FrameSourceTest, ARotationTagTurnsTheFramesAsAPlayerShowsThem) {
  ASSERT_TRUE(Shell("ffmpeg -version >/dev/null")) << "ffmpeg is missing (tools/install-deps)";
  const fs::path dir = FreshDir("frames_video_rotation");
  WriteCornerClip(dir / "stored.mp4", 30.0);
  for (int tag : {90, 180, 270}) {
    const fs::path tagged = dir / ("tagged" + std::to_string(tag) + ".mp4");
    const fs::path shown = dir / ("shown" + std::to_string(tag) + ".png");
    ASSERT_TRUE(Shell("ffmpeg -y -v error -i '" + (dir / "stored.mp4").string() +
                      "' -c copy -metadata:s:v:0 rotate=" + std::to_string(tag) + " '" +
                      tagged.string() + "'"));
    ASSERT_TRUE(Shell("ffmpeg -y -v error -i '" + tagged.string() +
                      "' -frames:v 1 -pix_fmt gray '" + shown.string() + "'"));
    const cv::Mat player = cv::imread(shown.string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(player.empty());
    VideoSource src(tagged);
    const cv::Mat ours = src.Read(0);
    ASSERT_EQ(ours.size(), player.size()) << "tag " << tag;
    EXPECT_EQ(src.info().width, player.cols) << "tag " << tag;
    EXPECT_EQ(src.info().height, player.rows) << "tag " << tag;
    EXPECT_TRUE(src.info().rotation_applied);
    const cv::Point2d a = DarkCentre(ours), b = DarkCentre(player);
    EXPECT_LT(std::hypot(a.x - b.x, a.y - b.y), 1.0)
        << "tag " << tag << ": the corner block at (" << a.x << ", " << a.y
        << "), the player shows it at (" << b.x << ", " << b.y << ")";
    // The tag in the clockwise sense a player turns by: where the stored top-left corner goes.
    const int expected_rotation = b.x > 32 && b.y < 24 ? 90 : b.x > 32 && b.y > 24 ? 180 : 270;
    EXPECT_EQ(src.info().rotation_deg, expected_rotation) << "tag " << tag;
  }
}

TEST(FrameSourceTest, ARotationTagThatIsNotAQuarterTurnIsRefusedNamingTheClip) {
  ASSERT_TRUE(Shell("ffmpeg -version >/dev/null")) << "ffmpeg is missing (tools/install-deps)";
  const fs::path dir = FreshDir("frames_video_rotation45");
  WriteCornerClip(dir / "stored.mp4", 30.0);
  ASSERT_TRUE(Shell("ffmpeg -y -v error -i '" + (dir / "stored.mp4").string() +
                    "' -c copy -metadata:s:v:0 rotate=45 '" + (dir / "tilted.mp4").string() + "'"));
  ExpectError([&] { VideoSource src(dir / "tilted.mp4"); }, "tilted.mp4: its rotation tag");
  ExpectError([&] { VideoSource src(dir / "tilted.mp4"); }, "not a multiple of 90");
}

}  // namespace
}  // namespace hoof::tracking
