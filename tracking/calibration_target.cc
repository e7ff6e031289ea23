#include "tracking/calibration_target.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <Eigen/Dense>

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

/// Fits z = c0 + c1 x + c2 y + c3 x^2 + c4 x y + c5 y^2 (x, y scaled by `scale`) by least
/// squares; returns the coefficients (empty when under-determined).
Eigen::VectorXd FitQuadratic(const std::vector<Eigen::Vector3d>& xyz, double scale) {
  if (xyz.size() < 6) return {};
  Eigen::MatrixXd a(xyz.size(), 6);
  Eigen::VectorXd z(xyz.size());
  for (std::size_t i = 0; i < xyz.size(); ++i) {
    const double x = xyz[i].x() / scale, y = xyz[i].y() / scale;
    a.row(static_cast<Eigen::Index>(i)) << 1, x, y, x * x, x * y, y * y;
    z(static_cast<Eigen::Index>(i)) = xyz[i].z();
  }
  return a.colPivHouseholderQr().solve(z);
}

/// The board's corners found again in `grey` flattened by its white and black levels (see
/// MeasureCheckerboard); `corners` unchanged when the levels cannot be fitted or the corners
/// are not found again at the same places.
std::vector<cv::Point2f> FlattenedCorners(const cv::Mat& grey, const cv::Size& size,
                                          const std::vector<cv::Point2f>& corners) {
  const int cols = size.width, rows = size.height;
  const auto at = [&](int r, int c) { return corners[static_cast<std::size_t>(r * cols + c)]; };
  double sq = 0;
  for (int c = 0; c + 1 < cols; ++c) sq += cv::norm(at(0, c + 1) - at(0, c)) / (cols - 1);
  const int h = std::max(1, static_cast<int>(std::floor(0.2 * sq)));
  std::vector<Eigen::Vector3d> even, odd;  // (x, y, mean level) at the inner squares' centres
  for (int r = 0; r + 1 < rows; ++r)
    for (int c = 0; c + 1 < cols; ++c) {
      const cv::Point2f m = 0.25f * (at(r, c) + at(r, c + 1) + at(r + 1, c) + at(r + 1, c + 1));
      const int x0 = static_cast<int>(std::lround(m.x)), y0 = static_cast<int>(std::lround(m.y));
      if (x0 - h < 0 || y0 - h < 0 || x0 + h >= grey.cols || y0 + h >= grey.rows) return corners;
      const double level = cv::mean(grey(cv::Rect(x0 - h, y0 - h, 2 * h + 1, 2 * h + 1)))[0];
      ((r + c) % 2 == 0 ? even : odd).emplace_back(m.x, m.y, level);
    }
  const double scale = std::max(grey.cols, grey.rows);
  const Eigen::VectorXd fe = FitQuadratic(even, scale), fo = FitQuadratic(odd, scale);
  if (fe.size() != 6 || fo.size() != 6) return corners;
  cv::Mat flat(grey.size(), CV_8U);
  for (int y = 0; y < grey.rows; ++y)
    for (int x = 0; x < grey.cols; ++x) {
      const double u = x / scale, v = y / scale;
      Eigen::Matrix<double, 6, 1> b;
      b << 1, u, v, u * u, u * v, v * v;
      const double le = b.dot(fe), lo = b.dot(fo);
      const double white = std::max(le, lo), black = std::min(le, lo);
      const double t = (grey.at<std::uint8_t>(y, x) - black) / std::max(white - black, 1.0);
      flat.at<std::uint8_t>(y, x) = cv::saturate_cast<std::uint8_t>(40 + 175 * t);
    }
  std::vector<cv::Point2f> again;
  if (!cv::findChessboardCornersSB(flat, size, again,
                                   cv::CALIB_CB_ACCURACY | cv::CALIB_CB_EXHAUSTIVE) ||
      again.size() != corners.size())
    return corners;
  // The same corners in the same order (the detector may start from the opposite corner).
  double same_order = 0, reversed = 0;
  for (std::size_t i = 0; i < again.size(); ++i) {
    same_order = std::max(same_order, cv::norm(again[i] - corners[i]));
    reversed = std::max(reversed, cv::norm(again[again.size() - 1 - i] - corners[i]));
  }
  if (reversed < same_order) std::reverse(again.begin(), again.end());
  return std::min(same_order, reversed) < 0.5 * sq ? again : corners;
}

