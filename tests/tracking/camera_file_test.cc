// Camera files (tracking/camera_file.h): the real Photron and Phantom recordings in
// tests/data/real-footage against independent unpackings and header parses written here,
// round trips through the writers, every refused file, and streaming.

#include "tracking/camera_file.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <tiffio.h>

#include "support/test_util.h"

namespace hoof::tracking {
namespace {

namespace fs = std::filesystem;

const fs::path kPhotron = fs::path(HOOF_SOURCE_DIR) / "tests/data/real-footage/photron";
const fs::path kPhantom = fs::path(HOOF_SOURCE_DIR) / "tests/data/real-footage/phantom";

const auto ExpectError = [](auto fn, const std::string& needle) {
  hoof::testing::ExpectErrorContaining(fn, needle);
};

std::vector<unsigned char> Bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void WriteBytes(const fs::path& p, const std::vector<unsigned char>& b) {
  std::ofstream out(p, std::ios::binary);
  out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

/// Big-endian bit stream reader: the test's own 12-bit unpacking, bit by bit (the reader
/// unpacks byte triplets).
class BitStream {
 public:
  explicit BitStream(const std::vector<unsigned char>& b) : b_(b) {}
  unsigned Take(int bits) {
    unsigned v = 0;
    for (int i = 0; i < bits; ++i, ++pos_) {
      const unsigned bit = (b_[pos_ / 8] >> (7 - pos_ % 8)) & 1u;
      v = (v << 1) | bit;
    }
    return v;
  }

 private:
  const std::vector<unsigned char>& b_;
  std::size_t pos_ = 0;
};

TEST(CameraFileTest, BallClipIsReadExactlyAsAnIndependentTwelveBitUnpacking) {
  auto src = OpenCameraFile(kPhotron / "ball_12bit.mraw");
  const CameraFileInfo& info = src->info();
  // pyMRAW's shape (15, 384, 384) and the header's facts (README.md of the data).
  EXPECT_EQ(info.format, "photron-mraw");
  EXPECT_EQ(src->count(), 15);
  EXPECT_EQ(info.frame_count, 15);
  EXPECT_EQ(info.height, 384);
  EXPECT_EQ(info.width, 384);
  EXPECT_EQ(info.bit_depth, 12);
  EXPECT_EQ(info.storage_bits, 12);
  EXPECT_EQ(info.fps, 30000.0);
  ASSERT_TRUE(info.shutter_s.has_value());
  EXPECT_NEAR(*info.shutter_s, 20e-6, 1e-15);
  EXPECT_EQ(info.first_frame_number, 52);  // <startFrame>52</startFrame>
  ASSERT_TRUE(info.trigger_time_s.has_value());
  EXPECT_NEAR(*info.trigger_time_s, -52.0 / 30000.0, 1e-15);
  EXPECT_NE(info.camera.find("FASTCAM Nova S16"), std::string::npos);

  const auto raw = Bytes(kPhotron / "ball_12bit.mraw");
  ASSERT_EQ(raw.size(), 15u * 384 * 384 * 3 / 2);
  BitStream bits(raw);
  double sum = 0;
  unsigned lo = 4096, hi = 0;
  long mismatches = 0;
  for (int f = 0; f < 15; ++f) {
    const cv::Mat m = src->Read(f);
    ASSERT_EQ(m.type(), CV_16UC1);
    ASSERT_EQ(m.rows, 384);
    ASSERT_EQ(m.cols, 384);
    for (int y = 0; y < 384; ++y)
      for (int x = 0; x < 384; ++x) {
        const unsigned v = bits.Take(12);
        mismatches += m.at<std::uint16_t>(y, x) != v;
        sum += v;
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_EQ(src->Read(0).at<std::uint16_t>(0, 0), 4095);
  EXPECT_EQ(lo, 84u);
  EXPECT_EQ(hi, 4095u);
  EXPECT_NEAR(sum / (15.0 * 384 * 384), 3493.98, 0.005);
}

TEST(CameraFileTest, BeamClipIsSixteenBitLittleEndian) {
  auto src = OpenCameraFile(kPhotron / "beam.cihx");  // the header names the clip too
  const CameraFileInfo& info = src->info();
  // pyMRAW's (4, 80, 1024): 4 frames of height 80 and width 1024.
  EXPECT_EQ(info.frame_count, 4);
  EXPECT_EQ(info.height, 80);
  EXPECT_EQ(info.width, 1024);
  EXPECT_EQ(info.storage_bits, 16);
  EXPECT_EQ(info.bit_depth, 12);  // <effectiveBit><depth>12</depth>
  EXPECT_EQ(info.fps, 50000.0);
  ASSERT_TRUE(info.shutter_s.has_value());
  EXPECT_NEAR(*info.shutter_s, 5e-6, 1e-15);

  const auto raw = Bytes(kPhotron / "beam.mraw");
  ASSERT_EQ(raw.size(), 4u * 80 * 1024 * 2);
  double sum = 0;
  long mismatches = 0;
  std::size_t k = 0;
  for (int f = 0; f < 4; ++f) {
    const cv::Mat m = src->Read(f);
    ASSERT_EQ(m.type(), CV_16UC1);
    for (int y = 0; y < 80; ++y)
      for (int x = 0; x < 1024; ++x, k += 2) {
        const unsigned v = raw[k] + 256u * raw[k + 1];
        mismatches += m.at<std::uint16_t>(y, x) != v;
        sum += v;
      }
  }
  EXPECT_EQ(mismatches, 0);
  const cv::Mat f0 = src->Read(0);
  EXPECT_EQ(f0.at<std::uint16_t>(0, 0), 76);
  EXPECT_EQ(f0.at<std::uint16_t>(0, 1), 83);
  EXPECT_EQ(f0.at<std::uint16_t>(0, 2), 79);
  EXPECT_EQ(f0.at<std::uint16_t>(0, 3), 63);
  EXPECT_NEAR(sum / (4.0 * 80 * 1024), 770.19, 0.005);
}

TEST(CameraFileTest, FramesReadInAnyOrderAreTheSameAndOneBufferIsReused) {
  auto src = OpenCameraFile(kPhotron / "ball_12bit.mraw");
  std::vector<cv::Mat> forward;
  for (int i = 0; i < src->count(); ++i) forward.push_back(src->Read(i).clone());
  for (const int i : {14, 3, 7, 0, 14, 9, 1}) {
    const cv::Mat m = src->Read(i);
    EXPECT_EQ(cv::norm(m, forward[static_cast<std::size_t>(i)], cv::NORM_INF), 0.0) << i;
  }
  // The source keeps one frame buffer: once the caller lets go of a frame, the next one is
  // read into the same memory; a frame the caller still holds is never overwritten.
  const std::uint8_t* first = src->Read(2).data;
  EXPECT_EQ(src->Read(5).data, first);
  const cv::Mat held = src->Read(6);
  const cv::Mat next = src->Read(7);
  EXPECT_NE(next.data, held.data);
  EXPECT_EQ(cv::norm(held, forward[6], cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(next, forward[7], cv::NORM_INF), 0.0);
}

/// A clip of `n` frames, `w` x `h`, whose values are a seeded random pattern below 2^bits.
std::vector<cv::Mat> Clip(int n, int w, int h, int bits, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> value(0, (1 << bits) - 1);
  std::vector<cv::Mat> frames;
  for (int i = 0; i < n; ++i) {
    cv::Mat m(h, w, bits == 8 ? CV_8U : CV_16U);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        if (bits == 8)
          m.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(value(rng));
        else
          m.at<std::uint16_t>(y, x) = static_cast<std::uint16_t>(value(rng));
      }
    frames.push_back(m);
  }
  return frames;
}

CameraFileSpec Spec(int n, int w, int h, int bits) {
  CameraFileSpec s;
  s.frame_count = n;
  s.width = w;
  s.height = h;
  s.bits = bits;
  s.fps = 8000;
  s.shutter_s = 50e-6;
  s.first_frame_number = -3;
  return s;
}

void WriteMraw(const fs::path& path, const std::vector<cv::Mat>& frames, const CameraFileSpec& s) {
  MrawWriter w(path, s);
  for (const cv::Mat& f : frames) w.Write(f);
  w.Finish();
}

TEST(CameraFileTest, MrawRoundTripsAtEightTwelveAndSixteenBits) {
  const fs::path dir = hoof::testing::FreshDir("camera_mraw_round_trip");
  for (const int bits : {8, 12, 16}) {
    const auto frames = Clip(5, 34, 7, bits, 100u + static_cast<unsigned>(bits));
    const fs::path path = dir / ("clip" + std::to_string(bits) + ".mraw");
    WriteMraw(path, frames, Spec(5, 34, 7, bits));
    // Only the two files, no temporaries left beside them.
    EXPECT_TRUE(fs::exists(fs::path(path).replace_extension(".cihx")));
    auto src = OpenCameraFile(path);
    const CameraFileInfo& info = src->info();
    EXPECT_EQ(info.frame_count, 5);
    EXPECT_EQ(info.width, 34);
    EXPECT_EQ(info.height, 7);
    EXPECT_EQ(info.bit_depth, bits);
    EXPECT_EQ(info.fps, 8000.0);
    ASSERT_TRUE(info.shutter_s.has_value());
    EXPECT_NEAR(*info.shutter_s, 50e-6, 1e-15);
    EXPECT_EQ(info.first_frame_number, -3);
    EXPECT_EQ(fs::file_size(path), 5u * 34 * 7 * static_cast<unsigned>(bits) / 8);
    for (int i = 4; i >= 0; --i) {
      const cv::Mat m = src->Read(i);
      ASSERT_EQ(m.depth(), bits == 8 ? CV_8U : CV_16U);
      EXPECT_EQ(cv::norm(m, frames[static_cast<std::size_t>(i)], cv::NORM_INF), 0.0)
          << bits << " bits, frame " << i;
    }
  }
  int leftovers = 0;
  for (const auto& e : fs::directory_iterator(dir))
    leftovers += e.path().string().find(".tmp-") != std::string::npos;
  EXPECT_EQ(leftovers, 0);
}

TEST(CameraFileTest, TheOldTextHeaderIsRead) {
  const fs::path dir = hoof::testing::FreshDir("camera_cih");
  const auto frames = Clip(3, 8, 4, 16, 7);
  WriteMraw(dir / "clip.mraw", frames, Spec(3, 8, 4, 16));
  fs::remove(dir / "clip.cihx");
  {
    std::ofstream cih(dir / "clip.cih");
    cih << "#Camera Information Header\r\nCamera Type : FASTCAM SA5\r\n"
        << "Record Rate(fps) : 20000\r\nShutter Speed(s) : 1/40000\r\nTotal Frame : 3\r\n"
        << "Start Frame : -1\r\nImage Width : 8\r\nImage Height : 4\r\nColor Type : Mono\r\n"
        << "Color Bit : 16\r\nFile Format : MRaw\r\nEffectiveBit Depth : 12\r\n";
  }
  auto src = OpenCameraFile(dir / "clip.mraw");
  EXPECT_EQ(src->info().fps, 20000.0);
  EXPECT_NEAR(*src->info().shutter_s, 25e-6, 1e-15);
  EXPECT_EQ(src->info().bit_depth, 12);
  EXPECT_EQ(src->info().storage_bits, 16);
  EXPECT_EQ(src->info().first_frame_number, -1);
  EXPECT_EQ(src->info().camera, "FASTCAM SA5");
  EXPECT_EQ(src->info().header, (dir / "clip.cih").string());
  EXPECT_EQ(cv::norm(src->Read(2), frames[2], cv::NORM_INF), 0.0);
}

TEST(CameraFileTest, BadMrawFilesAreRefusedNamingTheFileAndTheFrame) {
  const fs::path dir = hoof::testing::FreshDir("camera_mraw_bad");
  const auto frames = Clip(4, 16, 6, 12, 3);
  WriteMraw(dir / "clip.mraw", frames, Spec(4, 16, 6, 12));
  const auto data = Bytes(dir / "clip.mraw");
  const std::string cihx = hoof::testing::ReadAll(dir / "clip.cihx");
  const int frame_bytes = 16 * 6 * 3 / 2;  // 144
  ASSERT_EQ(data.size(), 4u * frame_bytes);

  // Cut short inside frame 2.
  WriteBytes(dir / "cut.mraw", {data.begin(), data.begin() + 2 * frame_bytes + 10});
  fs::copy_file(dir / "clip.cihx", dir / "cut.cihx");
  ExpectError([&] { OpenCameraFile(dir / "cut.mraw"); }, "cut.mraw: cut short");
  ExpectError([&] { OpenCameraFile(dir / "cut.mraw"); }, "frame 2 is incomplete");

  // A header that says 16 bits for 12-bit data: the size is not that of the header's frames.
  const auto replaced = [&](std::string text, const std::string& from, const std::string& to) {
    EXPECT_NE(text.find(from), std::string::npos) << from;
    for (std::size_t at = text.find(from); at != std::string::npos;
         at = text.find(from, at + to.size()))
      text.replace(at, from.size(), to);
    return text;
  };
  WriteBytes(dir / "depth.mraw", data);
  { std::ofstream(dir / "depth.cihx") << replaced(cihx, "<bit>12</bit>", "<bit>16</bit>"); }
  // 576 bytes hold 3 whole frames of 16 x 6 at 16 bits (192 bytes): frame 3 is incomplete.
  ExpectError([&] { OpenCameraFile(dir / "depth.mraw"); }, "depth.mraw: cut short");
  ExpectError([&] { OpenCameraFile(dir / "depth.mraw"); }, "frame 3 is incomplete");
  ExpectError([&] { OpenCameraFile(dir / "depth.mraw"); },
              "the size is exactly that of 4 frames at 12 bits");
  // ... and one that says 8 bits: more data than the header's frames.
  {
    std::ofstream(dir / "depth.cihx") << replaced(replaced(cihx, "<bit>12</bit>", "<bit>8</bit>"),
                                                  "<depth>12</depth>", "<depth>8</depth>");
  }
  ExpectError([&] { OpenCameraFile(dir / "depth.mraw"); },
              "the header's size or bit depth disagrees with the data");
  // A header with fewer frames than the data.
  WriteBytes(dir / "count.mraw", data);
  {
    std::ofstream(dir / "count.cihx")
        << replaced(cihx, "<totalFrame>4</totalFrame>", "<totalFrame>3</totalFrame>");
  }
  ExpectError([&] { OpenCameraFile(dir / "count.mraw"); }, "count.mraw: the header (count.cihx)");
  // An unknown bit depth.
  WriteBytes(dir / "odd.mraw", data);
  { std::ofstream(dir / "odd.cihx") << replaced(cihx, "<bit>12</bit>", "<bit>10</bit>"); }
  ExpectError([&] { OpenCameraFile(dir / "odd.mraw"); },
              "odd.cihx: bit depth 10 is not one this reader knows");
  // A missing header, a missing field, and the frames missing beside a header.
  WriteBytes(dir / "alone.mraw", data);
  ExpectError([&] { OpenCameraFile(dir / "alone.mraw"); },
              "alone.mraw: its camera header is missing (looked for alone.cihx and alone.cih");
  { std::ofstream(dir / "norate.cihx") << replaced(cihx, "<recordRate>8000</recordRate>", ""); }
  WriteBytes(dir / "norate.mraw", data);
  ExpectError([&] { OpenCameraFile(dir / "norate.mraw"); },
              "norate.cihx: recordInfo/recordRate is missing");
  // A frame rate no camera has: one frame in 10^6 s makes every time the clip gives enormous.
  { std::ofstream(dir / "slow.cihx") << replaced(cihx, "<recordRate>8000<", "<recordRate>1e-6<"); }
  WriteBytes(dir / "slow.mraw", data);
  ExpectError([&] { OpenCameraFile(dir / "slow.mraw"); },
              "slow.cihx: frame rate 1e-06 fps is not within 0.001 to 1e+09");
  fs::copy_file(dir / "clip.cihx", dir / "lonely.cihx");
  ExpectError([&] { OpenCameraFile(dir / "lonely.cihx"); }, "no lonely.mraw beside it");
  // A hostile header asking for a huge frame is refused before any allocation.
  WriteBytes(dir / "huge.mraw", data);
  {
    std::ofstream(dir / "huge.cihx")
        << replaced(replaced(cihx, "<width>16</width>", "<width>65536</width>"),
                    "<height>6</height>", "<height>65536</height>");
  }
  ExpectError([&] { OpenCameraFile(dir / "huge.mraw"); }, "huge.cihx: image size");
}

// --- Phantom CINE ------------------------------------------------------------------------------

/// Little-endian fields of a byte buffer, read here byte by byte (the reader uses memcpy).
std::uint64_t Le(const std::vector<unsigned char>& b, std::size_t at, int bytes) {
  std::uint64_t v = 0;
  for (int k = bytes - 1; k >= 0; --k) v = (v << 8) | b[at + static_cast<std::size_t>(k)];
  return v;
}
std::int64_t LeSigned32(const std::vector<unsigned char>& b, std::size_t at) {
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(Le(b, at, 4)));
}

/// What the test reads from a CINE file itself: the header fields and image 0's pixels.
struct CineFacts {
  std::int64_t first_image = 0;
  std::uint64_t count = 0, width = 0, height = 0, frame_rate = 0, real_bpp = 0, flip_v = 0;
  cv::Mat image0;  // top row first
};

CineFacts ParseCineHere(const fs::path& p) {
  const auto b = Bytes(p);
  CineFacts f;
  EXPECT_EQ(b[0], 'C');
  EXPECT_EQ(b[1], 'I');
  f.first_image = LeSigned32(b, 16);
  f.count = Le(b, 20, 4);
  const std::size_t bmp = Le(b, 24, 4), setup = Le(b, 28, 4), table = Le(b, 32, 4);
  f.width = Le(b, bmp + 4, 4);
  f.height = Le(b, bmp + 8, 4);
  EXPECT_EQ(Le(b, bmp + 14, 2), 16u);  // 16 bits per pixel in storage
  f.frame_rate = Le(b, setup + 768, 4);
  f.flip_v = Le(b, setup + 760, 4);
  f.real_bpp = Le(b, setup + 896, 4);
  const std::size_t image = Le(b, table, 8);
  const std::size_t pixels = image + Le(b, image, 4);
  f.image0 = cv::Mat(static_cast<int>(f.height), static_cast<int>(f.width), CV_16U);
  for (std::size_t r = 0; r < f.height; ++r) {
    // Rows are stored bottom first unless the setup's vertical flip is set.
    const std::size_t y = f.flip_v ? r : f.height - 1 - r;
    for (std::size_t x = 0; x < f.width; ++x)
      f.image0.at<std::uint16_t>(static_cast<int>(y), static_cast<int>(x)) =
          static_cast<std::uint16_t>(Le(b, pixels + 2 * (r * f.width + x), 2));
  }
  return f;
}

TEST(CameraFileTest, LegacyCineAgreesWithAnIndependentParseOfItsHeader) {
  const fs::path path = kPhantom / "cine_legacy.cine";
  const CineFacts here = ParseCineHere(path);
  auto src = OpenCameraFile(path);
  const CameraFileInfo& info = src->info();
  // PIMS: opens, 97 frames, a non-zero frame rate, two-dimensional frames.
  EXPECT_EQ(src->count(), 97);
  EXPECT_GT(info.fps, 0);
  EXPECT_EQ(src->Read(0).dims, 2);
  // The README's facts and the test's own parse.
  EXPECT_EQ(info.format, "phantom-cine");
  EXPECT_EQ(here.count, 97u);
  EXPECT_EQ(static_cast<std::uint64_t>(info.frame_count), here.count);
  EXPECT_EQ(info.width, 128);
  EXPECT_EQ(info.height, 128);
  EXPECT_EQ(static_cast<std::uint64_t>(info.width), here.width);
  EXPECT_EQ(info.first_frame_number, -7722);
  EXPECT_EQ(info.first_frame_number, here.first_image);
  EXPECT_EQ(here.frame_rate, 35087u);
  EXPECT_EQ(info.fps, 35087.0);
  EXPECT_EQ(info.decimation, 1);
  EXPECT_EQ(here.real_bpp, 14u);
  EXPECT_EQ(info.bit_depth, 14);
  EXPECT_EQ(info.storage_bits, 16);
  ASSERT_TRUE(info.shutter_s.has_value());
  EXPECT_NEAR(*info.shutter_s, 1e-6, 1e-15);
  // The trigger from the time stamps agrees with image number / rate (image 0 is the trigger).
  ASSERT_TRUE(info.trigger_time_s.has_value());
  // (The trigger falls somewhere within a frame period, and the stamps hold the camera's
  // clock: agreement within two periods.)
  EXPECT_NEAR(*info.trigger_time_s, 7722.0 / 35087.0, 2.0 / 35087.0);
  // Time stamps, one per image, about 1/35087 s apart.
  ASSERT_TRUE(src->TimeOf(96).has_value());
  EXPECT_EQ(*src->TimeOf(0), 0.0);
  EXPECT_NEAR(*src->TimeOf(96) / 96.0, 1.0 / 35087.0, 1e-9);
  const cv::Mat f0 = src->Read(0);
  ASSERT_EQ(f0.type(), CV_16UC1);
  EXPECT_EQ(cv::norm(f0, here.image0, cv::NORM_INF), 0.0);
  double hi = 0;
  cv::minMaxLoc(f0, nullptr, &hi);
  EXPECT_LT(hi, 1 << 14);  // 14 significant bits
}

TEST(CameraFileTest, DecimatedCineGivesTheRateOfItsSavedImages) {
  const fs::path path = kPhantom / "cine_781.cine";
  const CineFacts here = ParseCineHere(path);
  auto src = OpenCameraFile(path);
  const CameraFileInfo& info = src->info();
  EXPECT_EQ(src->count(), 15);
  EXPECT_EQ(static_cast<std::uint64_t>(info.frame_count), here.count);
  EXPECT_EQ(info.width, 256);
  EXPECT_EQ(info.height, 256);
  EXPECT_EQ(info.first_frame_number, -5417);
  EXPECT_EQ(info.first_frame_number, here.first_image);
  // Recorded at 90 000 fps, saved keeping one image in ten (the PIMS test's comment).
  EXPECT_EQ(here.frame_rate, 90000u);
  EXPECT_EQ(info.recording_fps, 90000.0);
  EXPECT_EQ(info.decimation, 10);
  EXPECT_EQ(info.fps, 9000.0);
  EXPECT_EQ(info.bit_depth, 12);
  EXPECT_EQ(static_cast<std::uint64_t>(info.bit_depth), here.real_bpp);
  ASSERT_TRUE(info.shutter_s.has_value());
  EXPECT_NEAR(*info.shutter_s, 10e-6, 1e-15);
  // The time stamps agree with 9000 fps within 0.1 % (the camera's clock: 9003 fps).
  ASSERT_TRUE(src->TimeOf(14).has_value());
  EXPECT_NEAR(*src->TimeOf(14) * 9000.0 / 14.0, 1.0, 1e-3);
  ASSERT_TRUE(info.trigger_time_s.has_value());
  EXPECT_NEAR(*info.trigger_time_s * 9000.0 / 5417.0, 1.0, 1e-3);
  for (int i = 0; i < 15; ++i) EXPECT_EQ(src->Read(i).dims, 2);
  EXPECT_EQ(cv::norm(src->Read(0), here.image0, cv::NORM_INF), 0.0);
}

TEST(CameraFileTest, CineRoundTripsAtEightTwelveAndSixteenBitsWithTimeStamps) {
  const fs::path dir = hoof::testing::FreshDir("camera_cine_round_trip");
  for (const int bits : {8, 12, 16}) {
    const auto frames = Clip(4, 12, 5, bits, 200u + static_cast<unsigned>(bits));
    const fs::path path = dir / ("clip" + std::to_string(bits) + ".cine");
    CameraFileSpec spec = Spec(4, 12, 5, bits);
    spec.times_s = {0.0, 125e-6, 375e-6, 500e-6};  // frame 2 came late: a dropped frame
    CineWriter w(path, spec);
    for (const cv::Mat& f : frames) w.Write(f);
    w.Finish();
    auto src = OpenCameraFile(path);
    EXPECT_EQ(src->info().frame_count, 4);
    EXPECT_EQ(src->info().bit_depth, bits);
    EXPECT_EQ(src->info().fps, 8000.0);
    EXPECT_EQ(src->info().first_frame_number, -3);
    // Frame 0 is image -3: the trigger came 3 frame periods after it.
    EXPECT_NEAR(*src->info().trigger_time_s, 3.0 / 8000.0, 2e-9);
    EXPECT_NEAR(*src->info().shutter_s, 50e-6, 1e-15);
    for (int i = 3; i >= 0; --i) {
      EXPECT_EQ(cv::norm(src->Read(i), frames[static_cast<std::size_t>(i)], cv::NORM_INF), 0.0)
          << bits << " bits, frame " << i;
      // TIME64 resolves 2^-32 s; its two lowest bits are flags.
      EXPECT_NEAR(*src->TimeOf(i), spec.times_s[static_cast<std::size_t>(i)], 2e-9);
    }
  }
}

TEST(CameraFileTest, BadCineFilesAreRefusedNamingTheFile) {
  const fs::path dir = hoof::testing::FreshDir("camera_cine_bad");
  const auto frames = Clip(3, 8, 4, 16, 9);
  {
    CineWriter w(dir / "good.cine", Spec(3, 8, 4, 16));
    for (const cv::Mat& f : frames) w.Write(f);
    w.Finish();
  }
  const auto good = Bytes(dir / "good.cine");
  auto bad = good;
  bad[0] = 'X';
  WriteBytes(dir / "magic.cine", bad);
  ExpectError([&] { OpenCameraFile(dir / "magic.cine"); }, "magic.cine: not a Phantom CINE file");
  // The offset of image 1 pointed past the end.
  bad = good;
  const std::size_t table = Le(good, 32, 4);
  for (int k = 0; k < 8; ++k) bad[table + 8 + static_cast<std::size_t>(k)] = k < 4 ? 0xff : 0;
  WriteBytes(dir / "offset.cine", bad);
  ExpectError([&] { OpenCameraFile(dir / "offset.cine"); },
              "offset.cine: image 1 (frame 1) lies at byte 4294967295, past the end");
  // Cut short inside the last image.
  WriteBytes(dir / "cut.cine", {good.begin(), good.end() - 20});
  ExpectError([&] { OpenCameraFile(dir / "cut.cine"); }, "cut.cine: image 2 (frame 2)");
  // A table of offsets longer than the file.
  bad = good;
  bad[20] = 0xff;
  bad[21] = 0xff;
  bad[22] = 0xff;
  bad[23] = 0x0f;
  WriteBytes(dir / "count.cine", bad);
  ExpectError([&] { OpenCameraFile(dir / "count.cine"); }, "runs past the end of the file");
  // 10-bit packed: refused, saying why.
  bad = good;
  bad[44 + 16] = 0x00;
  bad[44 + 17] = 0x01;  // biCompression 256
  WriteBytes(dir / "p10.cine", bad);
  ExpectError([&] { OpenCameraFile(dir / "p10.cine"); }, "p10.cine: holds 10-bit packed images");
  // An annotation that leaves no room for the pixels is found when the frame is read.
  bad = good;
  const std::size_t image0 = Le(good, table, 8);
  bad[image0] = 0xff;
  bad[image0 + 1] = 0xff;
  WriteBytes(dir / "annotation.cine", bad);
  auto src = OpenCameraFile(dir / "annotation.cine");
  ExpectError([&] { src->Read(0); }, "annotation.cine: frame 0 has an annotation of 65535 bytes");
  EXPECT_EQ(cv::norm(src->Read(1), frames[1], cv::NORM_INF), 0.0);
  // A vanishing recorded rate (the smallest double) that the decimation divides to zero: found
  // by libFuzzer; a zero rate would make every time the clip gives infinite.
  bad = good;
  const std::size_t setup = Le(good, 28, 4);
  const double tiny = std::numeric_limits<double>::denorm_min();
  const float two = 2.0f;
  std::memcpy(bad.data() + setup + 10400, &tiny, sizeof tiny);  // FrameRate (double)
  std::memcpy(bad.data() + setup + 10388, &two, sizeof two);    // decimation (float)
  WriteBytes(dir / "rate.cine", bad);
  ExpectError([&] { OpenCameraFile(dir / "rate.cine"); },
              "rate.cine: its setup block's frame rate: 0 fps is not within 0.001 to 1e+09 "
              "(recorded at 4.94066e-324 fps, one image in 2 kept)");
  // Every one-byte truncation of the headers is an error, never a crash.
  for (std::size_t n = 0; n < 200; n += 7) {
    WriteBytes(dir / "short.cine", {good.begin(), good.begin() + static_cast<std::ptrdiff_t>(n)});
    ExpectError([&] { OpenCameraFile(dir / "short.cine"); }, "short.cine");
  }
}

// --- TIFF --------------------------------------------------------------------------------------

void WriteTiff(const fs::path& path, const std::vector<cv::Mat>& pages) {
  TIFF* t = TIFFOpen(path.c_str(), "w");
  ASSERT_NE(t, nullptr);
  for (const cv::Mat& m : pages) {
    TIFFSetField(t, TIFFTAG_IMAGEWIDTH, static_cast<std::uint32_t>(m.cols));
    TIFFSetField(t, TIFFTAG_IMAGELENGTH, static_cast<std::uint32_t>(m.rows));
    TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, static_cast<std::uint16_t>(m.elemSize1() * 8));
    TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, static_cast<std::uint16_t>(1));
    TIFFSetField(t, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
    TIFFSetField(t, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
    TIFFSetField(t, TIFFTAG_COMPRESSION, COMPRESSION_ADOBE_DEFLATE);
    TIFFSetField(t, TIFFTAG_ROWSPERSTRIP, static_cast<std::uint32_t>(3));
    for (int y = 0; y < m.rows; ++y)
      ASSERT_GE(
          TIFFWriteScanline(t, const_cast<uchar*>(m.ptr(y)), static_cast<std::uint32_t>(y), 0), 0);
    TIFFWriteDirectory(t);
  }
  TIFFClose(t);
}

TEST(CameraFileTest, MultiPageSixteenBitTiffIsReadPageByPage) {
  const fs::path dir = hoof::testing::FreshDir("camera_tiff");
  for (const int bits : {8, 16}) {
    const auto pages = Clip(6, 21, 9, bits, 300u + static_cast<unsigned>(bits));
    const fs::path path = dir / ("clip" + std::to_string(bits) + ".tif");
    WriteTiff(path, pages);
    auto src = OpenCameraFile(path);
    EXPECT_EQ(src->info().format, "tiff");
    EXPECT_EQ(src->count(), 6);
    EXPECT_EQ(src->info().width, 21);
    EXPECT_EQ(src->info().height, 9);
    EXPECT_EQ(src->info().bit_depth, bits);
    EXPECT_TRUE(std::isnan(src->info().fps));
    for (const int i : {5, 0, 3, 1, 4, 2}) {
      const cv::Mat m = src->Read(i);
      ASSERT_EQ(m.depth(), bits == 8 ? CV_8U : CV_16U);
      EXPECT_EQ(cv::norm(m, pages[static_cast<std::size_t>(i)], cv::NORM_INF), 0.0) << i;
    }
  }
  // A page of another size is refused naming the page; the others still read.
  auto pages = Clip(3, 10, 6, 16, 5);
  pages[1] = Clip(1, 12, 6, 16, 6)[0];
  WriteTiff(dir / "mixed.tiff", pages);
  auto src = OpenCameraFile(dir / "mixed.tiff");
  ExpectError([&] { src->Read(1); }, "mixed.tiff page 1 (frame 1) is 12 x 6");
  EXPECT_EQ(cv::norm(src->Read(2), pages[2], cv::NORM_INF), 0.0);
  // A 110-byte TIFF whose page claims 30000 x 30000 16-bit pixels: refused before a 1.8 GB
  // frame is allocated.
  {
    std::vector<unsigned char> t = {'I', 'I', 42, 0, 8, 0, 0, 0};
    const auto u16 = [&](unsigned v) {
      t.push_back(static_cast<unsigned char>(v & 0xff));
      t.push_back(static_cast<unsigned char>(v >> 8));
    };
    const auto u32 = [&](std::uint32_t v) {
      u16(v & 0xffff);
      u16(v >> 16);
    };
    const auto entry = [&](unsigned tag, unsigned type, std::uint32_t value) {
      u16(tag);
      u16(type);
      u32(1);
      if (type == 3) {
        u16(value);
        u16(0);
      } else {
        u32(value);
      }
    };
    u16(8);
    entry(256, 4, 30000);       // ImageWidth
    entry(257, 4, 30000);       // ImageLength
    entry(258, 3, 16);          // BitsPerSample
    entry(259, 3, 1);           // Compression: none
    entry(262, 3, 1);           // Photometric: black is zero
    entry(273, 4, 8);           // StripOffsets
    entry(278, 4, 30000);       // RowsPerStrip
    entry(279, 4, 1800000000);  // StripByteCounts
    u32(0);
    WriteBytes(dir / "claims.tif", t);
  }
  ExpectError([&] { OpenCameraFile(dir / "claims.tif"); },
              "claims.tif page 0 (frame 0): claims 30000 x 30000 pixels, far more than its");
  // Not a TIFF at all.
  WriteBytes(dir / "junk.tif", {'n', 'o', 't', ' ', 'a', ' ', 't', 'i', 'f', 'f'});
  ExpectError([&] { OpenCameraFile(dir / "junk.tif"); }, "junk.tif: not a readable TIFF file");
}

TEST(CameraFileTest, ARangeOfAClipIsRenumberedFromZero) {
  auto whole = OpenCameraFile(kPhotron / "ball_12bit.mraw");
  const cv::Mat f7 = whole->Read(7).clone();
  FrameRangeSource range(OpenCameraFile(kPhotron / "ball_12bit.mraw"), 5, 4);
  EXPECT_EQ(range.count(), 4);
  EXPECT_EQ(cv::norm(range.Read(2), f7, cv::NORM_INF), 0.0);
  EXPECT_NE(range.Describe(2).find("ball_12bit.mraw frame 7"), std::string::npos);
  ExpectError([&] { FrameRangeSource(OpenCameraFile(kPhotron / "ball_12bit.mraw"), 10, 6); },
              "frames 10 to 15 are not within the 15 frames of the clip");
  EXPECT_FALSE(range.TimeOf(0).has_value());  // an MRAW has no per-frame time stamps
  // A range of a CINE keeps its time stamps, counted from the range's first frame (the real
  // 2019 file, whose camera clock gives 9003 fps).
  auto cine = OpenCameraFile(kPhantom / "cine_781.cine");
  FrameRangeSource cine_range(OpenCameraFile(kPhantom / "cine_781.cine"), 5, 4);
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(cine_range.TimeOf(i).has_value()) << i;
    EXPECT_EQ(*cine_range.TimeOf(i), *cine->TimeOf(5 + i) - *cine->TimeOf(5)) << i;
  }
  EXPECT_EQ(*cine_range.TimeOf(0), 0.0);
  EXPECT_NEAR(*cine_range.TimeOf(3) * 9003.0 / 3.0, 1.0, 1e-3);
  EXPECT_FALSE(cine_range.TimeOf(4).has_value());
}

TEST(CameraFileTest, RecognisesCameraFilesByExtension) {
  for (const char* name : {"a.mraw", "a.MRAW", "a.cih", "a.cihx", "b.cine", "c.tif", "c.TIFF"})
    EXPECT_TRUE(IsCameraFile(name)) << name;
  for (const char* name : {"a.avi", "a.png", "a", "mraw", "a.cin"})
    EXPECT_FALSE(IsCameraFile(name)) << name;
}

}  // namespace
}  // namespace hoof::tracking
