#include "tracking/ball_spin.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include <Eigen/Dense>

#include "tracking/frame_source.h"
#include "tracking/image_sample.h"

namespace hoof::tracking {
namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;

/// (-pi, pi]
double Wrap(double a) {
  a = std::fmod(a + std::numbers::pi, kTwoPi);
  if (a <= 0) a += kTwoPi;
  return a - std::numbers::pi;
}

/// Robust noise s.d. from horizontal second differences, x[k-1] - 2 x[k] + x[k+1], which a
/// brightness gradient (a small ball's shading changes by several levels per pixel) leaves at 0
/// and white noise of s.d. s gives an s.d. of sqrt(6) s: 1.4826 MAD / sqrt(6).
double NeighbourNoise(const cv::Mat& f) {
  std::vector<double> d;
  for (int y = 0; y < f.rows; ++y) {
    const float* row = f.ptr<float>(y);
    for (int x = 1; x + 1 < f.cols; ++x)
      d.push_back(std::abs(row[x - 1] - 2 * row[x] + row[x + 1]));
  }
  if (d.empty()) return 0.0;
  auto mid = d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2);
  std::nth_element(d.begin(), mid, d.end());
  return 1.4826 * *mid / std::sqrt(6.0);
}

/// Takes out of one ring (weighted samples) its mean and first harmonic along the ring.
void RemoveShading(float* v, const float* w, int n) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (int k = 0; k < n; ++k) {
    if (w[k] <= 0) continue;
    const double a = kTwoPi * k / n;
    const Eigen::Vector3d x(1.0, std::cos(a), std::sin(a));
    A += x * x.transpose();
    b += x * v[k];
  }
  const Eigen::Vector3d coef = A.ldlt().solve(b);
  const bool ok = A(0, 0) >= 4 && coef.allFinite();
  for (int k = 0; k < n; ++k) {
    const double a = kTwoPi * k / n;
    v[k] = w[k] > 0 && ok
               ? static_cast<float>(v[k] - coef(0) - coef(1) * std::cos(a) - coef(2) * std::sin(a))
               : 0.0f;
  }
}

/// The correlation at a fractional shift `k` (in samples), interpolated linearly.
double At(const std::vector<double>& c, double k) {
  const int n = static_cast<int>(c.size());
  double f = std::fmod(k, static_cast<double>(n));
  if (f < 0) f += n;
  const int i = static_cast<int>(std::floor(f)) % n;
  const double u = f - std::floor(f);
  return (1 - u) * c[static_cast<std::size_t>(i)] + u * c[static_cast<std::size_t>((i + 1) % n)];
}

/// The local maximum of `c` reached climbing from shift `k0` (samples), refined by a parabola
/// through it and its neighbours; as a shift in samples near k0 (not wrapped).
double ClimbToPeak(const std::vector<double>& c, double k0) {
  const int n = static_cast<int>(c.size());
  long k = std::lround(k0);
  const auto val = [&](long i) { return c[static_cast<std::size_t>(((i % n) + n) % n)]; };
  for (int steps = 0; steps < n; ++steps) {
    if (val(k + 1) > val(k))
      ++k;
    else if (val(k - 1) > val(k))
      --k;
    else
      break;
  }
  const double ym = val(k - 1), y0 = val(k), yp = val(k + 1);
  const double den = ym - 2 * y0 + yp;
  const double d = den < 0 ? 0.5 * (ym - yp) / den : 0.0;
  return static_cast<double>(k) + std::clamp(d, -0.5, 0.5);
}

}  // namespace

