#include "tracking/silhouette_tracker.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include <Eigen/Dense>
#include <opencv2/imgproc.hpp>

#include "tracking/circle_fit.h"
#include "tracking/image_sample.h"
#include "tracking/read_ahead.h"

namespace hoof::tracking {
namespace {

constexpr double kPi = std::numbers::pi;

double MedianOf(std::vector<double>& v) {
  if (v.empty()) return std::nan("");
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

/// Bilinear sample of a CV_32F image; false outside.
bool Sample(const cv::Mat& img, double x, double y, double& value) {
  return SampleBilinear(img, x, y, value);
}

/// Robust noise s.d. from horizontal neighbour differences of the pixels where `mask` is set
/// (or all pixels without a mask): 1.4826 MAD / sqrt(2).
double NoiseOf(const cv::Mat& f, const cv::Mat& mask = cv::Mat()) {
  std::vector<double> d;
  for (int y = 0; y < f.rows; ++y) {
    const float* row = f.ptr<float>(y);
    const unsigned char* m = mask.empty() ? nullptr : mask.ptr<unsigned char>(y);
    for (int x = 0; x + 1 < f.cols; ++x)
      if (!m || (m[x] && m[x + 1])) d.push_back(std::abs(row[x + 1] - row[x]));
  }
  if (d.empty()) return 0.0;
  return 1.4826 * MedianOf(d) / std::sqrt(2.0);
}

cv::Mat ToFloat(const cv::Mat& grey) {
  cv::Mat f;
  grey.convertTo(f, CV_32F);
  return f;
}

/// Noise s.d. of `f` on the ring from r + 3 to r + 8 px about c: the ball's surround.
double SurroundNoise(const cv::Mat& f, const Eigen::Vector2d& c, double r) {
  cv::Mat ring(f.size(), CV_8U, cv::Scalar(0));
  const cv::Point centre(static_cast<int>(std::lround(c.x())),
                         static_cast<int>(std::lround(c.y())));
  cv::circle(ring, centre, static_cast<int>(std::lround(r + 8)), cv::Scalar(255), cv::FILLED);
  cv::circle(ring, centre, static_cast<int>(std::lround(r + 3)), cv::Scalar(0), cv::FILLED);
  return NoiseOf(f, ring);
}

/// One ray's edge point: where the profile steps from the body's level to the surround's.
struct RayEdge {
  double r = 0;     ///< distance from the ray's origin (px)
  double step = 0;  ///< local step, body minus surround, sign-adjusted to be > 0 (frame units)
};

/// The edge along one ray. `profile` holds samples every `step_px` from `a_lo`; `valid` says
/// which could be sampled. Candidates are the positions in [r_lo, r_hi] where the narrow step
/// (the mean over 0.5..1.5 px inside minus the mean over 0.5..1.5 px outside, times `sign`) is a
/// local maximum above `threshold`, and whose wide step (1.5..2.5 px on either side) is above it
/// too: a sharp edge of the body's polarity. Of these the outermost is taken (the limb of a
/// convex body lies outside any shading or terminator on it; a surface, shadow or reflection
/// beyond it gives a point off the circle that the robust fit drops). The point is where the
/// profile crosses the level midway between the local levels at 1.5..2.5 px, nearest the
/// candidate: levels measured on the ray itself, so a shaded body, or a surround that changes
/// from ray to ray, does not move it.
/// `sum` and `count` are work space, resized here.
std::optional<RayEdge> EdgeAlongRay(const std::vector<double>& profile,
                                    const std::vector<char>& valid, double a_lo, double step_px,
                                    double r_lo, double r_hi, double sign, double threshold,
                                    std::vector<double>& sum, std::vector<int>& count) {
  const int n = static_cast<int>(profile.size());
  const int per_px = static_cast<int>(std::lround(1.0 / step_px));
  // Prefix sums of the valid samples.
  sum.resize(static_cast<std::size_t>(n) + 1);
  count.resize(static_cast<std::size_t>(n) + 1);
  sum[0] = 0.0;
  count[0] = 0;
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    sum[k + 1] = sum[k] + (valid[k] ? profile[k] : 0.0);
    count[k + 1] = count[k] + (valid[k] ? 1 : 0);
  }
  // Mean of samples i0..i1 (inclusive) when all are valid.
  const auto mean = [&](int i0, int i1, double& m) {
    if (i0 < 0 || i1 >= n || i1 < i0) return false;
    const int c = count[static_cast<std::size_t>(i1) + 1] - count[static_cast<std::size_t>(i0)];
    if (c != i1 - i0 + 1) return false;
    m = (sum[static_cast<std::size_t>(i1) + 1] - sum[static_cast<std::size_t>(i0)]) / c;
    return true;
  };
  const auto narrow = [&](int i, double& d) {
    double in = 0, out = 0;
    if (!mean(i - 3 * per_px / 2, i - per_px / 2, in) ||
        !mean(i + per_px / 2, i + 3 * per_px / 2, out))
      return false;
    d = sign * (in - out);
    return true;
  };
  const int i_lo = std::max(0, static_cast<int>(std::ceil((r_lo - a_lo) / step_px)));
  const int i_hi = std::min(n - 1, static_cast<int>(std::floor((r_hi - a_lo) / step_px)));
  const int half = per_px / 2;  // local maximum over +-0.5 px
  for (int i = i_hi; i >= i_lo; --i) {
    double d = 0;
    if (!narrow(i, d) || !(d > threshold)) continue;
    bool peak = true;
    for (int j = i - half; j <= i + half && peak; ++j) {
      double dj = 0;
      if (j != i && narrow(j, dj) && dj > d) peak = false;
    }
    if (!peak) continue;
    double in = 0, out = 0;
    if (!mean(i - 5 * per_px / 2, i - 3 * per_px / 2, in) ||
        !mean(i + 3 * per_px / 2, i + 5 * per_px / 2, out))
      continue;
    const double wide = sign * (in - out);
    if (!(wide > threshold)) continue;
    const double mid = 0.5 * (in + out);
    double best = -1, best_gap = 1e300;
    for (int j = std::max(1, i - 3 * per_px / 2); j <= std::min(n - 1, i + 3 * per_px / 2); ++j) {
      const auto k = static_cast<std::size_t>(j);
      if (!valid[k] || !valid[k - 1]) continue;
      const double v0 = profile[k - 1], v1 = profile[k];
      if ((v0 - mid) * (v1 - mid) > 0 || v0 == v1) continue;
      const double rc = a_lo + (j - 1 + (mid - v0) / (v1 - v0)) * step_px;
      const double gap = std::abs(rc - (a_lo + i * step_px));
      if (gap < best_gap) {
        best_gap = gap;
        best = rc;
      }
    }
    if (best > 0) return RayEdge{best, wide};
  }
  return std::nullopt;
}

/// The ball in `f` (a CV_32F window) near the circle (c0, r0): along rays from the centre, the
/// outermost sharp step of the body's polarity within +-h of r0 (EdgeAlongRay), located where
/// the profile crosses the level midway between its own levels just inside and just outside,
/// and weighted by the square of that step over the noise (the variance of a crossing goes as
/// (noise / step)^2); then the weighted robust circle, repeated with a 3 px band about the
/// last fit until it settles. A ray whose step is not significant (3 noise s.d. of a difference of
/// two means, and at least 5 % of the body's contrast) gives no point: a shaded limb against
/// an equally dark surround, or the contact side against the surface. Coordinates are the
/// window's.
SilhouetteObservation MeasureBall(const cv::Mat& f, Eigen::Vector2d c0, double r0, double search,
                                  Polarity polarity, const SilhouetteOptions& options) {
  SilhouetteObservation obs;
  obs.status = "lost";
  if (polarity == Polarity::kAuto) return obs;
  const double sign = polarity == Polarity::kBrightOnDark ? 1.0 : -1.0;
  if (!(r0 >= 3.0)) {
    obs.status = "too small for a circle fit (radius < 3 px)";
    return obs;
  }
  obs.noise = SurroundNoise(f, c0, r0);
  CircleFit fit;
  constexpr double kStepPx = 0.25;
  // Passes: the first within the search band, then 3 px bands about the last fit until the
  // circle moves less than kConvergedPx (a body found afresh starts from its thresholded
  // region, which may be several px off for a shaded ball).
  constexpr int kMaxPasses = 8;
  constexpr double kConvergedPx = 0.01;
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    if (!(r0 >= 3.0)) {
      obs.status = "too small for a circle fit (radius < 3 px)";
      return obs;
    }
    const double h = pass == 0 ? std::max(3.0, search) : 3.0;
    const int rays = std::clamp(static_cast<int>(std::lround(kPi * r0)), 24, 720);
    const double r_in = std::max(0.5 * r0, r0 - h - 1.5), r_out = r0 + h + 1.5;
    std::vector<double> inner, outer;
    for (int k = 0; k < rays; ++k) {
      const double a = 2 * kPi * k / rays;
      const Eigen::Vector2d u{std::cos(a), std::sin(a)};
      double v = 0;
      if (Sample(f, c0.x() + r_in * u.x(), c0.y() + r_in * u.y(), v)) inner.push_back(v);
      if (Sample(f, c0.x() + r_out * u.x(), c0.y() + r_out * u.y(), v)) outer.push_back(v);
    }
    if (inner.size() < 8 || outer.size() < 8) return obs;
    const double in = MedianOf(inner), out = MedianOf(outer);
    obs.contrast = in - out;
    if (!(sign * (in - out) > 0)) {
      obs.status = "the body's polarity does not match the frame";
      return obs;
    }
    const double threshold = std::max(3.0 * std::sqrt(2.0) * obs.noise, 0.05 * std::abs(in - out));
    const double r_lo = std::max(0.4 * r0, r0 - h), r_hi = r0 + h;
    const double a_lo = r_lo - 3.0, a_hi = r_hi + 3.0;
    const int samples = static_cast<int>(std::floor((a_hi - a_lo) / kStepPx)) + 1;
    std::vector<double> profile(static_cast<std::size_t>(samples));
    std::vector<char> valid(static_cast<std::size_t>(samples));
    std::vector<Eigen::Vector2d> points;
    std::vector<double> weights, sum;
    std::vector<int> count;
    points.reserve(static_cast<std::size_t>(rays));
    weights.reserve(static_cast<std::size_t>(rays));
    for (int k = 0; k < rays; ++k) {
      const double a = 2 * kPi * k / rays;
      const Eigen::Vector2d u{std::cos(a), std::sin(a)};
      for (int i = 0; i < samples; ++i) {
        const double r = a_lo + i * kStepPx;
        double v = 0;
        valid[static_cast<std::size_t>(i)] =
            r > 0 && Sample(f, c0.x() + r * u.x(), c0.y() + r * u.y(), v);
        profile[static_cast<std::size_t>(i)] = v;
      }
      const auto edge =
          EdgeAlongRay(profile, valid, a_lo, kStepPx, r_lo, r_hi, sign, threshold, sum, count);
      if (!edge) continue;
      points.push_back(c0 + edge->r * u);
      weights.push_back(edge->step * edge->step);
    }
    fit = FitCircleRobust(points, weights, options.outlier_sigmas, options.min_outlier_px);
    if (!fit.ok) {
      obs.status = "too few edge points for a circle";
      return obs;
    }
    const double moved = std::max((fit.c - c0).norm(), std::abs(fit.r - r0));
    c0 = fit.c;
    r0 = fit.r;
    if (pass >= 1 && moved < kConvergedPx) break;
  }
  if (std::abs(obs.contrast) < options.min_significance * obs.noise) {
    obs.status = "no significant contrast at the edge";
    return obs;
  }
  obs.found = true;
  obs.status = "ok";
  obs.p_I = fit.c;
  obs.cov_p_I = fit.cov.topLeftCorner<2, 2>();
  obs.diameter_px = 2 * fit.r;
  obs.diameter_se_px = 2 * std::sqrt(fit.cov(2, 2));
  obs.edge_points = fit.n;
  obs.edge_points_rejected = fit.rejected;
  obs.rms_residual_px = fit.rms;
  return obs;
}

/// The region (holes filled) of `mask` that is the body: the largest one of at least
/// `min_area` not touching the border (for a ball, round enough: 4 pi A / P^2 > 0.5), or, when
/// `near` is given, the one whose centroid is nearest it. Empty when none.
std::vector<cv::Point> PickRegion(const cv::Mat& mask, const SilhouetteOptions& options,
                                  const std::optional<Eigen::Vector2d>& near) {
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  std::vector<cv::Point> best;
  double best_score = -1e300;
  for (auto& c : contours) {
    const cv::Rect box = cv::boundingRect(c);
    if (!near && (box.x <= 0 || box.y <= 0 || box.x + box.width >= mask.cols ||
                  box.y + box.height >= mask.rows))
      continue;
    const double area = cv::contourArea(c);
    if (area < options.min_area_px) continue;
    if (options.shape == SilhouetteShape::kBall) {
      const double perimeter = cv::arcLength(c, true);
      if (!(4 * kPi * area / (perimeter * perimeter) > 0.5)) continue;
    }
    double score = area;
    if (near) {
      const cv::Moments m = cv::moments(c);
      score = -(Eigen::Vector2d(m.m10 / m.m00, m.m01 / m.m00) - *near).norm();
    }
    if (score > best_score) {
      best_score = score;
      best = c;
    }
  }
  return best;
}

/// Median of `f` where `mask` is set.
double MedianWhere(const cv::Mat& f, const cv::Mat& mask) {
  std::vector<double> v;
  for (int y = 0; y < f.rows; ++y) {
    const float* row = f.ptr<float>(y);
    const unsigned char* m = mask.ptr<unsigned char>(y);
    for (int x = 0; x < f.cols; ++x)
      if (m[x]) v.push_back(row[x]);
  }
  return MedianOf(v);
}

cv::Mat Disk(int radius) {
  return cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius + 1, 2 * radius + 1));
}

