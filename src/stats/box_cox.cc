#include "stats/box_cox.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <boost/math/tools/minima.hpp>

#include "stats/accurate_sum.h"
#include "stats/distributions.h"
#include "stats/moments.h"

namespace hoof::stats {
namespace {

/// y + shift as long double; throws std::invalid_argument naming the group when it is not > 0
/// (Box-Cox needs positive data).
long double Shifted(double y, double shift, const std::string& group) {
  const long double x = static_cast<long double>(y) + shift;
  if (!(x > 0.0L)) {
    std::ostringstream os;
    os.precision(17);
    os << "Box-Cox needs positive values: group \"" << group << "\" value " << y << " plus shift "
       << shift << " is not > 0";
    throw std::invalid_argument(os.str());
  }
  return x;
}

constexpr int kGridCells = 120;
constexpr std::array<double, 7> kSimpleLambdas = {-2.0, -1.0, -0.5, 0.0, 0.5, 1.0, 2.0};

/// The data in the form the likelihood needs: u = ln(y / c) per value, grouped.
struct LogData {
  double log_c = 0.0;  ///< ln c, c = first shifted value.
  std::vector<std::vector<long double>> u;
  long double sum_u = 0.0L;
  std::size_t n = 0;
};

LogData MakeLogData(const GroupedData& data, double shift) {
  LogData d;
  const long double c = static_cast<long double>(data.values.at(0).at(0)) + shift;
  AccurateSum sum_u;
  for (std::size_t g = 0; g < data.groups(); ++g) {
    d.u.emplace_back();
    for (double y : data.values[g]) {
      const long double x = Shifted(y, shift, data.labels[g]);
      const long double u = std::log1p((x - c) / c);
      d.u.back().push_back(u);
      sum_u.Add(u);
      ++d.n;
    }
  }
  d.log_c = static_cast<double>(std::log(c));
  d.sum_u = sum_u.Value();
  return d;
}

/// l(lambda) with c factored out (see the header).
long double LogLikelihood(const LogData& d, long double lambda) {
  GroupedData v;
  v.values.resize(d.u.size());
  v.labels.resize(d.u.size());
  for (std::size_t g = 0; g < d.u.size(); ++g) {
    for (long double u : d.u[g]) {
      const long double t = lambda == 0.0L ? u : std::expm1(lambda * u) / lambda;
      v.values[g].push_back(static_cast<double>(t));
    }
  }
  const Moments m = ComputeMoments(v);
  AccurateSum ss;
  for (const GroupMoments& g : m.groups) ss.Add(g.sum_sq);
  const long double ss_v = ss.Value();
  if (!(ss_v > 0.0L) || !std::isfinite(ss_v)) return -std::numeric_limits<long double>::infinity();
  const long double n = static_cast<long double>(d.n);
  const long double log_c = d.log_c;
  // ln SS_within(lambda) = 2 lambda ln c + ln SS_v and sum ln y = n ln c + sum u; the two
  // lambda n ln c terms cancel exactly, so they are left out:
  // l = -(n/2) ln(SS_v / n) - n ln c + (lambda - 1) sum u.
  return -0.5L * n * std::log(ss_v / n) - n * log_c + (lambda - 1.0L) * d.sum_u;
}

/// Solves l(x) = target on [a, b] by bisection, given l(a) >= target > l(b) or the reverse.
long double Crossing(const LogData& d, long double a, long double b, long double target) {
  const bool a_above = LogLikelihood(d, a) >= target;
  for (int i = 0; i < 200 && a != b; ++i) {
    const long double mid = 0.5L * (a + b);
    if (mid == a || mid == b) break;
    if ((LogLikelihood(d, mid) >= target) == a_above) {
      a = mid;
    } else {
      b = mid;
    }
  }
  return 0.5L * (a + b);
}

std::string FormatNumber(double x) {
  std::ostringstream os;
  os << x;
  return os.str();
}

}  // namespace

void BoxCoxOptions::Validate() const {
  if (!std::isfinite(lambda_min) || !std::isfinite(lambda_max) || !(lambda_min < lambda_max)) {
    std::ostringstream os;
    os << "Box-Cox search interval [lambda_min, lambda_max] = [" << lambda_min << ", " << lambda_max
       << "] must be finite with lambda_min < lambda_max";
    throw std::invalid_argument(os.str());
  }
  if (!(confidence > 0.0 && confidence < 1.0)) {
    std::ostringstream os;
    os << "Box-Cox confidence = " << confidence << " must be in (0, 1)";
    throw std::invalid_argument(os.str());
  }
}

double BoxCoxShift(const GroupedData& data) {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  for (const auto& g : data.values) {
    for (double y : g) {
      lo = std::min(lo, y);
      hi = std::max(hi, y);
    }
  }
  if (lo > 0.0) return 0.0;
  return 0.01 * (hi - lo) - lo;
}

double BoxCoxLogLikelihood(const GroupedData& data, double lambda, double shift) {
  if (!std::isfinite(lambda)) throw std::invalid_argument("Box-Cox lambda must be finite");
  return static_cast<double>(LogLikelihood(MakeLogData(data, shift), lambda));
}

namespace {

/// The lambda of largest profile likelihood in [lo, hi] and that likelihood: a grid, then
/// Brent about its best cell.
std::pair<long double, long double> MaximumLikelihoodLambda(const LogData& d, long double lo,
                                                            long double hi) {
  const long double step = (hi - lo) / kGridCells;
  int best = 0;
  long double best_l = -std::numeric_limits<long double>::infinity();
  for (int i = 0; i <= kGridCells; ++i) {
    const long double l = LogLikelihood(d, i == kGridCells ? hi : lo + step * i);
    if (l > best_l) {
      best_l = l;
      best = i;
    }
  }
  const long double a = best == 0 ? lo : lo + step * (best - 1);
  const long double b = best == kGridCells ? hi : lo + step * (best + 1);
  const auto negative = [&d](long double x) { return -LogLikelihood(d, x); };
  std::uintmax_t iterations = 500;
  const auto [x_min, f_min] = boost::math::tools::brent_find_minima(
      negative, a, b, std::numeric_limits<long double>::digits / 2, iterations);
  long double lambda_ml = x_min, l_ml = -f_min;
  if (best_l > l_ml) {  // Brent never does worse than the grid, but keep the better.
    lambda_ml = best == kGridCells ? hi : lo + step * best;
    l_ml = best_l;
  }
  return {lambda_ml, l_ml};
}

/// Replaces lambda_ML by the simple lambda (kSimpleLambdas) nearest it inside its interval,
/// where there is one, and says so in the rule.
void PreferSimple(const LogData& d, const BoxCoxOptions& options, BoxCoxResult& r) {
  double chosen = std::numeric_limits<double>::quiet_NaN();
  long double chosen_l = 0.0L;
  for (double s : kSimpleLambdas) {
    if (s < r.ci_low || s > r.ci_high) continue;
    const long double l = LogLikelihood(d, s);
    const double dist = std::fabs(s - r.lambda_ml);
    const double best_dist = std::fabs(chosen - r.lambda_ml);
    if (std::isnan(chosen) || dist < best_dist || (dist == best_dist && l > chosen_l)) {
      chosen = s;
      chosen_l = l;
    }
  }
  if (!std::isnan(chosen)) {
    r.lambda = chosen;
    r.rule += "; simple lambda " + FormatNumber(chosen) + " nearest lambda_ML inside the " +
              FormatNumber(100.0 * options.confidence) + "% interval [" + FormatNumber(r.ci_low) +
              ", " + FormatNumber(r.ci_high) + "]";
  } else {
    r.rule += "; no simple lambda inside the " + FormatNumber(100.0 * options.confidence) +
              "% interval [" + FormatNumber(r.ci_low) + ", " + FormatNumber(r.ci_high) +
              "], lambda_ML used";
  }
}

}  // namespace

BoxCoxResult EstimateBoxCox(const GroupedData& data, const BoxCoxOptions& options) {
  options.Validate();
  ValidateOneWay(data);
  BoxCoxResult r;
  r.shift = BoxCoxShift(data);
  const LogData d = MakeLogData(data, r.shift);
  if (!std::isfinite(LogLikelihood(d, 1.0L))) {
    throw std::invalid_argument(
        "every group is constant (zero within-group variance); Box-Cox lambda is undefined");
  }
  const long double lo = options.lambda_min, hi = options.lambda_max;
  const auto [lambda_ml, l_ml] = MaximumLikelihoodLambda(d, lo, hi);
  r.lambda_ml = static_cast<double>(lambda_ml);
  r.log_likelihood_ml = static_cast<double>(l_ml);
  const long double target =
      l_ml - 0.5L * static_cast<long double>(ChiSquaredQuantile(options.confidence, 1.0));
  r.ci_low_at_limit = LogLikelihood(d, lo) >= target;
  r.ci_high_at_limit = LogLikelihood(d, hi) >= target;
  r.ci_low = static_cast<double>(r.ci_low_at_limit ? lo : Crossing(d, lo, lambda_ml, target));
  r.ci_high = static_cast<double>(r.ci_high_at_limit ? hi : Crossing(d, lambda_ml, hi, target));

  r.lambda = r.lambda_ml;
  r.rule = "lambda_ML = " + FormatNumber(r.lambda_ml) + " (profile likelihood, one-way model)";
  if (options.prefer_simple) PreferSimple(d, options, r);
  if (r.shift != 0.0) r.rule += "; data shifted by " + FormatNumber(r.shift) + " first";
  return r;
}

GroupedData ApplyBoxCox(const GroupedData& data, double lambda, double shift) {
  if (!std::isfinite(lambda)) throw std::invalid_argument("Box-Cox lambda must be finite");
  GroupedData out;
  out.labels = data.labels;
  out.values.resize(data.groups());
  for (std::size_t g = 0; g < data.groups(); ++g) {
    for (double y : data.values[g]) {
      const long double x = Shifted(y, shift, data.labels[g]);
      const long double log_x = std::log(x);
      const long double t = lambda == 0.0 ? log_x : std::expm1(lambda * log_x) / lambda;
      out.values[g].push_back(static_cast<double>(t));
    }
  }
  return out;
}

std::string DescribeBoxCox(double lambda, double shift) {
  const std::string y = shift == 0.0 ? "y" : "(y + " + FormatNumber(shift) + ")";
  if (lambda == 0.0) return "ln" + (shift == 0.0 ? "(y)" : y);
  if (lambda == 1.0) return y + " - 1 (no transform)";
  if (lambda == 0.5) return "2 (sqrt" + (shift == 0.0 ? "(y)" : y) + " - 1)";
  if (lambda == -1.0) return "1 - 1/" + y;
  const std::string l = FormatNumber(lambda);
  return "(" + y + "^" + l + " - 1)/" + l;
}

}  // namespace hoof::stats
