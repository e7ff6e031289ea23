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
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

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

TEST(CameraFileTest, RecognisesCameraFilesByExtension) {
  for (const char* name : {"a.mraw", "a.MRAW", "a.cih", "a.cihx", "b.cine", "c.tif", "c.TIFF"})
    EXPECT_TRUE(IsCameraFile(name)) << name;
  for (const char* name : {"a.avi", "a.png", "a", "mraw", "a.cin"})
    EXPECT_FALSE(IsCameraFile(name)) << name;
}

}  // namespace
}  // namespace hoof::tracking