/// An elongated body in `f` (a CV_32F window) whose filled region is `filled`: the centroid
/// and principal axis of the coverage, where a pixel well inside counts 1, one well outside 0,
/// and one in the 2-px band about the edge (I - out) / (in - out) clipped to [0, 1], with the
/// levels in and out measured just inside and just outside the edge. For an anti-aliased edge
/// that weight is the pixel's coverage, so the moments are the outline's. The uncertainty is
/// the noise of the band's weights carried through the moments.
SilhouetteObservation MeasureOutline(const cv::Mat& f, const cv::Mat& filled) {
  SilhouetteObservation obs;
  obs.status = "lost";
  cv::Mat in2, in4, out3, out7;
  cv::erode(filled, in2, Disk(2));
  cv::erode(filled, in4, Disk(4));
  cv::dilate(filled, out3, Disk(3));
  cv::dilate(filled, out7, Disk(7));
  const cv::Mat ring = out7 & ~out3;
  if (cv::countNonZero(in4) < 4 || cv::countNonZero(ring) < 4) return obs;
  const double in = MedianWhere(f, in4), out = MedianWhere(f, ring);
  obs.contrast = in - out;
  obs.noise = NoiseOf(f, ring);
  if (!(std::abs(in - out) > 0)) return obs;
  cv::Mat band_outer;
  cv::dilate(filled, band_outer, Disk(2));
  double m00 = 0, m10 = 0, m01 = 0;
  struct Px {
    double x, y, w;
    bool band;
  };
  std::vector<Px> px;
  for (int y = 0; y < f.rows; ++y) {
    const float* row = f.ptr<float>(y);
    const unsigned char* inner = in2.ptr<unsigned char>(y);
    const unsigned char* outer = band_outer.ptr<unsigned char>(y);
    for (int x = 0; x < f.cols; ++x) {
      if (!outer[x]) continue;
      const bool band = !inner[x];
      const double w = band ? std::clamp((row[x] - out) / (in - out), 0.0, 1.0) : 1.0;
      px.push_back({static_cast<double>(x), static_cast<double>(y), w, band});
      m00 += w;
      m10 += w * x;
      m01 += w * y;
    }
  }
  if (!(m00 > 0)) return obs;
  const Eigen::Vector2d c{m10 / m00, m01 / m00};
  double mu20 = 0, mu02 = 0, mu11 = 0;
  for (const auto& p : px) {
    const double dx = p.x - c.x(), dy = p.y - c.y();
    mu20 += p.w * dx * dx;
    mu02 += p.w * dy * dy;
    mu11 += p.w * dx * dy;
  }
  mu20 /= m00;
  mu02 /= m00;
  mu11 /= m00;
  const double a = mu20 - mu02, b = 2 * mu11;
  const double angle = 0.5 * std::atan2(b, a);
  const double common = std::sqrt(a * a + b * b);
  const double l1 = 0.5 * (mu20 + mu02 + common), l2 = 0.5 * (mu20 + mu02 - common);
  // Uncertainty: only the band's weights are noisy, each with s.d. noise / |in - out|.
  const double sw = obs.noise / std::abs(in - out);
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  double var_angle = 0;
  for (const auto& p : px) {
    if (!p.band) continue;
    const Eigen::Vector2d d{p.x - c.x(), p.y - c.y()};
    cov += d * d.transpose();
    const double da = ((d.x() * d.x() - d.y() * d.y()) - a) / m00;
    const double db = 2 * (d.x() * d.y() - mu11) / m00;
    const double dtheta = 0.5 * (a * db - b * da) / (a * a + b * b);
    var_angle += dtheta * dtheta;
  }
  obs.found = true;
  obs.status = "ok";
  obs.p_I = c;
  obs.cov_p_I = sw * sw * cov / (m00 * m00);
  obs.has_orientation = true;
  obs.angle_I_rad = angle;
  obs.angle_se_rad = sw * std::sqrt(var_angle);
  obs.length_px = std::sqrt(12 * std::max(0.0, l1));
  obs.width_px = std::sqrt(12 * std::max(0.0, l2));
  return obs;
}