void BallSpinOptions::Validate() const {
  if (!(inner_fraction >= 0 && inner_fraction < outer_fraction && outer_fraction <= 1))
    throw std::invalid_argument(
        "spin: inner_fraction and outer_fraction must satisfy 0 <= "
        "inner < outer <= 1");
  if (rings < 1 || rings > 64) throw std::invalid_argument("spin: rings must be in [1, 64]");
  if (angles < 16 || angles > 1024 || (angles & (angles - 1)) != 0)
    throw std::invalid_argument("spin: angles must be a power of two in [16, 1024]");
  if (!(highlight_quantile > 0.5 && highlight_quantile <= 1))
    throw std::invalid_argument("spin: highlight_quantile must be in (0.5, 1]");
  if (!(min_texture_to_noise > 0))
    throw std::invalid_argument("spin: min_texture_to_noise must be > 0");
  if (min_pairs < 1) throw std::invalid_argument("spin: min_pairs must be >= 1");
  if (!(min_radius_px >= 3)) throw std::invalid_argument("spin: min_radius_px must be >= 3");
  if (min_static_faces < 2) throw std::invalid_argument("spin: min_static_faces must be >= 2");
  if (!(alias_margin >= 0 && alias_margin < 1))
    throw std::invalid_argument("spin: alias_margin must be in [0, 1)");
  if (!(min_mean_peak >= 0 && min_mean_peak < 1))
    throw std::invalid_argument("spin: min_mean_peak must be in [0, 1)");
}

BallFace SampleBallFace(const cv::Mat& grey, const Eigen::Vector2d& centre_I, double radius_px,
                        double noise_sd, const BallSpinOptions& options) {
  options.Validate();
  BallFace face;
  face.centre_I = centre_I;
  face.radius_px = radius_px;
  face.texture = cv::Mat(options.rings, options.angles, CV_32F, cv::Scalar::all(0));
  face.weight = cv::Mat(options.rings, options.angles, CV_32F, cv::Scalar::all(0));
  if (!(radius_px >= options.min_radius_px) || !centre_I.allFinite()) {
    std::ostringstream os;
    os << std::setprecision(3) << "the ball is too small to show its texture (" << 2 * radius_px
       << " px across, " << 2 * options.min_radius_px << " needed)";
    face.why = os.str();
    return face;
  }
  // The window of the frame that holds the ball, as unit floats.
  const int x0 = static_cast<int>(std::floor(centre_I.x() - radius_px)) - 1;
  const int y0 = static_cast<int>(std::floor(centre_I.y() - radius_px)) - 1;
  const int side = static_cast<int>(std::ceil(2 * radius_px)) + 3;
  const cv::Rect box = cv::Rect(x0, y0, side, side) & cv::Rect(0, 0, grey.cols, grey.rows);
  if (box.width < 3 || box.height < 3) {
    face.why = "the ball lies outside the frame";
    return face;
  }
  const cv::Mat f = ToUnitFloat(grey(box));
  const double cx = centre_I.x() - box.x, cy = centre_I.y() - box.y;
  std::vector<float> all;
  for (int r = 0; r < options.rings; ++r) {
    const double rho =
        radius_px * (options.inner_fraction +
                     (options.outer_fraction - options.inner_fraction) * (r + 0.5) / options.rings);
    float* v = face.texture.ptr<float>(r);
    float* w = face.weight.ptr<float>(r);
    for (int k = 0; k < options.angles; ++k) {
      const double a = kTwoPi * k / options.angles;
      double value = 0;
      if (SampleBilinear(f, cx + rho * std::cos(a), cy + rho * std::sin(a), value)) {
        v[k] = static_cast<float>(value);
        w[k] = 1.0f;
        all.push_back(v[k]);
      }
    }
  }
  if (all.size() < static_cast<std::size_t>(options.angles)) {
    face.why = "the ball lies mostly outside the frame";
    return face;
  }
  // The highlight: the brightest samples stay where the light is.
  auto q = all.begin() + static_cast<std::ptrdiff_t>(options.highlight_quantile *
                                                     static_cast<double>(all.size() - 1));
  std::nth_element(all.begin(), q, all.end());
  const float bright = *q;
  double ss = 0, sw = 0;
  for (int r = 0; r < options.rings; ++r) {
    float* v = face.texture.ptr<float>(r);
    float* w = face.weight.ptr<float>(r);
    for (int k = 0; k < options.angles; ++k)
      if (w[k] > 0 && v[k] > bright && options.highlight_quantile < 1) w[k] = 0;
    RemoveShading(v, w, options.angles);
    for (int k = 0; k < options.angles; ++k) {
      ss += w[k] * v[k] * v[k];
      sw += w[k];
    }
  }
  face.texture_sd = sw > 0 ? std::sqrt(ss / sw) : 0.0;
  face.noise_sd = noise_sd > 0 ? noise_sd : NeighbourNoise(f);
  face.textured = face.texture_sd > options.min_texture_to_noise * face.noise_sd;
  if (!face.textured)
    face.why = "the ball shows no texture that turns with it (texture s.d. " +
               std::to_string(face.texture_sd) + ", noise " + std::to_string(face.noise_sd) + ")";
  return face;
}