/// The recorded image points of the undistorted points `u` (px), through `lens`'s distortion
/// (OpenCV's model, as ImageToWorld::ToImage); `u` itself without a lens model.
std::vector<Eigen::Vector2d> Distort(const ImageToWorld& lens,
                                     const std::vector<Eigen::Vector2d>& u) {
  if (!lens.distortion || !lens.camera_matrix || u.empty()) return u;
  const auto& k = *lens.camera_matrix;
  std::vector<cv::Point3d> obj;
  for (const auto& x : u) obj.emplace_back((x.x() - k[2]) / k[0], (x.y() - k[5]) / k[4], 1.0);
  std::vector<cv::Point2d> img;
  const cv::Mat K(3, 3, CV_64F, const_cast<double*>(k.data()));
  const cv::Mat D(1, 5, CV_64F, const_cast<double*>(lens.distortion->data()));
  cv::projectPoints(obj, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, D, img);
  std::vector<Eigen::Vector2d> out;
  for (const auto& p : img) out.emplace_back(p.x, p.y);
  return out;
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
    if (found.area() > 0 && !same) {
      // The count found, in the stated order (the longer side first if the stated one is).
      const bool swap = (found.width >= found.height) != (cols >= rows);
      throw std::runtime_error(
          name + ": the checkerboard found has " +
          SizeText(swap ? found.height : found.width, swap ? found.width : found.height) +
          " inner corners, not the " + SizeText(cols, rows) + " stated");
    }
    throw std::runtime_error(name + ": no checkerboard of " + SizeText(cols, rows) +
                             " inner corners found");
  }
  // Found again in the image flattened by the board's own white and black levels: a vignetted
  // or unevenly lit board moves the corners the detector fits toward the darker side, by
  // ~0.015 px at 80 px from the centre of a rendered board (a 0.023 % scale bias, 15 times the
  // residuals' s.e.). The levels are the means of small patches at the centres of the inner
  // squares, each colour fitted with a quadratic in x and y; the image becomes (I - black) /
  // (white - black). (Envelopes by morphology were tried first: beyond the card they fall to
  // the background and tilt the outer corners, a bias of their own, -0.011 %.)
  corners = FlattenedCorners(grey, size, corners);
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
  cv::Mat grey;
  if (image.channels() > 1)
    cv::cvtColor(image, grey, image.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
  else
    grey = image;
  cv::Mat f;
  grey.convertTo(f, CV_64F);
  // The profile is taken along the straight line between the segment's ends in the
  // undistorted image, where the ruler is straight and its ticks evenly spaced, each point
  // read from the recorded image where the lens puts it. (Along the recorded segment instead
  // the period shrinks toward the frame's edges under barrel distortion, and each tick's phase
  // leans toward its nearer neighbour: -0.012 % on rendered rulers.)
  const Eigen::Vector2d from_u = lens.Undistort(from_px), to_u = lens.Undistort(to_px);
  const double length = (to_u - from_u).norm();
  const Eigen::Vector2d u = (to_u - from_u) / length, n(-u.y(), u.x());
  const auto sample = [&f](const Eigen::Vector2d& x) {
    const int x0 = std::clamp(static_cast<int>(std::floor(x.x())), 0, f.cols - 2),
              y0 = std::clamp(static_cast<int>(std::floor(x.y())), 0, f.rows - 2);
    const double fx = std::clamp(x.x() - x0, 0.0, 1.0), fy = std::clamp(x.y() - y0, 0.0, 1.0);
    return (1 - fy) * ((1 - fx) * f.at<double>(y0, x0) + fx * f.at<double>(y0, x0 + 1)) +
           fy * ((1 - fx) * f.at<double>(y0 + 1, x0) + fx * f.at<double>(y0 + 1, x0 + 1));
  };
  // The profile every tenth of a pixel (fine enough that summing it is close to integrating
  // the bilinear interpolant), averaged across the band.
  const double step = 0.1;
  const int m = length < 10 ? 0 : static_cast<int>(std::floor(length / step)) + 1;
  const int n_band = static_cast<int>(2 * band) + 1;
  std::vector<Eigen::Vector2d> ideal;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < n_band; ++j) ideal.push_back(from_u + (i * step) * u + (j - band) * n);
  const std::vector<Eigen::Vector2d> recorded = Distort(lens, ideal);
  std::vector<double> prof(static_cast<std::size_t>(m));
  for (int i = 0; i < m; ++i) {
    double s = 0;
    for (int j = 0; j < n_band; ++j)
      s += sample(recorded[static_cast<std::size_t>(i * n_band + j)]);
    prof[static_cast<std::size_t>(i)] = s / n_band;
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
  cv::Mat in(1, nfft, CV_64F, cv::Scalar::all(0));
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
  // The profile relative to the ruler's own level about each point (the running maximum over a
  // period for dark ticks, minimum for light ones, then averaged over a period): the light
  // falls off toward the frame's edges, and a slope across a tick's window would lean its phase
  // toward the darker side (-0.01 % on rendered rulers with vignetting).
  {
    const bool dark = mean < median;
    const int hw = std::max(1, static_cast<int>(std::lround(0.5 * period0)));
    std::vector<double> env(prof.size()), smooth(prof.size());
    for (int i = 0; i < m; ++i) {
      double e = prof[static_cast<std::size_t>(i)];
      for (int j = std::max(0, i - hw); j <= std::min(m - 1, i + hw); ++j)
        e = dark ? std::max(e, prof[static_cast<std::size_t>(j)])
                 : std::min(e, prof[static_cast<std::size_t>(j)]);
      env[static_cast<std::size_t>(i)] = e;
    }
    for (int i = 0; i < m; ++i) {
      double sum = 0;
      int c = 0;
      for (int j = std::max(0, i - hw); j <= std::min(m - 1, i + hw); ++j, ++c)
        sum += env[static_cast<std::size_t>(j)];
      smooth[static_cast<std::size_t>(i)] = std::max(sum / c, 1e-9);
    }
    for (std::size_t i = 0; i < prof.size(); ++i)
      d[i] = dark ? 1 - prof[i] / smooth[i] : prof[i] / smooth[i] - 1;
  }
  // Each tick's position from the phase of the profile's fundamental over one period centred
  // where the previous tick and the period put it: x = c - P arg(sum (d_i - mean) e^(-2 pi i
  // (i - c) / P)) / (2 pi). A symmetric tick lies where its fundamental peaks; over a whole
  // period the ruler's level and the harmonics drop out, and so do the interpolation's ripples
  // at the pixel pitch. (A centroid above half the peak, tried first, moves a thin tick by a
  // part of a pixel that depends on where it falls on the pixel grid; with a period near a whole
  // number of pixels that error drifts along the ruler and biased the slope by up to 0.07 % on
  // rendered rulers at 5 px per tick.)
  const int n_win = std::max(4, static_cast<int>(std::lround(period0)));
  int first = 0;
  for (int i = 0; i < std::min(m, static_cast<int>(std::ceil(period0))); ++i)
    if (d[static_cast<std::size_t>(i)] > d[static_cast<std::size_t>(first)]) first = i;
  std::vector<double> k_index, pos;
  double expect = first;
  for (int k = 0; expect < m; ++k, expect += period0) {
    // Twice: the window re-centred on the first estimate.
    double at = expect;
    bool ok = true;
    for (int pass = 0; pass < 2 && ok; ++pass) {
      const int lo = static_cast<int>(std::lround(at - 0.5 * n_win));
      if (lo < 0 || lo + n_win > m) {
        ok = false;
        break;
      }
      double mean_w = 0;
      for (int i = lo; i < lo + n_win; ++i) mean_w += d[static_cast<std::size_t>(i)] / n_win;
      double re = 0, im = 0;
      for (int i = lo; i < lo + n_win; ++i) {
        const double ph = 2 * M_PI * (i - at) / period0,
                     v = d[static_cast<std::size_t>(i)] - mean_w;
        re += v * std::cos(ph);
        im -= v * std::sin(ph);
      }
      if (!(std::hypot(re, im) > 0)) {
        ok = false;
        break;
      }
      at -= period0 * std::atan2(im, re) / (2 * M_PI);
    }
    if (!ok) continue;
    k_index.push_back(k);
    pos.push_back(at);
    expect = at;  // follow the ticks (the loop adds the period)
  }
  if (pos.size() < 4)
    throw std::runtime_error(name + ": fewer than 4 ruler ticks found along the segment");
  // Positions along the undistorted line (px).
  std::vector<double> t;
  for (double x : pos) t.push_back(x * step);
  LineFit line = FitLine(k_index, t);
  // One pass without ticks far off the line (a mark or a number on the ruler).
  std::vector<double> abs_r;
  for (double r : line.residuals) abs_r.push_back(std::abs(r));
  const double cut = std::max(5 * 1.4826 * MedianOf(abs_r), 0.05);
  std::vector<double> k2, t2;
  CalibrationScale out;
  std::vector<Eigen::Vector2d> on_line;
  for (std::size_t i = 0; i < t.size(); ++i)
    if (std::abs(line.residuals[i]) <= cut) {
      k2.push_back(k_index[i]);
      t2.push_back(t[i]);
      on_line.push_back(from_u + (pos[i] * step) * u);
    }
  if (k2.size() < 4)
    throw std::runtime_error(name + ": fewer than 4 regular ruler ticks found along the segment");
  out.points_px = Distort(lens, on_line);
  line = FitLine(k2, t2);
  if (!(line.slope > 0) || line.rms > 0.25 * line.slope)
    throw std::runtime_error(name + ": no regular ticks found along the ruler segment");
  // Neighbouring ticks' errors are alike (where a tick falls on the pixel grid drifts slowly
  // along the ruler, as does any lens distortion left over): the slope's s.e. is widened by
  // sqrt((1 + rho) / (1 - rho)), rho the residuals' lag-one autocorrelation (an AR(1) model's
  // variance inflation; rho taken between 0 and 0.95).
  double r01 = 0, r00 = 0;
  for (std::size_t i = 0; i < line.residuals.size(); ++i) {
    r00 += line.residuals[i] * line.residuals[i];
    if (i + 1 < line.residuals.size()) r01 += line.residuals[i] * line.residuals[i + 1];
  }
  const double rho = r00 > 0 ? std::clamp(r01 / r00, 0.0, 0.95) : 0.0;
  out.m_per_px = tick_m / line.slope;
  out.m_per_px_se =
      tick_m * line.slope_se * std::sqrt((1 + rho) / (1 - rho)) / (line.slope * line.slope);
  out.rms_residual_px = line.rms;
  out.points = static_cast<int>(k2.size());
  out.angle_deg = std::atan2(u.y(), u.x()) * 180.0 / M_PI;
  return out;
}

}  // namespace hoof::tracking