/// The significance of a region: |median inside - median of the surround| over the noise.
bool Significant(const cv::Mat& f, const cv::Mat& filled, const SilhouetteOptions& options) {
  cv::Mat in2, out3, out8;
  cv::erode(filled, in2, Disk(2));
  cv::dilate(filled, out3, Disk(3));
  cv::dilate(filled, out8, Disk(8));
  const cv::Mat ring = out8 & ~out3;
  if (cv::countNonZero(in2) < 4 || cv::countNonZero(ring) < 4) return false;
  const double contrast = std::abs(MedianWhere(f, in2) - MedianWhere(f, ring));
  return contrast > options.min_significance * NoiseOf(f, ring) && contrast > 0;
}

/// Orients an outline's axis: against gravity without a previous angle, else nearest it.
void OrientAxis(SilhouetteObservation& obs, const SilhouetteOptions& options,
                const std::optional<double>& previous) {
  if (!obs.has_orientation) return;
  const Eigen::Vector2d x_B{std::cos(obs.angle_I_rad), std::sin(obs.angle_I_rad)};
  bool flip = false;
  if (previous)
    flip = x_B.dot(Eigen::Vector2d(std::cos(*previous), std::sin(*previous))) < 0;
  else
    flip = x_B.dot(-options.gravity_I) < 0;
  if (flip) obs.angle_I_rad += obs.angle_I_rad > 0 ? -kPi : kPi;
}

