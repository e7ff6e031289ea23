#include "tracking/motion_blobs.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/imgproc.hpp>

#include "tracking/frame_differences.h"
#include "tracking/frame_timing.h"
#include "tracking/read_ahead.h"

namespace hoof::tracking {
namespace {

double MedianOf(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

/// The working size: `options.work_width_px` wide at most, the frame's aspect kept.
cv::Size WorkSize(const cv::Size& full, const MotionOptions& options) {
  if (full.width <= options.work_width_px) return full;
  const double s = static_cast<double>(options.work_width_px) / full.width;
  return {options.work_width_px, std::max(1, static_cast<int>(std::lround(full.height * s)))};
}

/// The robust noise of a likeness image: its median and 1.4826 x its median absolute deviation,
/// from a grid of at most about 20000 pixels.
std::pair<double, double> LikenessNoise(const cv::Mat& L) {
  const int step =
      std::max(1, static_cast<int>(std::sqrt(static_cast<double>(L.total()) / 20000.0)));
  std::vector<double> v;
  for (int y = 0; y < L.rows; y += step) {
    const auto* row = L.ptr<std::uint8_t>(y);
    for (int x = 0; x < L.cols; x += step) v.push_back(row[x]);
  }
  const double med = MedianOf(v);
  for (double& x : v) x = std::abs(x - med);
  return {med, 1.4826 * MedianOf(v)};
}

/// The median of the m = `row.size()` bytes at each of the `n` positions of the rows `row`, into
/// `out`: the element at sorted index `half` = m / 2, which is the largest value v with at most
/// m / 2 of the m bytes below v. It is built bit by bit from the top, counting at each bit the
/// bytes below the value tried, for 64 positions at once in OpenCV's universal intrinsics (a
/// per-position nth_element took 4 to 8 times as long on a 1080p clip); m <= 255.
void MedianOfRows(const std::vector<const std::uint8_t*>& row, std::uint8_t half, int n,
                  std::uint8_t* out) {
  int x = 0;
#if CV_SIMD128
  constexpr int kLanes = 16, kVectors = 4;
  const cv::v_uint8x16 one = cv::v_setall_u8(1), at_most = cv::v_setall_u8(half);
  for (; x + kLanes * kVectors <= n; x += kLanes * kVectors) {
    cv::v_uint8x16 value[kVectors], trial[kVectors], below[kVectors];
    for (auto& v : value) v = cv::v_setzero_u8();
    for (int bit = 128; bit > 0; bit >>= 1) {
      const cv::v_uint8x16 b = cv::v_setall_u8(static_cast<std::uint8_t>(bit));
      for (int k = 0; k < kVectors; ++k) {
        trial[k] = value[k] | b;
        below[k] = cv::v_setzero_u8();
      }
      for (const std::uint8_t* r : row)
        for (int k = 0; k < kVectors; ++k)
          below[k] += (cv::v_load(r + x + kLanes * k) < trial[k]) & one;
      for (int k = 0; k < kVectors; ++k)
        value[k] = cv::v_select(below[k] <= at_most, trial[k], value[k]);
    }
    for (int k = 0; k < kVectors; ++k) cv::v_store(out + x + kLanes * k, value[k]);
  }
#endif
  for (; x < n; ++x) {
    int value = 0;
    for (int bit = 128; bit > 0; bit >>= 1) {
      const int trial = value | bit;
      int below = 0;
      for (const std::uint8_t* r : row) below += r[x] < trial ? 1 : 0;
      if (below <= half) value = trial;
    }
    out[x] = static_cast<std::uint8_t>(value);
  }
}

}  // namespace

void MotionOptions::Validate() const {
  auto fail = [](const std::string& field, const std::string& rule) {
    throw std::invalid_argument("MotionOptions." + field + " " + rule);
  };
  if (background_frames < 3 || background_frames > 255)
    fail("background_frames", "must be in [3, 255]");
  if (work_width_px < 64) fail("work_width_px", "must be >= 64");
  if (!(noise_sigmas > 0)) fail("noise_sigmas", "must be > 0");
  if (!(min_likeness > 0)) fail("min_likeness", "must be > 0");
  if (!(min_area_fraction > 0 && min_area_fraction < 1))
    fail("min_area_fraction", "must be in (0, 1)");
  if (max_regions < 1) fail("max_regions", "must be >= 1");
  if (!(link_sizes > 0)) fail("link_sizes", "must be > 0");
  if (!(link_size_ratio > 1)) fail("link_size_ratio", "must be > 1");
  if (max_gap_frames < 0) fail("max_gap_frames", "must be >= 0");
  if (thumbnail_px < 0) fail("thumbnail_px", "must be >= 0");
  if (timing_grid_pixels < 1) fail("timing_grid_pixels", "must be >= 1");
}

cv::Size ThumbnailSize(const cv::Size& full, int longest_px) {
  const double zoom =
      std::min(1.0, static_cast<double>(longest_px) / std::max({full.width, full.height, 1}));
  return {std::max(1, static_cast<int>(full.width * zoom)),
          std::max(1, static_cast<int>(full.height * zoom))};
}

cv::Mat ToBgr8(const cv::Mat& image, const std::string& what) {
  if (image.empty()) throw std::runtime_error(what + ": empty image");
  cv::Mat eight;
  if (image.depth() == CV_8U) {
    eight = image;
  } else if (image.depth() == CV_16U || image.depth() == CV_32F || image.depth() == CV_64F) {
    cv::Mat grey = image.channels() == 1 ? image : ToGrey(image, what);
    const auto [lo, hi] = FrameLevels(grey);
    const double span = hi > lo ? hi - lo : 1.0;
    image.convertTo(eight, CV_8U, 255.0 / span, -lo * 255.0 / span);
  } else {
    throw std::runtime_error(what + ": unsupported image depth");
  }
  cv::Mat bgr;
  switch (eight.channels()) {
    case 1:
      cv::cvtColor(eight, bgr, cv::COLOR_GRAY2BGR);
      return bgr;
    case 3:
      return eight;
    case 4:
      cv::cvtColor(eight, bgr, cv::COLOR_BGRA2BGR);
      return bgr;
    default:
      throw std::runtime_error(what + ": unsupported number of channels");
  }
}

cv::Mat Likeness(const cv::Mat& frame, const cv::Mat& background) {
  CV_Assert(frame.type() == CV_8UC3 && background.type() == CV_8UC3 &&
            frame.size() == background.size());
  cv::Mat out(frame.size(), CV_8UC1);
  for (int y = 0; y < frame.rows; ++y) {
    const auto* f = frame.ptr<std::uint8_t>(y);
    const auto* b = background.ptr<std::uint8_t>(y);
    auto* o = out.ptr<std::uint8_t>(y);
    for (int x = 0; x < frame.cols; ++x, f += 3, b += 3) {
      const float i0 = f[0], i1 = f[1], i2 = f[2], b0 = b[0], b1 = b[1], b2 = b[2];
      const float bb = b0 * b0 + b1 * b1 + b2 * b2 + 1.0f;
      const float g =
          std::clamp((i0 * b0 + i1 * b1 + i2 * b2) / bb, static_cast<float>(kShadowGainMin),
                     static_cast<float>(kShadowGainMax));
      const float d0 = i0 - g * b0, d1 = i1 - g * b1, d2 = i2 - g * b2;
      o[x] = cv::saturate_cast<std::uint8_t>(std::sqrt(d0 * d0 + d1 * d1 + d2 * d2));
    }
  }
  return out;
}

cv::Mat MedianBackground(FrameSource& source, const MotionOptions& options,
                         const std::function<void(int)>& progress) {
  options.Validate();
  const int n = source.count();
  const int k = std::min(n, options.background_frames);
  std::vector<int> picks;
  for (int i = 0; i < k; ++i)
    picks.push_back(k == 1 ? 0 : static_cast<int>(std::lround(i * (n - 1.0) / (k - 1.0))));
  picks.erase(std::unique(picks.begin(), picks.end()), picks.end());
  std::vector<cv::Mat> frames;
  for (int f : picks) {
    frames.push_back(ToBgr8(source.ReadColour(f), source.Describe(f)));
    if (frames.back().size() != frames.front().size())
      throw std::runtime_error(source.Describe(f) + ": its size differs from frame " +
                               std::to_string(picks.front()) + "'s");
    if (progress) progress(f);
  }
  const cv::Size size = frames.front().size();
  cv::Mat out(size, CV_8UC3);
  const int m = static_cast<int>(frames.size());
  const auto half = static_cast<std::uint8_t>(m / 2);
  // On the calling thread: a tenth of a second for 41 frames of 1080p, and nothing handed
  // between threads that ThreadSanitizer cannot follow (OpenCV's pool is TBB's).
  std::vector<const std::uint8_t*> row(static_cast<std::size_t>(m));
  for (int y = 0; y < size.height; ++y) {
    for (int i = 0; i < m; ++i) row[static_cast<std::size_t>(i)] = frames[i].ptr<std::uint8_t>(y);
    MedianOfRows(row, half, 3 * size.width, out.ptr<std::uint8_t>(y));
  }
  return out;
}

double MotionPath::Travel() const {
  double t = 0;
  for (const auto& r : regions) t = std::max(t, (r.p_I - regions.front().p_I).norm());
  return t;
}

double MotionPath::MedianDiameter() const {
  std::vector<double> d;
  for (const auto& r : regions) d.push_back(r.diameter_px);
  return MedianOf(d);
}

Eigen::Vector3d MotionPath::MedianRgb() const {
  Eigen::Vector3d out;
  for (int c = 0; c < 3; ++c) {
    std::vector<double> v;
    for (const auto& r : regions) v.push_back(r.rgb[c]);
    out[c] = MedianOf(v);
  }
  return out;
}

double MotionPath::MedianLikeness() const {
  std::vector<double> v;
  for (const auto& r : regions) v.push_back(r.likeness);
  return MedianOf(v);
}

namespace {

/// The regions of one frame (`frame`, full size; `small`, the frame at the working size of
/// `small_background`) that differ from the background.
std::vector<MotionRegion> RegionsOf(const cv::Mat& frame, const cv::Mat& small,
                                    const cv::Mat& background, const cv::Mat& small_background,
                                    int index, const MotionOptions& options, double& noise) {
  const cv::Mat L = Likeness(small, small_background);
  const auto [med, sd] = LikenessNoise(L);
  noise = sd;
  const double threshold = std::max(options.min_likeness, med + options.noise_sigmas * sd);
  cv::Mat mask = L > threshold;
  const cv::Mat k3 = cv::getStructuringElement(cv::MORPH_ELLIPSE, {3, 3});
  cv::morphologyEx(mask, mask, cv::MORPH_OPEN, k3);
  cv::morphologyEx(mask, mask, cv::MORPH_CLOSE, k3);
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8, CV_32S);
  const double min_area =
      std::max(4.0, options.min_area_fraction * static_cast<double>(small.total()));
  // Sums of colour and likeness per label, in one pass.
  std::vector<Eigen::Vector4d> sums(static_cast<std::size_t>(n), Eigen::Vector4d::Zero());
  std::vector<Eigen::Vector3d> second(static_cast<std::size_t>(n), Eigen::Vector3d::Zero());
  for (int y = 0; y < small.rows; ++y) {
    const auto* lab = labels.ptr<int>(y);
    const auto* px = small.ptr<std::uint8_t>(y);
    const auto* l = L.ptr<std::uint8_t>(y);
    for (int x = 0; x < small.cols; ++x)
      if (lab[x] > 0) {
        const auto k = static_cast<std::size_t>(lab[x]);
        sums[k] += Eigen::Vector4d(px[3 * x + 2], px[3 * x + 1], px[3 * x], l[x]);
        second[k] += Eigen::Vector3d(static_cast<double>(x) * x, static_cast<double>(x) * y,
                                     static_cast<double>(y) * y);
      }
  }
  const double sx = static_cast<double>(frame.cols) / small.cols;
  const double sy = static_cast<double>(frame.rows) / small.rows;
  std::vector<MotionRegion> out;
  for (int i = 1; i < n; ++i) {
    const int area = stats.at<int>(i, cv::CC_STAT_AREA);
    if (area < min_area) continue;
    const int bx = stats.at<int>(i, cv::CC_STAT_LEFT), by = stats.at<int>(i, cv::CC_STAT_TOP);
    const int bw = stats.at<int>(i, cv::CC_STAT_WIDTH), bh = stats.at<int>(i, cv::CC_STAT_HEIGHT);
    MotionRegion r;
    r.frame = index;
    r.p_I = {(centroids.at<double>(i, 0) + 0.5) * sx - 0.5,
             (centroids.at<double>(i, 1) + 0.5) * sy - 0.5};
    r.area_px = area * sx * sy;
    r.diameter_px = std::sqrt(4 * r.area_px / M_PI);
    r.fill = static_cast<double>(area) / (static_cast<double>(bw) * bh);
    r.aspect = static_cast<double>(std::max(bw, bh)) / std::max(1, std::min(bw, bh));
    const Eigen::Vector4d s = sums[static_cast<std::size_t>(i)] / area;
    r.rgb = s.head<3>();
    r.likeness = s[3];
    r.touches_border = bx <= 0 || by <= 0 || bx + bw >= small.cols || by + bh >= small.rows;
    {
      const double cx = centroids.at<double>(i, 0), cy = centroids.at<double>(i, 1);
      const Eigen::Vector3d m = second[static_cast<std::size_t>(i)] / area;
      // Central moments, plus a pixel's own 1/12, scaled to full size.
      r.moments << (m[0] - cx * cx + 1.0 / 12) * sx * sx, (m[1] - cx * cy) * sx * sy,
          (m[1] - cx * cy) * sx * sy, (m[2] - cy * cy + 1.0 / 12) * sy * sy;
    }
    out.push_back(r);
  }
  std::sort(out.begin(), out.end(),
            [](const MotionRegion& a, const MotionRegion& b) { return a.area_px > b.area_px; });
  if (out.size() > static_cast<std::size_t>(options.max_regions))
    out.resize(static_cast<std::size_t>(options.max_regions));
  // The full-size pixels around each region, for the sub-pixel measurement.
  const cv::Rect whole(0, 0, frame.cols, frame.rows);
  for (auto& r : out) {
    if (r.area_px > static_cast<double>(frame.total()) / 16) continue;
    const double half = 1.2 * r.diameter_px + 16;
    const cv::Rect box =
        cv::Rect(static_cast<int>(std::floor(r.p_I.x() - half)),
                 static_cast<int>(std::floor(r.p_I.y() - half)),
                 static_cast<int>(std::ceil(2 * half)), static_cast<int>(std::ceil(2 * half))) &
        whole;
    if (box.width < 8 || box.height < 8) continue;
    r.crop = box;
    r.crop_bgr = frame(box).clone();
    r.crop_background = background(box);
  }
  return out;
}

struct Active {
  MotionPath path;
  Eigen::Vector2d v{0, 0};  ///< px per frame
};

}  // namespace

MotionScene FindMotion(FrameSource& source, const cv::Mat& background, const MotionOptions& options,
                       const std::function<void(int)>& progress) {
  options.Validate();
  if (background.empty() || background.type() != CV_8UC3)
    throw std::invalid_argument("FindMotion: the background must be 8-bit BGR");
  MotionScene scene;
  scene.background = background;
  scene.frame_count = source.count();
  scene.width = background.cols;
  scene.height = background.rows;
  cv::Mat small_background;
  cv::resize(background, small_background, WorkSize(background.size(), options), 0, 0,
             cv::INTER_AREA);
  const cv::Size thumbnail = ThumbnailSize(background.size(), options.thumbnail_px);
  const bool keep_thumbnails =
      options.thumbnail_px > 0 &&
      static_cast<double>(thumbnail.area()) * scene.frame_count <= 64.0 * 1024 * 1024;
  std::vector<Active> active;
  std::vector<double> noises;
  FrameDifferencer differencer(options.timing_grid_pixels);
  // Frame f + 1 is decoded on a thread of its own while frame f is measured.
  ReadAhead reader(source, 2, /*colour=*/true);
  for (int f = 0; f < source.count(); ++f) {
    const cv::Mat frame = ToBgr8(reader.Next(), source.Describe(f));
    if (frame.size() != background.size())
      throw std::runtime_error(source.Describe(f) + ": " + std::to_string(frame.cols) + " x " +
                               std::to_string(frame.rows) + " px, but the background is " +
                               std::to_string(background.cols) + " x " +
                               std::to_string(background.rows));
    {
      // The repeats are judged on a grid of the frame at the working size, its pixels as they
      // are (an exact copy still differs by exactly 0), not on the whole frame made grey.
      cv::Mat sampled, grey;
      cv::resize(frame, sampled, small_background.size(), 0, 0, cv::INTER_NEAREST);
      cv::cvtColor(sampled, grey, cv::COLOR_BGR2GRAY);
      differencer.Add(grey, source.Describe(f));
    }
    cv::Mat small;
    cv::resize(frame, small, small_background.size(), 0, 0, cv::INTER_AREA);
    if (keep_thumbnails) {
      cv::Mat grey;
      cv::cvtColor(small, grey, cv::COLOR_BGR2GRAY);
      cv::resize(grey, scene.thumbnails.emplace_back(), thumbnail, 0, 0, cv::INTER_AREA);
    }
    double noise = 0;
    std::vector<MotionRegion> regions =
        RegionsOf(frame, small, background, small_background, f, options, noise);
    noises.push_back(noise);
    // Link: the pairs within their gates, nearest first.
    struct Pair {
      double d;
      std::size_t path, region;
    };
    std::vector<Pair> pairs;
    for (std::size_t a = 0; a < active.size(); ++a) {
      const MotionRegion& last = active[a].path.regions.back();
      const int gap = f - last.frame;
      const Eigen::Vector2d predicted = last.p_I + active[a].v * gap;
      const double gate = options.link_sizes * last.diameter_px + active[a].v.norm() * gap + 2.0;
      for (std::size_t r = 0; r < regions.size(); ++r) {
        const double ratio = regions[r].diameter_px / std::max(1e-9, last.diameter_px);
        if (ratio > options.link_size_ratio || ratio < 1 / options.link_size_ratio) continue;
        const double d = (regions[r].p_I - predicted).norm();
        if (d < gate) pairs.push_back({d, a, r});
      }
    }
    std::sort(pairs.begin(), pairs.end(), [](const Pair& x, const Pair& y) { return x.d < y.d; });
    std::vector<bool> path_used(active.size(), false), region_used(regions.size(), false);
    for (const Pair& p : pairs) {
      if (path_used[p.path] || region_used[p.region]) continue;
      path_used[p.path] = region_used[p.region] = true;
      Active& a = active[p.path];
      const MotionRegion& last = a.path.regions.back();
      a.v = (regions[p.region].p_I - last.p_I) / static_cast<double>(f - last.frame);
      a.path.regions.push_back(std::move(regions[p.region]));
    }
    for (std::size_t r = 0; r < regions.size(); ++r)
      if (!region_used[r]) {
        Active a;
        a.path.regions.push_back(std::move(regions[r]));
        active.push_back(std::move(a));
      }
    // Paths not seen for too long end.
    for (std::size_t a = 0; a < active.size();) {
      if (f - active[a].path.last_frame() > options.max_gap_frames) {
        // A path of fewer than 4 regions carries no arc of its own: its pixels are not kept
        // (memory would otherwise grow with every speck of every frame).
        if (active[a].path.regions.size() < 4)
          for (auto& r : active[a].path.regions) r.crop_bgr = r.crop_background = cv::Mat();
        scene.paths.push_back(std::move(active[a].path));
        active.erase(active.begin() + static_cast<std::ptrdiff_t>(a));
      } else {
        ++a;
      }
    }
    if (progress) progress(f);
  }
  for (auto& a : active) scene.paths.push_back(std::move(a.path));
  std::stable_sort(
      scene.paths.begin(), scene.paths.end(),
      [](const MotionPath& a, const MotionPath& b) { return a.regions.size() > b.regions.size(); });
  scene.noise = MedianOf(noises);
  scene.differences = differencer.Finish();
  scene.repeat = FindRepeats(scene.differences, FrameTimingOptions{}.repeat_fraction_of_noise);
  return scene;
}

namespace {

/// Bilinear sample of an 8-bit image at `p` (px); -1 outside.
double Sample(const cv::Mat& L, const Eigen::Vector2d& p) {
  const int x0 = static_cast<int>(std::floor(p.x())), y0 = static_cast<int>(std::floor(p.y()));
  if (x0 < 0 || y0 < 0 || x0 + 1 >= L.cols || y0 + 1 >= L.rows) return -1;
  const double fx = p.x() - x0, fy = p.y() - y0;
  auto at = [&](int x, int y) { return static_cast<double>(L.at<std::uint8_t>(y, x)); };
  return (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) +
         fy * ((1 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1));
}

/// The ball's width across `n` (unit) through `c` on its likeness `L`: the distance between
/// the outermost half-level crossings on either side, the levels the median inside (within a
/// quarter of `d`, the fitted diameter) and outside (0.8 to 1.1 d from the centre). Motion blur
/// stretches the ball along its motion only, so across it the width is the ball's. NaN where
/// the levels do not differ or a crossing is not found.
double WidthAcross(const cv::Mat& L, const Eigen::Vector2d& c, const Eigen::Vector2d& n, double d) {
  const double step = 0.25;
  std::vector<double> inside, outside;
  for (double s = -1.1 * d; s <= 1.1 * d; s += step) {
    const double v = Sample(L, c + s * n);
    if (v < 0) return std::numeric_limits<double>::quiet_NaN();
    if (std::abs(s) < 0.25 * d) inside.push_back(v);
    if (std::abs(s) > 0.8 * d) outside.push_back(v);
  }
  const double in = MedianOf(inside), out = MedianOf(outside);
  if (!(in - out > 10)) return std::numeric_limits<double>::quiet_NaN();
  const double half = 0.5 * (in + out);
  double reach[2];
  for (int side = 0; side < 2; ++side) {
    const double sign = side == 0 ? 1.0 : -1.0;
    reach[side] = std::numeric_limits<double>::quiet_NaN();
    double prev = Sample(L, c);
    for (double s = step; s <= 1.1 * d; s += step) {
      const double v = Sample(L, c + sign * s * n);
      if (prev >= half && v < half) {
        reach[side] = s - step + step * (prev - half) / (prev - v);
        // The outermost crossing: keep looking for a later one that stays below.
      }
      prev = v;
    }
  }
  return reach[0] + reach[1];
}

}  // namespace

SilhouetteTrack MeasureBallPath(const MotionPath& path, int frame_count,
                                const SilhouetteOptions& options) {
  SilhouetteTrack track;
  track.polarity = Polarity::kBrightOnDark;
  track.frames.resize(static_cast<std::size_t>(std::max(0, frame_count)));
  for (auto& o : track.frames) o.status = "not on the body's path";
  SilhouetteOptions so = options;
  so.shape = SilhouetteShape::kBall;
  so.polarity = Polarity::kBrightOnDark;
  const double diameter = path.MedianDiameter();
  for (std::size_t k = 0; k < path.regions.size(); ++k) {
    const MotionRegion& r = path.regions[k];
    if (r.frame < 0 || r.frame >= frame_count) continue;
    SilhouetteObservation& out = track.frames[static_cast<std::size_t>(r.frame)];
    if (r.crop_bgr.empty()) {
      out.status = "the region is too large to be the ball";
      continue;
    }
    const cv::Mat L = Likeness(r.crop_bgr, r.crop_background);
    SilhouetteObservation previous;
    previous.diameter_px = diameter;
    const Eigen::Vector2d offset(r.crop.x, r.crop.y);
    SilhouetteObservation o = MeasureSilhouetteNear(L, so, Polarity::kBrightOnDark, r.p_I - offset,
                                                    previous, 0.35 * diameter + 3);
    // An edge fit that fails, or that lies a quarter of the ball off the region or a third off
    // its size, has taken the edge of something else (a net behind the ball, its own stripes
    // smeared by motion blur): the region's centroid, the centre at mid-exposure, stands in.
    // The ball's size across its smear is the region's narrowest width (a disc of diameter D
    // has second moments D^2 / 16; blur adds only along the motion).
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> moments(r.moments);
    const double across =
        r.moments.trace() > 0 ? 4 * std::sqrt(std::max(0.0, moments.eigenvalues()(0))) : diameter;
    const double ball = std::min(diameter, across);
    const bool agrees = o.found && (o.p_I + offset - r.p_I).norm() <= 0.25 * ball &&
                        o.diameter_px >= 0.75 * ball && o.diameter_px <= 1.33 * diameter;
    if (!agrees) {
      if (r.touches_border) {  // cut by the frame's edge: its centroid is not the ball's either
        out.status = "the ball's edge was not fitted (" + (o.found ? "off its region" : o.status) +
                     ") and its region is cut by the frame's edge";
        continue;
      }
      SilhouetteObservation c;
      c.found = true;
      c.status = "the region's centroid (the edge fit " +
                 (o.found ? std::string("lies off the region") : o.status) + ")";
      c.p_I = r.p_I;
      const double sd = 0.05 * diameter;  // a blob's outline wanders by a few per cent of it
      c.cov_p_I = Eigen::Matrix2d::Identity() * sd * sd;
      c.diameter_px = diameter;
      c.diameter_se_px = 0.1 * diameter;
      out = c;
      continue;
    }
    // Across the motion, where the ball moves more than a tenth of its size between frames:
    // there motion blur stretches the fitted circle.
    const MotionRegion& before = path.regions[k > 0 ? k - 1 : k];
    const MotionRegion& after = path.regions[k + 1 < path.regions.size() ? k + 1 : k];
    const Eigen::Vector2d motion = after.p_I - before.p_I;
    const int frames = std::max(1, after.frame - before.frame);
    if (motion.norm() / frames > 0.1 * o.diameter_px) {
      const Eigen::Vector2d n(-motion.y() / motion.norm(), motion.x() / motion.norm());
      const double w = WidthAcross(L, o.p_I, n, o.diameter_px);
      if (std::isfinite(w) && w > 0.5 * o.diameter_px && w < 1.2 * o.diameter_px) o.diameter_px = w;
    }
    if (options.sample_faces) {
      cv::Mat grey;
      cv::cvtColor(r.crop_bgr, grey, cv::COLOR_BGR2GRAY);
      o.face = SampleBallFace(grey, o.p_I, 0.5 * o.diameter_px, 0.0, options.spin);
      o.face->centre_I += offset;
    }
    o.p_I += offset;
    out = o;
  }
  return track;
}

}  // namespace hoof::tracking