std::vector<double> FaceCorrelation(const BallFace& a, const BallFace& b) {
  if (a.texture.size() != b.texture.size() || a.texture.empty())
    throw std::invalid_argument("spin: faces sampled alike are needed");
  cv::Mat A, B, prod, r;
  cv::dft(a.texture, A, cv::DFT_ROWS | cv::DFT_COMPLEX_OUTPUT);
  cv::dft(b.texture, B, cv::DFT_ROWS | cv::DFT_COMPLEX_OUTPUT);
  // B conj(A): entry k of the inverse is sum_j a[j] b[j + k], largest where b is a turned by k.
  cv::mulSpectrums(B, A, prod, cv::DFT_ROWS, true);
  cv::idft(prod, r, cv::DFT_ROWS | cv::DFT_REAL_OUTPUT | cv::DFT_SCALE);
  const double norm =
      std::sqrt(cv::sum(a.texture.mul(a.texture))[0] * cv::sum(b.texture.mul(b.texture))[0]);
  std::vector<double> c(static_cast<std::size_t>(r.cols), 0.0);
  for (int y = 0; y < r.rows; ++y)
    for (int k = 0; k < r.cols; ++k) c[static_cast<std::size_t>(k)] += r.at<float>(y, k);
  for (double& x : c) x = norm > 0 ? x / norm : 0.0;
  return c;
}

FaceTurn BestTurn(const std::vector<double>& correlation) {
  if (correlation.empty()) return {};
  const auto best = std::max_element(correlation.begin(), correlation.end());
  const double k = ClimbToPeak(correlation, static_cast<double>(best - correlation.begin()));
  const double n = static_cast<double>(correlation.size());
  return {Wrap(kTwoPi * k / n), At(correlation, k)};
}