/// Measures the body in the window `f` (CV_32F) whose filled region is `region`; adds `offset`
/// (the window's origin) to the position.
SilhouetteObservation MeasureRegion(const cv::Mat& f, const std::vector<cv::Point>& region,
                                    const cv::Point& offset, Polarity polarity,
                                    const SilhouetteOptions& options) {
  cv::Mat filled(f.size(), CV_8U, cv::Scalar(0));
  cv::drawContours(filled, std::vector<std::vector<cv::Point>>{region}, 0, cv::Scalar(255),
                   cv::FILLED);
  SilhouetteObservation obs;
  if (options.shape == SilhouetteShape::kBall) {
    const cv::Moments m = cv::moments(filled, true);
    const Eigen::Vector2d c{m.m10 / m.m00, m.m01 / m.m00};
    obs = MeasureBall(f, c, std::sqrt(m.m00 / kPi), 4.0, polarity, options);
  } else {
    obs = MeasureOutline(f, filled);
  }
  obs.p_I += Eigen::Vector2d(offset.x, offset.y);
  return obs;
}

/// Otsu's split of `f` (levels from its own percentiles), lightly smoothed: the bright mask.
cv::Mat BrightMask(const cv::Mat& f) {
  const auto [lo, hi] = FrameLevels(f);
  cv::Mat u8;
  if (!(hi > lo)) return cv::Mat(f.size(), CV_8U, cv::Scalar(0));
  cv::Mat smooth;
  cv::GaussianBlur(f, smooth, cv::Size(0, 0), 1.0);
  smooth.convertTo(u8, CV_8U, 255.0 / (hi - lo), -255.0 * lo / (hi - lo));
  cv::Mat bin;
  cv::threshold(u8, bin, 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU);
  return bin;
}

