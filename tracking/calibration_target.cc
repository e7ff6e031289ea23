#include "tracking/calibration_target.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace hoof::tracking {
namespace {

double MedianOf(std::vector<double> v) {
  if (v.empty()) return 0.0;
  auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

/// A similarity p = s R q + t of the grid points q (m) onto the image points p (px), R a
/// rotation or (mirror) a reflection; least squares with its scale's standard error.
struct SimilarityFit {
  double px_per_m = 0.0, px_per_m_se = 0.0, rms_px = 0.0, angle_rad = 0.0;
  double ssr = 0.0;
};

SimilarityFit FitSimilarity(const std::vector<Eigen::Vector2d>& q,
                            const std::vector<Eigen::Vector2d>& p, bool mirror) {
  const double n = static_cast<double>(q.size());
  Eigen::Vector2d q0{0, 0}, p0{0, 0};
  for (std::size_t i = 0; i < q.size(); ++i) {
    q0 += q[i] / n;
    p0 += p[i] / n;
  }
  // Centred, the two columns of the linear part are orthogonal with equal norm sum |q|^2, so
  // a and b decouple: p = [a -b; b a] q (or [a b; b -a] q for a mirror image).
  double sqq = 0, sa = 0, sb = 0;
  for (std::size_t i = 0; i < q.size(); ++i) {
    const Eigen::Vector2d u = q[i] - q0, v = p[i] - p0;
    sqq += u.squaredNorm();
    if (mirror) {
      sa += v.x() * u.x() - v.y() * u.y();
      sb += v.x() * u.y() + v.y() * u.x();
    } else {
      sa += v.x() * u.x() + v.y() * u.y();
      sb += v.y() * u.x() - v.x() * u.y();
    }
  }
  const double a = sa / sqq, b = sb / sqq;
  Eigen::Matrix2d m;
  if (mirror)
    m << a, b, b, -a;
  else
    m << a, -b, b, a;
  SimilarityFit f;
  for (std::size_t i = 0; i < q.size(); ++i) f.ssr += (m * (q[i] - q0) - (p[i] - p0)).squaredNorm();
  f.px_per_m = std::hypot(a, b);
  // 2n coordinates, 4 parameters; var(a) = var(b) = s^2 / sum |q|^2, and so is var(|(a, b)|).
  const double s2 = f.ssr / (2 * n - 4);
  f.px_per_m_se = std::sqrt(s2 / sqq);
  f.rms_px = std::sqrt(f.ssr / n);
  f.angle_rad = std::atan2(b, a);
  return f;
}

/// A straight-line fit y = y0 + slope k of positions y against integer indices k.
struct LineFit {
  double slope = 0.0, slope_se = 0.0, intercept = 0.0, rms = 0.0;
  std::vector<double> residuals;
};

LineFit FitLine(const std::vector<double>& k, const std::vector<double>& y) {
  const double n = static_cast<double>(k.size());
  double km = 0, ym = 0;
  for (std::size_t i = 0; i < k.size(); ++i) {
    km += k[i] / n;
    ym += y[i] / n;
  }
  double skk = 0, sky = 0;
  for (std::size_t i = 0; i < k.size(); ++i) {
    skk += (k[i] - km) * (k[i] - km);
    sky += (k[i] - km) * (y[i] - ym);
  }
  LineFit f;
  f.slope = sky / skk;
  f.intercept = ym - f.slope * km;
  double ss = 0;
  for (std::size_t i = 0; i < k.size(); ++i) {
    const double r = y[i] - f.intercept - f.slope * k[i];
    f.residuals.push_back(r);
    ss += r * r;
  }
  f.rms = std::sqrt(ss / n);
  f.slope_se = n > 2 ? std::sqrt(ss / (n - 2) / skk) : 0.0;
  return f;
}

std::string SizeText(int cols, int rows) {
  return std::to_string(cols) + " x " + std::to_string(rows);
}

/// The inner-corner count of the board in `grey` (any count from 3 x 3 up), or 0 x 0.
cv::Size BoardSizeFound(const cv::Mat& grey) {
  std::vector<cv::Point2f> corners;
  cv::Mat meta;
  if (!cv::findChessboardCornersSB(grey, cv::Size(3, 3), corners,
                                   cv::CALIB_CB_LARGER | cv::CALIB_CB_EXHAUSTIVE, meta))
    return {0, 0};
  return meta.size();
}

}  // namespace

cv::Mat ToGrey8(const cv::Mat& image) {
  cv::Mat grey;
  if (image.channels() == 3)
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  else if (image.channels() == 4)
    cv::cvtColor(image, grey, cv::COLOR_BGRA2GRAY);
  else
    grey = image;
  cv::Mat f;
  grey.convertTo(f, CV_32F);
  std::vector<float> v(f.begin<float>(), f.end<float>());
  if (v.empty()) return cv::Mat();
  const auto at = [&v](double q) {
    auto it = v.begin() + static_cast<std::ptrdiff_t>(q * static_cast<double>(v.size() - 1));
    std::nth_element(v.begin(), it, v.end());
    return static_cast<double>(*it);
  };
  const double lo = at(0.001), hi = at(0.999);
  cv::Mat out;
  const double span = hi > lo ? hi - lo : 1.0;
  f.convertTo(out, CV_8U, 255.0 / span, -lo * 255.0 / span);
  return out;
}

CalibrationScale MeasureCheckerboard(const cv::Mat& image, int cols, int rows, double square_m,
                                     const ImageToWorld& lens, const std::string& name) {
  if (cols < 3 || rows < 3)
    throw std::runtime_error(name + ": a checkerboard needs 3 x 3 or more inner corners, not " +
                             SizeText(cols, rows));
  if (!(square_m > 0)) throw std::runtime_error(name + ": the square size must be > 0");
  if (image.empty()) throw std::runtime_error(name + ": the calibration image is empty");
  const cv::Mat grey = ToGrey8(image);
  // The board found, whatever its size: a board of another count than stated is an error (a
  // smaller stated count would otherwise fit a part of the board).
  const cv::Size found = BoardSizeFound(grey);
  const bool same = (found.width == cols && found.height == rows) ||
                    (found.width == rows && found.height == cols);
  std::vector<cv::Point2f> corners;
  const cv::Size size(cols, rows);
  bool ok = (found.area() == 0 || same) &&
            cv::findChessboardCornersSB(grey, size, corners,
                                        cv::CALIB_CB_ACCURACY | cv::CALIB_CB_EXHAUSTIVE);
  if (!ok && found.area() == 0) {
    // The classic detector with OpenCV's sub-pixel refinement, for boards the sector-based
    // one misses.
    ok = cv::findChessboardCorners(grey, size, corners,
                                   cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE);
    if (ok)
      cv::cornerSubPix(grey, corners, cv::Size(5, 5), cv::Size(-1, -1),
                       cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-3));
  }
  if (!ok) {
    if (found.area() > 0 && !same)
      throw std::runtime_error(name + ": the checkerboard found has " +
                               SizeText(found.width, found.height) +
                               " inner corners, trial.json says " + SizeText(cols, rows));
    throw std::runtime_error(name + ": no checkerboard of " + SizeText(cols, rows) +
                             " inner corners found");
  }
  std::vector<Eigen::Vector2d> q, p;
  CalibrationScale out;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const cv::Point2f& x = corners[static_cast<std::size_t>(r * cols + c)];
      out.points_px.emplace_back(x.x, x.y);
      p.push_back(lens.Undistort({x.x, x.y}));
      q.emplace_back(c * square_m, r * square_m);
    }
  const SimilarityFit proper = FitSimilarity(q, p, false), mirror = FitSimilarity(q, p, true);
  const SimilarityFit& f = proper.ssr <= mirror.ssr ? proper : mirror;
  out.m_per_px = 1.0 / f.px_per_m;
  out.m_per_px_se = f.px_per_m_se / (f.px_per_m * f.px_per_m);
  out.rms_residual_px = f.rms_px;
  out.points = static_cast<int>(q.size());
  out.angle_deg = f.angle_rad * 180.0 / M_PI;
  return out;
}