ArcSpin FitArcSpin(const std::vector<BallFace>& faces, const std::vector<double>& t_s,
                   const BallSpinOptions& options) {
  options.Validate();
  if (faces.size() != t_s.size()) throw std::invalid_argument("spin: one time per face is needed");
  ArcSpin out;
  // What stays where it is in the image from frame to frame (the shading that the ring's first
  // harmonic does not hold: the light's terminator, the camera's gamma) is the mean of the
  // arc's faces, the texture turning under it. It is taken out of each face, so that it does
  // not pull every pair's correlation toward no turn.
  std::vector<BallFace> turning = faces;
  int textured = 0;
  for (const auto& f : faces) textured += f.textured && f.texture.size == faces[0].texture.size;
  if (textured >= options.min_static_faces) {
    cv::Mat sum(faces[0].texture.size(), CV_32F, cv::Scalar::all(0)), count = sum.clone();
    for (const auto& f : faces) {
      if (!f.textured || f.texture.size != faces[0].texture.size) continue;
      sum += f.texture.mul(f.weight);
      count += f.weight;
    }
    cv::Mat mean;
    cv::divide(sum, cv::max(count, 1.0f), mean);
    for (auto& f : turning)
      if (f.textured && f.texture.size == faces[0].texture.size)
        f.texture = (f.texture - mean).mul(f.weight);
  }
  struct Pair {
    double dt;
    std::vector<double> c;
  };
  std::vector<Pair> pairs;
  for (std::size_t i = 0; i + 1 < turning.size(); ++i) {
    const double dt = t_s[i + 1] - t_s[i];
    if (!(dt > 0) || !turning[i].textured || !turning[i + 1].textured) continue;
    pairs.push_back({dt, FaceCorrelation(turning[i], turning[i + 1])});
  }
  out.pairs = static_cast<int>(pairs.size());
  if (out.pairs < options.min_pairs) {
    std::string why;
    for (const auto& f : faces)
      if (!f.textured && !f.why.empty()) why = f.why;
    out.why = std::to_string(out.pairs) + " pairs of consecutive frames show its texture (" +
              std::to_string(options.min_pairs) + " needed)" +
              (why.empty() ? std::string() : ": " + why);
    return out;
  }
  const double n = options.angles;
  double dt_min = pairs.front().dt, dt_max = dt_min;
  for (const auto& p : pairs) {
    dt_min = std::min(dt_min, p.dt);
    dt_max = std::max(dt_max, p.dt);
  }
  // Rates up to half a turn per closest frames, in steps of a quarter sample at the widest.
  const double w_max = std::numbers::pi / dt_min;
  const double step = 0.25 * (kTwoPi / n) / dt_max;
  const auto score = [&](double w) {
    double s = 0;
    for (const auto& p : pairs) s += At(p.c, w * p.dt * n / kTwoPi);
    return s;
  };
  std::vector<double> rates, scores;
  for (double w = -w_max; w <= w_max; w += step) {
    rates.push_back(w);
    scores.push_back(score(w));
  }
  const double s_best = *std::max_element(scores.begin(), scores.end());
  // A pattern that repeats around the ball (a cross every quarter turn) scores as well at each
  // of its aliases: of the peaks within options.alias_margin of the best, the slowest is
  // taken, the pattern turning by less than half its period between frames.
  double w_best = 0;
  bool chosen = false;
  for (std::size_t i = 0; i < rates.size(); ++i) {
    const bool peak = (i == 0 || scores[i] >= scores[i - 1]) &&
                      (i + 1 == rates.size() || scores[i] >= scores[i + 1]);
    if (!peak || scores[i] < s_best - options.alias_margin * std::abs(s_best)) continue;
    if (!chosen || std::abs(rates[i]) < std::abs(w_best)) w_best = rates[i];
    chosen = true;
  }
  // Each pair's own peak nearest the rate found; the rate through them by least squares.
  std::vector<double> turns;
  for (int iteration = 0; iteration < 3; ++iteration) {
    turns.clear();
    double num = 0, den = 0;
    for (const auto& p : pairs) {
      const double k = ClimbToPeak(p.c, w_best * p.dt * n / kTwoPi);
      const double turn = kTwoPi * k / n;
      turns.push_back(turn);
      num += turn * p.dt;
      den += p.dt * p.dt;
    }
    w_best = num / den;
  }
  double ss = 0, den = 0, peak = 0;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const double r = turns[i] - w_best * pairs[i].dt;
    ss += r * r;
    den += pairs[i].dt * pairs[i].dt;
    peak += At(pairs[i].c, w_best * pairs[i].dt * n / kTwoPi);
  }
  // One turn's resolution (a sample) as the floor of its error: the pairs may agree exactly.
  const double floor_turn = kTwoPi / n / std::sqrt(12.0);
  const double s2 = pairs.size() > 1 ? ss / static_cast<double>(pairs.size() - 1) : 0.0;
  out.w_I_rad_s = w_best;
  out.w_se_rad_s = std::sqrt(std::max(s2, floor_turn * floor_turn) / den);
  out.mean_peak = peak / static_cast<double>(pairs.size());
  if (out.mean_peak < options.min_mean_peak) {
    std::ostringstream os;
    os << std::setprecision(2) << "its faces, turned by the best spin, correlate at "
       << out.mean_peak << " on average (" << options.min_mean_peak
       << " needed): what changes between frames is not a texture turning";
    out.why = os.str();
    return out;
  }
  out.measured = true;
  return out;
}

}  // namespace hoof::tracking