/// A rigid body's size in the image does not change through a clip beyond a slow drift (nearing
/// the lens, focus, a slow out-of-plane turn), so a frame whose size departs from its
/// neighbours' was measured on the body joined by something else at the contact: for a ball, a
/// lit surface or its reflection, which pulls the circle (and its centre) toward it while every
/// edge point still lies on one larger circle; for an outline, a lit grain of the surface
/// beside its round end, which lengthens the region by a px or so and pulls its centroid and
/// axis toward it (too little for the "outline grew" refusal). Such a frame is left out as not
/// found (WarnOfLostFrames names it). The size is a ball's fitted diameter, an outline's
/// length along its axis (the second moment along it weighs a grain at the end most). The
/// neighbours are the found frames within kNeighbourFrames on each side; a frame departs when
/// its size differs from their median by more than kDepartureSd robust s.d.s of that difference
/// over the clip and by more than `departure_fraction` of the size.
void LeaveOutJoinedBodies(SilhouetteTrack& track, SilhouetteShape shape) {
  constexpr int kNeighbourFrames = 8;
  constexpr double kDepartureSd = 6.0;
  // A ball's diameter scatters more from frame to frame (its edge rays) than an outline's
  // length (every pixel of its band); motion blur changes neither by 0.01 %.
  const bool ball = shape == SilhouetteShape::kBall;
  const double departure_fraction = ball ? 0.005 : 0.002;
  const auto size = [&](const SilhouetteObservation& o) {
    return ball ? o.diameter_px : o.length_px;
  };
  const int n = track.frame_count();
  std::vector<double> local(static_cast<std::size_t>(n), std::nan("")), departure;
  for (int i = 0; i < n; ++i) {
    if (!track.frames[static_cast<std::size_t>(i)].found) continue;
    std::vector<double> d;
    for (int j = std::max(0, i - kNeighbourFrames); j <= std::min(n - 1, i + kNeighbourFrames); ++j)
      if (j != i && track.frames[static_cast<std::size_t>(j)].found)
        d.push_back(size(track.frames[static_cast<std::size_t>(j)]));
    if (d.size() < 4) continue;
    local[static_cast<std::size_t>(i)] = MedianOf(d);
    departure.push_back(std::abs(size(track.frames[static_cast<std::size_t>(i)]) -
                                 local[static_cast<std::size_t>(i)]));
  }
  if (departure.size() < 5) return;
  const double sd = 1.4826 * MedianOf(departure);
  for (int i = 0; i < n; ++i) {
    auto& o = track.frames[static_cast<std::size_t>(i)];
    const double m = local[static_cast<std::size_t>(i)];
    if (!o.found || !std::isfinite(m)) continue;
    const double off = std::abs(size(o) - m);
    if (off > kDepartureSd * sd && off > departure_fraction * m) {
      o.found = false;
      const auto px = [](double v) {
        std::ostringstream os;
        os << std::fixed << std::setprecision(2) << v << " px";
        return os.str();
      };
      o.status = ball ? "its fitted diameter " + px(o.diameter_px) +
                            " departs from its neighbours' " + px(m) +
                            " (the ball joined by a surface or a reflection)"
                      : "its length " + px(o.length_px) + " departs from its neighbours' " + px(m) +
                            " (the outline joined by the surface)";
    }
  }
}