CalibrationScale MeasureRuler(const cv::Mat& image, const Eigen::Vector2d& from_px,
                              const Eigen::Vector2d& to_px, double tick_m, const ImageToWorld& lens,
                              const std::string& name) {
  if (!(tick_m > 0)) throw std::runtime_error(name + ": the tick spacing must be > 0");
  if (image.empty()) throw std::runtime_error(name + ": the calibration image is empty");
  const double band = 2.0;  // px on each side of the segment, averaged
  const auto inside = [&](const Eigen::Vector2d& x) {
    return x.allFinite() && x.x() >= band && x.y() >= band && x.x() <= image.cols - 1 - band &&
           x.y() <= image.rows - 1 - band;
  };
  for (const auto& [label, x] : {std::pair<const char*, Eigen::Vector2d>{"from", from_px},
                                 std::pair<const char*, Eigen::Vector2d>{"to", to_px}})
    if (!inside(x)) {
      std::ostringstream os;
      os << name << ": the ruler segment's \"" << label << "\" point (" << x.x() << ", " << x.y()
         << ") lies outside the " << image.cols << " x " << image.rows << " image (or within "
         << band << " px of its edge)";
      throw std::runtime_error(os.str());
    }
  const double length = (to_px - from_px).norm();
  cv::Mat grey;
  if (image.channels() > 1)
    cv::cvtColor(image, grey, image.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
  else
    grey = image;
  cv::Mat f;
  grey.convertTo(f, CV_64F);
  const Eigen::Vector2d u = (to_px - from_px) / length, n(-u.y(), u.x());
  const auto sample = [&f](const Eigen::Vector2d& x) {
    const int x0 = std::min(static_cast<int>(x.x()), f.cols - 2),
              y0 = std::min(static_cast<int>(x.y()), f.rows - 2);
    const double fx = x.x() - x0, fy = x.y() - y0;
    return (1 - fy) * ((1 - fx) * f.at<double>(y0, x0) + fx * f.at<double>(y0, x0 + 1)) +
           fy * ((1 - fx) * f.at<double>(y0 + 1, x0) + fx * f.at<double>(y0 + 1, x0 + 1));
  };
  // The profile along the segment, every half pixel, averaged across the band.
  const double step = 0.5;
  const int m = static_cast<int>(std::floor(length / step)) + 1;
  std::vector<double> prof(static_cast<std::size_t>(m));
  for (int i = 0; i < m; ++i) {
    double s = 0;
    int c = 0;
    for (double w = -band; w <= band + 1e-9; w += 1.0, ++c)
      s += sample(from_px + (i * step) * u + w * n);
    prof[static_cast<std::size_t>(i)] = s / c;
  }
  // Ticks are the thin minority: darker than the ruler's median when the mean lies below it.
  double mean = 0;
  for (double x : prof) mean += x / m;
  const double median = MedianOf(prof);
  std::vector<double> d(prof.size());
  for (std::size_t i = 0; i < prof.size(); ++i)
    d[i] = mean < median ? median - prof[i] : prof[i] - median;
  // The period from the spectrum's peak (Hann window, zero padded 8 times), refined by a
  // parabola through the log magnitudes of the peak and its neighbours.
  const int nfft = cv::getOptimalDFTSize(8 * m);
  cv::Mat in = cv::Mat::zeros(1, nfft, CV_64F);
  double dm = 0;
  for (double x : d) dm += x / m;
  for (int i = 0; i < m; ++i)
    in.at<double>(0, i) = (d[static_cast<std::size_t>(i)] - dm) *
                          (0.5 - 0.5 * std::cos(2 * M_PI * i / std::max(1, m - 1)));
  cv::Mat spec;
  cv::dft(in, spec, cv::DFT_COMPLEX_OUTPUT);
  const auto mag = [&spec](int k) {
    const cv::Vec2d c = spec.at<cv::Vec2d>(0, k);
    return std::hypot(c[0], c[1]);
  };
  // Periods from 2.5 px (in samples: 5) to a quarter of the segment.
  const int k_lo = std::max(2, static_cast<int>(std::ceil(nfft * step * 4.0 / length))),
            k_hi = std::min(nfft / 2 - 1, static_cast<int>(std::floor(nfft * step / 2.5)));
  if (length < 10 || k_lo >= k_hi)
    throw std::runtime_error(name + ": the ruler segment is too short (" + std::to_string(length) +
                             " px) to hold 4 ticks");
  int kp = k_lo;
  for (int k = k_lo; k <= k_hi; ++k)
    if (mag(k) > mag(kp)) kp = k;
  const double l0 = std::log(mag(kp - 1) + 1e-300), l1 = std::log(mag(kp) + 1e-300),
               l2 = std::log(mag(kp + 1) + 1e-300);
  const double denom = l0 - 2 * l1 + l2;
  const double kf = kp + (denom < 0 ? 0.5 * (l0 - l2) / denom : 0.0);
  const double period0 = nfft / kf;  // in samples
  // Each tick's position: the centroid of its darkness above half its peak, within +-0.4 of a
  // period of where the previous tick and the period put it.
  const int half = std::max(1, static_cast<int>(std::floor(0.4 * period0)));
  int first = 0;
  for (int i = 0; i < std::min(m, static_cast<int>(std::ceil(period0))); ++i)
    if (d[static_cast<std::size_t>(i)] > d[static_cast<std::size_t>(first)]) first = i;
  std::vector<double> k_index, pos;
  double expect = first;
  for (int k = 0; expect < m; ++k, expect += period0) {
    const int c = static_cast<int>(std::lround(expect));
    const int a = c - half, b = c + half;
    if (a < 0 || b >= m) continue;
    double peak = -1e300, low = 1e300;
    for (int i = a; i <= b; ++i) {
      peak = std::max(peak, d[static_cast<std::size_t>(i)]);
      low = std::min(low, d[static_cast<std::size_t>(i)]);
    }
    const double thr = 0.5 * (peak + low);
    double sw = 0, sx = 0;
    for (int i = a; i <= b; ++i) {
      const double w = std::max(0.0, d[static_cast<std::size_t>(i)] - thr);
      sw += w;
      sx += w * i;
    }
    if (!(sw > 0)) continue;
    const double at = sx / sw;
    k_index.push_back(k);
    pos.push_back(at);
    expect = at;  // follow the ticks (the sum below adds the period)
  }
  if (pos.size() < 4)
    throw std::runtime_error(name + ": fewer than 4 ruler ticks found along the segment");
  // Undistorted positions along the segment's undistorted line.
  std::vector<Eigen::Vector2d> pts;
  for (double s : pos) pts.push_back(lens.Undistort(from_px + (s * step) * u));
  const Eigen::Vector2d dir = (pts.back() - pts.front()).normalized();
  std::vector<double> t;
  for (const auto& x : pts) t.push_back((x - pts.front()).dot(dir));
  LineFit line = FitLine(k_index, t);
  // One pass without ticks far off the line (a mark or a number on the ruler).
  std::vector<double> abs_r;
  for (double r : line.residuals) abs_r.push_back(std::abs(r));
  const double cut = std::max(5 * 1.4826 * MedianOf(abs_r), 0.05);
  std::vector<double> k2, t2;
  CalibrationScale out;
  for (std::size_t i = 0; i < t.size(); ++i)
    if (std::abs(line.residuals[i]) <= cut) {
      k2.push_back(k_index[i]);
      t2.push_back(t[i]);
      out.points_px.push_back(from_px + (pos[i] * step) * u);
    }
  if (k2.size() < 4)
    throw std::runtime_error(name + ": fewer than 4 regular ruler ticks found along the segment");
  line = FitLine(k2, t2);
  if (!(line.slope > 0) || line.rms > 0.25 * line.slope)
    throw std::runtime_error(name + ": no regular ticks found along the ruler segment");
  out.m_per_px = tick_m / line.slope;
  out.m_per_px_se = tick_m * line.slope_se / (line.slope * line.slope);
  out.rms_residual_px = line.rms;
  out.points = static_cast<int>(k2.size());
  out.angle_deg = std::atan2(u.y(), u.x()) * 180.0 / M_PI;
  return out;
}

}  // namespace hoof::tracking
