#include "tracking/frame_timing.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include <Eigen/Dense>

#include "tracking/frame_differences.h"

namespace hoof::tracking {
namespace {

double Quantile(std::vector<double> v, double q) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto k = static_cast<std::size_t>(std::floor(q * static_cast<double>(v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

/// The median of `v` (element v.size() / 2 in sorted order: the upper one of an even count),
/// exactly, in a few linear passes instead of a selection over every value (written here: no
/// Debian library has one; 3-4 times faster than std::nth_element on a frame's grid). A
/// histogram of 256 bins between the least and the greatest value finds the bin that holds it;
/// that bin's values are taken and binned again until few are left, which are then ordered.
/// Binning is monotone in the value, so the order of the bins is the order of their values.
/// `scratch` is reused; `v` is not changed. v must hold finite values; empty gives NaN.
double Median(const std::vector<double>& v, std::vector<double>& scratch) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  constexpr int kBins = 256;
  std::size_t k = v.size() / 2;
  const std::vector<double>* values = &v;
  std::vector<double> next;
  while (values->size() > 64) {
    const auto [lo_it, hi_it] = std::minmax_element(values->begin(), values->end());
    const double lo = *lo_it, hi = *hi_it;
    if (!(hi > lo)) return lo;  // all equal
    const double scale = kBins / (hi - lo);
    const auto bin = [lo, scale](double x) {
      return std::min(kBins - 1, static_cast<int>((x - lo) * scale));
    };
    std::array<std::size_t, kBins> count{};
    for (double x : *values) ++count[static_cast<std::size_t>(bin(x))];
    int b = 0;
    while (count[static_cast<std::size_t>(b)] <= k) k -= count[static_cast<std::size_t>(b++)];
    next.clear();
    for (double x : *values)
      if (bin(x) == b) next.push_back(x);
    if (next.size() == values->size()) break;  // cannot be split further (rounding): select
    scratch.swap(next);
    values = &scratch;
  }
  std::vector<double> last(values->begin(), values->end());
  std::nth_element(last.begin(), last.begin() + static_cast<std::ptrdiff_t>(k), last.end());
  return last[k];
}

template <typename T>
void SampleRows(const cv::Mat& grey, int step, double scale, std::vector<double>& out) {
  std::size_t k = 0;
  for (int y = step / 2; y < grey.rows; y += step) {
    const T* row = grey.ptr<T>(y);
    for (int x = step / 2; x < grey.cols; x += step) out[k++] = static_cast<double>(row[x]) * scale;
  }
}

/// Every `step`-th pixel of every `step`-th row, in units of the file's full scale, into `out`
/// (resized to fit).
void SampleGrid(const cv::Mat& image, int step, std::vector<double>& out) {
  const cv::Mat grey = image.channels() == 1 ? image : ToGrey(image, "frame");
  const auto along = [step](int n) {
    return static_cast<std::size_t>(n <= step / 2 ? 0 : (n - step / 2 + step - 1) / step);
  };
  out.resize(along(grey.rows) * along(grey.cols));
  switch (grey.depth()) {
    case CV_8U:
      SampleRows<std::uint8_t>(grey, step, 1.0 / 255.0, out);
      break;
    case CV_16U:
      SampleRows<std::uint16_t>(grey, step, 1.0 / 65535.0, out);
      break;
    case CV_32F:
      SampleRows<float>(grey, step, 1.0, out);
      break;
    case CV_64F:
      SampleRows<double>(grey, step, 1.0, out);
      break;
    default:
      throw std::runtime_error("frame timing: unsupported image depth " +
                               std::to_string(grey.depth()));
  }
}

/// The robust levels of a frame pair are medians over every k-th grid pixel: the brightness
/// gain and the difference's median, nuisance levels, over at most kLevelSamples (a median of
/// 1024 values is within about 4 % of the noise s.d. of the true one, which moves the mean
/// absolute difference by far less); the noise s.d. over at most kNoiseSamples (its clip-wide
/// level is a quantile over every frame's, which averages further). The mean absolute
/// difference uses every grid pixel. The medians are most of the comparison's cost, which
/// runs on the reader thread of `track` (bench/silhouette_bench.cc, timing:1).
constexpr std::size_t kLevelSamples = 1024;
constexpr std::size_t kNoiseSamples = 8192;

/// Residual sum of squares of p = c + v s + a s^2 (per coordinate) over the samples.
double ParabolaSsr(const std::vector<double>& s, const std::vector<Eigen::Vector2d>& p) {
  const auto m = static_cast<Eigen::Index>(s.size());
  double s_mean = 0;
  for (double x : s) s_mean += x / static_cast<double>(m);
  Eigen::MatrixXd X(m, 3), Y(m, 2);
  for (Eigen::Index i = 0; i < m; ++i) {
    const double u = s[static_cast<std::size_t>(i)] - s_mean;
    X.row(i) << 1.0, u, u * u;
    Y.row(i) = p[static_cast<std::size_t>(i)].transpose();
  }
  const Eigen::MatrixXd beta = X.colPivHouseholderQr().solve(Y);
  return (Y - X * beta).squaredNorm();
}

/// The slots of samples [a, b] (relative to a) from their gaps.
std::vector<double> SegmentSlots(const std::vector<int>& gap, std::size_t a, std::size_t b) {
  std::vector<double> s{0.0};
  for (std::size_t k = a; k < b; ++k) s.push_back(s.back() + gap[k]);
  return s;
}

double SegmentSsr(const std::vector<int>& gap, const std::vector<Eigen::Vector2d>& p, std::size_t a,
                  std::size_t b) {
  return ParabolaSsr(SegmentSlots(gap, a, b),
                     std::vector<Eigen::Vector2d>(p.begin() + static_cast<std::ptrdiff_t>(a),
                                                  p.begin() + static_cast<std::ptrdiff_t>(b + 1)));
}

/// Adds dropped captures to the gaps of samples [a, b]: forward selection, one at a time where
/// one lowers the parabola's residual the most (after each, a drop already placed moves to
/// another gap where that lowers it), up to a third of the samples; then the drops are kept
/// whose steps each lowered the residual by more than drop_significance times the residual
/// variance of the last model (at least position_noise_floor_px^2), a model that explains
/// every drop, so that two drops in one flight do not hide each other.
void FindDropsInFlight(std::vector<int>& gap, const std::vector<Eigen::Vector2d>& p, std::size_t a,
                       std::size_t b, const FrameTimingOptions& options) {
  const std::size_t m = b - a + 1;
  if (m < 5) return;
  const std::vector<int> base(gap.begin(), gap.end());
  std::vector<std::vector<int>> step_gaps{gap};
  std::vector<double> step_ssr{SegmentSsr(gap, p, a, b)};
  double ssr = step_ssr.back();
  for (std::size_t added = 0; added < std::max<std::size_t>(1, m / 3); ++added) {
    double best = ssr;
    std::size_t best_k = b;
    for (std::size_t k = a; k < b; ++k) {
      ++gap[k];
      const double trial = SegmentSsr(gap, p, a, b);
      --gap[k];
      if (trial < best) {
        best = trial;
        best_k = k;
      }
    }
    if (best_k == b) break;
    ++gap[best_k];
    ssr = best;
    for (bool moved = true; moved;) {
      moved = false;
      for (std::size_t from = a; from < b && !moved; ++from) {
        if (gap[from] <= base[from]) continue;
        for (std::size_t to = a; to < b && !moved; ++to) {
          if (to == from) continue;
          --gap[from];
          ++gap[to];
          const double trial = SegmentSsr(gap, p, a, b);
          if (trial < ssr - 1e-12 * (1 + ssr)) {
            ssr = trial;
            moved = true;
          } else {
            ++gap[from];
            --gap[to];
          }
        }
      }
    }
    step_gaps.push_back(gap);
    step_ssr.push_back(ssr);
  }
  const double dof = 2.0 * static_cast<double>(m) - 6.0;
  const double floor2 = options.position_noise_floor_px * options.position_noise_floor_px;
  const double variance = std::max(step_ssr.back() / dof, floor2);
  std::size_t keep = 0;
  while (keep + 1 < step_ssr.size() &&
         step_ssr[keep] - step_ssr[keep + 1] > options.drop_significance * variance)
    ++keep;
  gap = step_gaps[keep];
  // Local evidence: a drop stays only where the step across its gap is nearer the neighbouring
  // steps' velocity times the new gap than times one slot fewer (a model error near an impact,
  // which the parabola can take for a drop, leaves the step itself ordinary).
  for (std::size_t k = a + 1; k + 1 < b; ++k) {
    const Eigen::Vector2d v =
        0.5 * ((p[k] - p[k - 1]) / gap[k - 1] + (p[k + 2] - p[k + 1]) / gap[k + 1]);
    const Eigen::Vector2d d = p[k + 1] - p[k];
    while (gap[k] > base[k] && (d - gap[k] * v).norm() >= (d - (gap[k] - 1) * v).norm()) --gap[k];
  }
}

}  // namespace

void FrameTimingOptions::Validate() const {
  if (!(repeat_fraction_of_noise > 0 && repeat_fraction_of_noise < 1))
    throw std::invalid_argument("frame timing repeat_fraction_of_noise must be in (0, 1)");
  if (max_grid_pixels < 1000)
    throw std::invalid_argument("frame timing max_grid_pixels must be >= 1000");
  if (!(drop_significance > 0))
    throw std::invalid_argument("frame timing drop_significance must be > 0");
  if (!(position_noise_floor_px > 0))
    throw std::invalid_argument("frame timing position_noise_floor_px must be > 0");
  if (!(repeat_step_ratio > 0 && repeat_step_ratio < 1))
    throw std::invalid_argument("frame timing repeat_step_ratio must be in (0, 1)");
  if (!(repeat_min_motion_px > 0))
    throw std::invalid_argument("frame timing repeat_min_motion_px must be > 0");
  if (!(repeat_motion_fraction > 0 && repeat_motion_fraction < 1))
    throw std::invalid_argument("frame timing repeat_motion_fraction must be in (0, 1)");
}

std::string TimingSourceName(TimingSource source) {
  switch (source) {
    case TimingSource::kTimeStamps:
      return "time_stamps";
    case TimingSource::kMotion:
      return "motion";
    case TimingSource::kFrameIndex:
      break;
  }
  return "frame_index";
}

FrameDifferencer::FrameDifferencer(int max_grid_pixels) : max_grid_pixels_(max_grid_pixels) {
  if (max_grid_pixels < 1)
    throw std::invalid_argument("frame timing: max_grid_pixels must be 1 or more");
}

void FrameDifferencer::Add(const cv::Mat& image, const std::string& what) {
  if (frames_ == 0) {
    const double pixels = static_cast<double>(image.rows) * image.cols;
    step_ = std::max(1, static_cast<int>(std::ceil(std::sqrt(pixels / max_grid_pixels_))));
  }
  SampleGrid(image, step_, grid_);
  double mean_abs = std::nan(""), noise_sd = std::nan("");
  if (frames_ > 0) {
    if (grid_.size() != previous_.size())
      throw std::runtime_error(what + ": its size differs from the frame before");
    // The overall brightness may change (flicker multiplies the image): the previous frame
    // is scaled by the median ratio of the two first.
    const std::size_t n = grid_.size();
    const auto every = [n](std::size_t at_most) {
      return std::max<std::size_t>(1, (n + at_most - 1) / at_most);
    };
    const std::size_t level_every = every(kLevelSamples), noise_every = every(kNoiseSamples);
    some_.clear();
    for (std::size_t k = 0; k < n; k += level_every)
      if (previous_[k] > 0) some_.push_back(grid_[k] / previous_[k]);
    const double gain = some_.empty() ? 1.0 : Median(some_, scratch_);
    some_.clear();
    for (std::size_t k = 0; k < n; k += level_every)
      some_.push_back(grid_[k] - gain * previous_[k]);
    const double median = Median(some_, scratch_);
    double sum = 0;
    for (std::size_t k = 0; k < n; ++k) sum += std::abs(grid_[k] - gain * previous_[k] - median);
    some_.clear();
    for (std::size_t k = 0; k < n; k += noise_every)
      some_.push_back(std::abs(grid_[k] - gain * previous_[k] - median));
    mean_abs = sum / static_cast<double>(n);
    noise_sd = 1.4826 * Median(some_, scratch_);
  }
  d_.mean_abs_difference.push_back(mean_abs);
  d_.noise_sd.push_back(noise_sd);
  std::swap(previous_, grid_);
  ++frames_;
}

ImageDifferences FrameDifferencer::Finish() const {
  ImageDifferences d = d_;
  std::vector<double> sd(d.noise_sd.begin() + (frames_ > 0 ? 1 : 0), d.noise_sd.end());
  d.noise_mean_abs_difference =
      sd.empty() ? 0.0 : std::sqrt(2 / std::numbers::pi) * Quantile(sd, 0.75);
  return d;
}

DifferencingSource::DifferencingSource(FrameSource& inner, int max_grid_pixels, bool compare)
    : inner_(inner), compare_(compare), differencer_(max_grid_pixels) {}

cv::Mat DifferencingSource::Read(int index) {
  cv::Mat image = inner_.Read(index);
  if (!compare_) return image;
  std::lock_guard lock(mutex_);
  if (index == differencer_.frames_added()) differencer_.Add(image, inner_.Describe(index));
  return image;
}

cv::Mat DifferencingSource::ReadColour(int index) {
  cv::Mat image = inner_.ReadColour(index);
  if (!compare_) return image;
  std::lock_guard lock(mutex_);
  if (index == differencer_.frames_added())
    differencer_.Add(ToGrey(image, inner_.Describe(index)), inner_.Describe(index));
  return image;
}

std::optional<ImageDifferences> DifferencingSource::Differences() const {
  if (!compare_) return std::nullopt;
  std::lock_guard lock(mutex_);
  if (differencer_.frames_added() != inner_.count()) return std::nullopt;
  return differencer_.Finish();
}

ImageDifferences DifferenceFrames(FrameSource& source, int max_grid_pixels) {
  FrameDifferencer differencer(max_grid_pixels);
  for (int i = 0; i < source.count(); ++i) differencer.Add(source.Read(i), source.Describe(i));
  return differencer.Finish();
}

std::vector<bool> FindRepeats(const ImageDifferences& d, double fraction) {
  std::vector<bool> repeat(d.mean_abs_difference.size(), false);
  double limit = fraction * d.noise_mean_abs_difference;
  if (!(limit > 0)) {
    std::vector<double> D;
    for (std::size_t i = 1; i < repeat.size(); ++i)
      if (std::isfinite(d.mean_abs_difference[i])) D.push_back(d.mean_abs_difference[i]);
    limit = D.size() >= 4 ? 0.1 * fraction * Quantile(D, 0.75) : 0.0;
    // Only where the copies stand apart, the smallest difference above the limit at least 3
    // times the largest below it: a small body in a large still frame changes it so little
    // that copies and new captures overlap (its positions must tell them apart instead).
    double below = 0.0, above = std::numeric_limits<double>::infinity();
    for (double x : D) {
      if (x < limit)
        below = std::max(below, x);
      else
        above = std::min(above, x);
    }
    if (!(above >= 3 * below)) limit = 0.0;
  }
  for (std::size_t i = 1; i < repeat.size(); ++i) {
    const double D = d.mean_abs_difference[i];
    repeat[i] = D == 0.0 || D < limit;
  }
  return repeat;
}

std::vector<bool> RepeatsFromMotion(const std::vector<std::optional<Eigen::Vector2d>>& p,
                                    const FrameTimingOptions& options, int* candidates,
                                    int* moving) {
  const std::size_t n = p.size();
  std::vector<bool> repeat(n, false);
  // step[i]: the body's move from frame i - 1 to frame i (NaN where either is not found).
  std::vector<double> step(n, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 1; i < n; ++i)
    if (p[i] && p[i - 1]) step[i] = (*p[i] - *p[i - 1]).norm();
  int found = 0, moves = 0;
  for (std::size_t i = 1; i < n; ++i) {
    if (!std::isfinite(step[i])) continue;
    double around = 0.0;  // the larger of the steps into frame i - 1 and out of frame i
    if (std::isfinite(step[i - 1])) around = step[i - 1];
    if (i + 1 < n && std::isfinite(step[i + 1])) around = std::max(around, step[i + 1]);
    if (!(around >= options.repeat_min_motion_px)) continue;
    ++moves;
    if (step[i] < options.repeat_step_ratio * around) {
      repeat[i] = true;
      ++found;
    }
  }
  if (candidates) *candidates = found;
  if (moving) *moving = moves;
  if (found < 4 || found < options.repeat_motion_fraction * moves) repeat.assign(n, false);
  return repeat;
}

MotionRepeats AddRepeatsFromMotion(const std::vector<std::optional<Eigen::Vector2d>>& p,
                                   const FrameTimingOptions& options, std::vector<bool>& repeat) {
  std::vector<std::optional<Eigen::Vector2d>> q = p;
  q.resize(repeat.size());
  MotionRepeats m;
  const std::vector<bool> still = RepeatsFromMotion(q, options, &m.candidates, &m.moving);
  for (std::size_t i = 0; i < repeat.size(); ++i)
    if (still[i]) {
      ++m.taken;
      m.shown += repeat[i] ? 1 : 0;
    }
  m.used = m.taken > 0 && 2 * m.shown < m.taken;
  if (m.used)
    for (std::size_t i = 0; i < repeat.size(); ++i)
      if (still[i] && !repeat[i]) {
        repeat[i] = true;
        ++m.added;
      }
  return m;
}

HeldImageEvidence HeldImageFromMotion(const std::vector<std::optional<Eigen::Vector2d>>& p,
                                      const std::vector<bool>& repeat) {
  HeldImageEvidence e;
  const std::size_t n = std::min(p.size(), repeat.size());
  const auto sample = [&](std::size_t i) { return i < n && !repeat[i] && p[i].has_value(); };
  std::vector<double> ratios;
  for (std::size_t r = 2; r + 1 < n; ++r) {
    if (!repeat[r] || repeat[r - 1] || repeat[r + 1]) continue;
    if (!sample(r - 2) || !sample(r - 1) || !sample(r + 1)) continue;
    const double in = (*p[r - 1] - *p[r - 2]).norm(), out = (*p[r + 1] - *p[r - 1]).norm();
    if (!(in > 0.5 && out > 0.5)) continue;  // the body hardly moves: no evidence
    ratios.push_back(std::log2(out / in));
  }
  e.runs = static_cast<int>(ratios.size());
  if (ratios.empty()) return e;
  e.log2_step_ratio = Quantile(ratios, 0.5);
  if (e.runs >= 3 && e.log2_step_ratio < -0.5) e.held = HeldImage::kLast;
  return e;
}

std::vector<bool> SampleAtLastCopy(const std::vector<bool>& repeat) {
  std::vector<bool> out = repeat;
  for (std::size_t i = 1; i < repeat.size(); ++i) {
    if (!repeat[i] || repeat[i - 1]) continue;
    std::size_t last = i;
    while (last + 1 < repeat.size() && repeat[last + 1]) ++last;
    out[i - 1] = true;  // the run's first frame: shown early
    out[last] = false;  // the run's last frame: the capture at its own time
  }
  // The clip's last frame, unless a copy, may be shown early with its copy cut off.
  if (out.size() > 1 && !repeat.back()) out.back() = true;
  return out;
}

std::optional<std::vector<int>> SlotsFromStamps(const std::vector<double>& stamps_s, double fps) {
  std::vector<int> slot;
  for (std::size_t i = 0; i < stamps_s.size(); ++i) {
    if (!std::isfinite(stamps_s[i])) return std::nullopt;
    slot.push_back(static_cast<int>(std::lround((stamps_s[i] - stamps_s[0]) * fps)));
    if (i > 0 && slot[i] <= slot[i - 1]) return std::nullopt;
  }
  return slot;
}

std::vector<int> SlotsFromMotion(const std::vector<std::optional<Eigen::Vector2d>>& p,
                                 const std::vector<bool>& repeat, const Eigen::Vector2d& down,
                                 const FrameTimingOptions& options) {
  const std::size_t n = p.size();
  // The samples: frames with a position that are not repeats; gap[k] slots from sample k to
  // k + 1 (every frame between them, repeat or not found, takes one).
  std::vector<int> frame;
  std::vector<Eigen::Vector2d> q;
  for (std::size_t i = 0; i < n; ++i)
    if (p[i] && !(i < repeat.size() && repeat[i])) {
      frame.push_back(static_cast<int>(i));
      q.push_back(*p[i]);
    }
  std::vector<int> gap;
  for (std::size_t k = 0; k + 1 < frame.size(); ++k) gap.push_back(frame[k + 1] - frame[k]);
  // Impacts: the height along -down has a deep minimum (2 samples on each side higher by 20
  // noise floors); the lowest sample joins the flight it fits better.
  std::vector<double> h;
  const Eigen::Vector2d up = -down.normalized();
  for (const auto& x : q) h.push_back(up.dot(x));
  const double deep = 20 * options.position_noise_floor_px;
  std::vector<std::size_t> starts{0};  // first sample of each flight
  for (std::size_t j = 2; j + 2 < q.size(); ++j) {
    if (!(h[j] < h[j - 1] && h[j] <= h[j + 1] && h[j - 2] - h[j] > deep && h[j + 2] - h[j] > deep))
      continue;
    const std::size_t a = starts.back();
    std::size_t next = j + 1;
    std::size_t b = q.size() - 1;
    for (std::size_t k = j + 3; k + 2 < q.size(); ++k)
      if (h[k] < h[k - 1] && h[k] <= h[k + 1]) {
        b = k - 1;
        break;
      }
    if (j - a >= 3 && b - j >= 3 &&
        SegmentSsr(gap, q, a, j - 1) + SegmentSsr(gap, q, j, b) <
            SegmentSsr(gap, q, a, j) + SegmentSsr(gap, q, j + 1, b))
      next = j;
    starts.push_back(next);
  }
  starts.push_back(q.size());
  for (std::size_t s = 0; s + 1 < starts.size(); ++s)
    if (starts[s + 1] > starts[s] + 1)
      FindDropsInFlight(gap, q, starts[s], starts[s + 1] - 1, options);
  // Slots: one per frame; the extra slots of a gap are put after the frames before the sample
  // that closes it.
  std::vector<int> slot(n, 0);
  std::size_t k = 0;
  int extra = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (k + 1 < frame.size() && static_cast<int>(i) == frame[k + 1]) {
      extra += gap[k] - (frame[k + 1] - frame[k]);
      ++k;
    }
    slot[i] = static_cast<int>(i) + extra;
  }
  return slot;
}

FrameTiming UniformTiming(int frame_count, double fps) {
  FrameTiming t;
  t.fps = fps;
  for (int i = 0; i < frame_count; ++i) {
    t.slot.push_back(i);
    t.t_s.push_back(i / fps);
    t.repeat.push_back(false);
  }
  return t;
}

std::optional<std::vector<double>> TimeStamps(const FrameSource& source) {
  std::vector<double> t;
  for (int i = 0; i < source.count(); ++i) {
    const auto ti = source.TimeOf(i);
    if (!ti) return std::nullopt;
    t.push_back(*ti);
  }
  return t;
}

FrameTiming AnalyzeFrameTiming(FrameSource& source, double fps,
                               const std::optional<std::vector<double>>& stamps_s,
                               const std::vector<std::optional<Eigen::Vector2d>>& p,
                               const Eigen::Vector2d& down, const FrameTimingOptions& options) {
  options.Validate();
  return AnalyzeFrameTiming(DifferenceFrames(source, options.max_grid_pixels), fps, stamps_s, p,
                            down, options);
}

FrameTiming AnalyzeFrameTiming(const ImageDifferences& differences, double fps,
                               const std::optional<std::vector<double>>& stamps_s,
                               const std::vector<std::optional<Eigen::Vector2d>>& p,
                               const Eigen::Vector2d& down, const FrameTimingOptions& options) {
  options.Validate();
  const int n = static_cast<int>(differences.mean_abs_difference.size());
  FrameTiming t = UniformTiming(n, fps);
  t.differences = differences;
  t.repeat = FindRepeats(t.differences, options.repeat_fraction_of_noise);
  int repeats = 0;
  for (bool r : t.repeat) repeats += r ? 1 : 0;
  {
    std::ostringstream os;
    os << repeats << " of " << n
       << " frames repeat the previous image (mean absolute difference 0, or under "
       << options.repeat_fraction_of_noise << " of the noise-only difference of two captures, "
       << t.differences.noise_mean_abs_difference
       << " of full scale, or where that is 0 under a tenth of that fraction of the upper quartile "
          "of the frames' differences); they are not samples of the motion";
    t.notes.push_back(os.str());
  }
  {
    const MotionRepeats m = AddRepeatsFromMotion(p, options, t.repeat);
    repeats += m.added;
    std::ostringstream os;
    os << "the body stands still for a frame while it moves in " << m.candidates << " of "
       << m.moving << " frames (under " << options.repeat_step_ratio
       << " of the step before or after, of at least " << options.repeat_min_motion_px << " px)";
    if (m.used)
      os << ": the clip holds its images, and those frames are repeats too (" << m.added
         << " more than the images show)";
    else if (m.taken > 0)
      os << ": the images show " << m.shown << " of them as repeats, so the images decide";
    else
      os << ": fewer than " << options.repeat_motion_fraction
         << " of them, or fewer than 4, so none are taken from the motion";
    t.notes.push_back(os.str());
  }
  if (repeats > 0) {
    const HeldImageEvidence held = HeldImageFromMotion(p, t.repeat);
    std::ostringstream os;
    if (held.held == HeldImage::kLast) {
      t.held = HeldImage::kLast;
      t.repeat = SampleAtLastCopy(t.repeat);
      os << "each repeated image is shown early, in place of a capture left out (a frame-rate "
            "conversion): the body moves 2^"
         << held.log2_step_ratio
         << " as far from it to the next sample as to it from the one before (median of "
         << held.runs << " repeats), so its last copy is the sample";
    } else {
      os << "each repeated image is the capture of its first copy (the step after a copy over the "
            "step before it: 2^"
         << held.log2_step_ratio << ", median of " << held.runs << " repeats)";
    }
    t.notes.push_back(os.str());
  }
  for (int i = 0; i < n; ++i)
    if (t.repeat[static_cast<std::size_t>(i)]) t.repeated_frames.push_back(i);
  // A clip that holds its images. A camera that re-sends its buffer in place of a lost capture
  // shows its copies a period late, at the first copy's time exactly, but loses far fewer than
  // a quarter of its captures; the steps about single copies do not tell the two apart (a
  // screen recording's jitter shows a capture once where the next came early).
  if (t.held == HeldImage::kFirst && n > 0 && 4 * static_cast<int>(t.repeated_frames.size()) >= n) {
    t.capture_time_sd_s = 1.0 / (fps * std::sqrt(12.0));
    std::ostringstream os;
    os << "the clip holds its images (" << t.repeated_frames.size() << " of " << n
       << " frames repeat): an image was captured some time in the frame period before its first "
          "copy, so each sample's time has an s.d. of "
       << t.capture_time_sd_s * 1e3 << " ms, carried into its position along its motion";
    t.notes.push_back(os.str());
  }
  std::optional<std::vector<int>> slots;
  if (stamps_s && static_cast<int>(stamps_s->size()) == n) {
    slots = SlotsFromStamps(*stamps_s, fps);
    if (slots) {
      t.source = TimingSource::kTimeStamps;
      t.notes.push_back("capture slots from the file's time stamps, rounded to periods of 1/fps");
    } else {
      t.notes.push_back(
          "the file's time stamps do not increase frame by frame; slots from the motion");
    }
  }
  if (!slots && !options.drops_from_motion) {
    slots.emplace(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) (*slots)[static_cast<std::size_t>(i)] = i;
    t.source = TimingSource::kFrameIndex;
    t.notes.push_back(
        "no time stamps: frame i is capture i (dropped captures are looked for in the motion "
        "only when asked: --drops-from-motion)");
  }
  if (!slots) {
    std::vector<std::optional<Eigen::Vector2d>> q = p;
    q.resize(static_cast<std::size_t>(n));
    slots = SlotsFromMotion(q, t.repeat, down, options);
    t.source = TimingSource::kMotion;
    t.notes.push_back(
        "capture slots from the motion: a dropped capture shows as a step that a free-flight "
        "parabola at whole slots explains only with a slot left out (not seen across an impact "
        "or at the clip's ends)");
  }
  t.slot = *slots;
  std::vector<bool> held(static_cast<std::size_t>(t.slot.empty() ? 0 : t.slot.back() + 1), false);
  for (int i = 0; i < n; ++i) {
    const int s = t.slot[static_cast<std::size_t>(i)];
    t.t_s[static_cast<std::size_t>(i)] = s / fps;
    if (s >= 0 && s < static_cast<int>(held.size())) held[static_cast<std::size_t>(s)] = true;
  }
  for (std::size_t s = 0; s < held.size(); ++s)
    if (!held[s]) t.dropped_captures.push_back(static_cast<int>(s));
  return t;
}

}  // namespace hoof::tracking