/// One warning per run of consecutive frames, from `first` (the first frame where the body was
/// found) on, where the body was not found for
/// the same reason: "F to L (N frames): the body was not found (why)". A clip whose body leaves
/// the view for thousands of frames gives one line, not thousands.
void WarnOfLostFrames(SilhouetteTrack& track, const FrameSource& source, int first) {
  const int n = track.frame_count();
  const auto at = [&](int i) -> const SilhouetteObservation& {
    return track.frames[static_cast<std::size_t>(i)];
  };
  for (int i = first; i < n;) {
    if (at(i).found) {
      ++i;
      continue;
    }
    int last = i;
    while (last + 1 < n && !at(last + 1).found && at(last + 1).status == at(i).status) ++last;
    const std::string where = last == i ? source.Describe(i)
                                        : source.Describe(i) + " to " + source.Describe(last) +
                                              " (" + std::to_string(last - i + 1) + " frames)";
    track.warnings.push_back(where + ": the body was not found (" + at(i).status + ")");
    i = last + 1;
  }
}

}  // namespace

std::string PolarityName(Polarity polarity) {
  switch (polarity) {
    case Polarity::kDarkOnBright:
      return "dark_on_bright";
    case Polarity::kBrightOnDark:
      return "bright_on_dark";
    default:
      return "auto";
  }
}

void SilhouetteOptions::Validate() const {
  if (!(min_area_px > 0)) throw std::invalid_argument("silhouette min_area_px must be > 0");
  if (!(min_significance > 0))
    throw std::invalid_argument("silhouette min_significance must be > 0");
  if (!(outlier_sigmas > 0)) throw std::invalid_argument("silhouette outlier_sigmas must be > 0");
  if (!(min_outlier_px >= 0)) throw std::invalid_argument("silhouette min_outlier_px must be >= 0");
  if (!(gravity_I.allFinite() && gravity_I.norm() > 0))
    throw std::invalid_argument("silhouette gravity_I must be a non-zero direction");
  if (!(read_ahead_frames >= 0))
    throw std::invalid_argument("silhouette read_ahead_frames must be >= 0");
  spin.Validate();
}

std::pair<double, double> FrameLevels(const cv::Mat& grey) {
  // A sample of at most about 65536 pixels on a regular grid.
  const int step =
      std::max(1, static_cast<int>(std::sqrt(static_cast<double>(grey.total()) / 65536.0)));
  std::vector<double> v;
  v.reserve(grey.total() / static_cast<std::size_t>(step * step) + 1);
  cv::Mat f = grey.depth() == CV_32F ? grey : ToFloat(grey);
  for (int y = 0; y < f.rows; y += step) {
    const float* row = f.ptr<float>(y);
    for (int x = 0; x < f.cols; x += step) v.push_back(row[x]);
  }
  if (v.empty()) return {0.0, 0.0};
  const auto at = [&](double q) {
    const auto k = static_cast<std::ptrdiff_t>(q * static_cast<double>(v.size() - 1));
    std::nth_element(v.begin(), v.begin() + k, v.end());
    return v[static_cast<std::size_t>(k)];
  };
  const double lo = at(0.005), hi = at(0.995);
  return {lo, hi};
}

SilhouetteObservation FindSilhouette(const cv::Mat& grey, const SilhouetteOptions& options,
                                     Polarity* polarity_found) {
  options.Validate();
  const cv::Mat f = ToFloat(grey);
  const cv::Mat bright = BrightMask(f);
  SilhouetteObservation best;
  best.status = "lost";
  double best_area = 0;
  for (Polarity p : {Polarity::kDarkOnBright, Polarity::kBrightOnDark}) {
    if (options.polarity != Polarity::kAuto && options.polarity != p) continue;
    const cv::Mat mask = p == Polarity::kBrightOnDark ? bright : ~bright;
    const std::vector<cv::Point> region = PickRegion(mask, options, std::nullopt);
    if (region.empty()) continue;
    cv::Mat filled(f.size(), CV_8U, cv::Scalar(0));
    cv::drawContours(filled, std::vector<std::vector<cv::Point>>{region}, 0, cv::Scalar(255),
                     cv::FILLED);
    if (!Significant(f, filled, options)) continue;
    const double area = cv::contourArea(region);
    if (area <= best_area) continue;
    SilhouetteObservation obs = MeasureRegion(f, region, cv::Point(0, 0), p, options);
    if (!obs.found) continue;
    best = obs;
    best_area = area;
    if (polarity_found) *polarity_found = p;
  }
  if (best.found) OrientAxis(best, options, std::nullopt);
  return best;
}

SilhouetteObservation MeasureSilhouetteNear(const cv::Mat& grey, const SilhouetteOptions& options,
                                            Polarity polarity, const Eigen::Vector2d& predicted_I,
                                            const SilhouetteObservation& previous,
                                            double search_px) {
  const double extent = options.shape == SilhouetteShape::kBall
                            ? 0.5 * previous.diameter_px
                            : 0.5 * std::max(previous.length_px, previous.width_px) + 4;
  const int half = static_cast<int>(std::ceil(extent + search_px + 10));
  const cv::Rect window =
      cv::Rect(static_cast<int>(std::floor(predicted_I.x())) - half,
               static_cast<int>(std::floor(predicted_I.y())) - half, 2 * half + 1, 2 * half + 1) &
      cv::Rect(0, 0, grey.cols, grey.rows);
  SilhouetteObservation obs;
  obs.status = "lost";
  if (window.width < 8 || window.height < 8) return obs;
  const cv::Mat f = ToFloat(grey(window));
  const Eigen::Vector2d offset(window.x, window.y);
  if (options.shape == SilhouetteShape::kBall) {
    obs = MeasureBall(f, predicted_I - offset, 0.5 * previous.diameter_px, search_px, polarity,
                      options);
    if (obs.found) obs.p_I += offset;
  } else {
    const cv::Mat bright = BrightMask(f);
    const cv::Mat mask = polarity == Polarity::kBrightOnDark ? bright : ~bright;
    SilhouetteOptions near_options = options;
    near_options.min_area_px =
        std::max(options.min_area_px, 0.25 * previous.length_px * previous.width_px);
    const std::vector<cv::Point> region =
        PickRegion(mask, near_options, Eigen::Vector2d(predicted_I - offset));
    if (region.empty()) return obs;
    // The window reaches past the body's extent and the search distance on every side, so a
    // region that touches its border is the body joined by something else: a lit surface at
    // the contact, whose strip the window cuts (so the length test below cannot see it).
    const cv::Rect box = cv::boundingRect(region);
    if (box.x <= 0 || box.y <= 0 || box.x + box.width >= f.cols || box.y + box.height >= f.rows) {
      obs.status = "the outline reaches the edge of its search window (joined by another region)";
      return obs;
    }
    obs = MeasureRegion(f, region, window.tl(), polarity, options);
    if (obs.found && !(obs.length_px < 1.5 * previous.length_px + 4)) {
      obs.found = false;
      obs.status = "the outline grew (joined by another region)";
    }
  }
  if (obs.found && obs.has_orientation) OrientAxis(obs, options, previous.angle_I_rad);
  return obs;
}

SilhouetteTrack TrackSilhouette(FrameSource& source, const SilhouetteOptions& options,
                                const std::function<void(int)>& progress) {
  options.Validate();
  SilhouetteTrack track;
  track.polarity = options.polarity;
  int found_frames = 0, first_found = -1;
  std::optional<ReadAhead> reader;
  if (options.read_ahead_frames > 0 && source.count() > 1)
    reader.emplace(source, options.read_ahead_frames);
  for (int i = 0; i < source.count(); ++i) {
    const cv::Mat grey = reader ? reader->Next() : source.Read(i);
    SilhouetteObservation obs;
    const int n = static_cast<int>(track.frames.size());
    const bool have_last = n >= 1 && track.frames[static_cast<std::size_t>(n - 1)].found;
    if (have_last) {
      const auto& last = track.frames[static_cast<std::size_t>(n - 1)];
      Eigen::Vector2d predicted = last.p_I;
      double displacement = 0;
      if (n >= 2 && track.frames[static_cast<std::size_t>(n - 2)].found) {
        const Eigen::Vector2d d = last.p_I - track.frames[static_cast<std::size_t>(n - 2)].p_I;
        predicted += d;
        displacement = d.norm();
      }
      // The velocity reverses at an impact, so the prediction can miss by two displacements.
      obs = MeasureSilhouetteNear(grey, options, track.polarity, predicted, last,
                                  std::max(4.0, 3.0 * displacement + 2.0));
    }
    if (!obs.found) {
      SilhouetteOptions find = options;
      find.polarity = track.polarity;
      Polarity p = track.polarity;
      obs = FindSilhouette(grey, find, &p);
      if (obs.found) track.polarity = p;
      if (obs.found && obs.has_orientation && have_last)
        OrientAxis(obs, options, track.frames[static_cast<std::size_t>(n - 1)].angle_I_rad);
    }
    if (obs.found) {
      if (found_frames == 0) first_found = i;
      ++found_frames;
      if (options.sample_faces && options.shape == SilhouetteShape::kBall)
        obs.face = SampleBallFace(grey, obs.p_I, 0.5 * obs.diameter_px, 0.0, options.spin);
    }
    track.frames.push_back(obs);
    if (progress) progress(i);
  }
  LeaveOutJoinedBodies(track, options.shape);
  if (found_frames == 0)
    throw std::runtime_error(source.Describe(0) + " (and the other " +
                             std::to_string(source.count() - 1) +
                             " frames): no body found: no region of either polarity, clear of "
                             "the frame's border, stands out from its surround");
  WarnOfLostFrames(track, source, first_found);
  return track;
}

}  // namespace hoof::tracking
