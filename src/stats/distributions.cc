#include "stats/distributions.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/fisher_f.hpp>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>

namespace hoof::stats {
namespace {

void RequireDf(double df, const char* function, const char* name) {
  if (!(df > 0.0) || !std::isfinite(df)) {
    std::ostringstream os;
    os << function << ": degrees of freedom " << name << " = " << df << " must be finite and > 0";
    throw std::invalid_argument(os.str());
  }
}

void RequireProbability(double q, const char* function) {
  if (!(q > 0.0 && q < 1.0)) {
    std::ostringstream os;
    os << function << ": probability " << q << " must be in (0, 1)";
    throw std::invalid_argument(os.str());
  }
}

void RequireNonNegative(double x, const char* function, const char* name) {
  if (std::isnan(x) || x < 0.0) {
    std::ostringstream os;
    os << function << ": " << name << " = " << x << " must be >= 0";
    throw std::invalid_argument(os.str());
  }
}

}  // namespace

double FUpperTail(double f, double df1, double df2) {
  RequireDf(df1, "FUpperTail", "df1");
  RequireDf(df2, "FUpperTail", "df2");
  RequireNonNegative(f, "FUpperTail", "F");
  if (std::isinf(f)) return 0.0;
  if (f == 0.0) return 1.0;
  return boost::math::cdf(boost::math::complement(boost::math::fisher_f(df1, df2), f));
}

double TTwoSided(double t, double df) {
  RequireDf(df, "TTwoSided", "df");
  if (std::isnan(t)) throw std::invalid_argument("TTwoSided: t is NaN");
  if (std::isinf(t)) return 0.0;
  const double upper =
      boost::math::cdf(boost::math::complement(boost::math::students_t(df), std::fabs(t)));
  return 2.0 * upper;
}

double TQuantile(double q, double df) {
  RequireDf(df, "TQuantile", "df");
  RequireProbability(q, "TQuantile");
  return boost::math::quantile(boost::math::students_t(df), q);
}

double ChiSquaredUpperTail(double x, double df) {
  RequireDf(df, "ChiSquaredUpperTail", "df");
  RequireNonNegative(x, "ChiSquaredUpperTail", "x");
  if (std::isinf(x)) return 0.0;
  if (x == 0.0) return 1.0;
  return boost::math::cdf(boost::math::complement(boost::math::chi_squared(df), x));
}

double ChiSquaredQuantile(double q, double df) {
  RequireDf(df, "ChiSquaredQuantile", "df");
  RequireProbability(q, "ChiSquaredQuantile");
  return boost::math::quantile(boost::math::chi_squared(df), q);
}

std::pair<double, double> WilsonInterval(int k, int n, double confidence) {
  if (n <= 0 || k < 0 || k > n) {
    std::ostringstream os;
    os << "WilsonInterval: " << k << " successes in " << n << " trials (need 0 <= k <= n, n > 0)";
    throw std::invalid_argument(os.str());
  }
  RequireProbability(confidence, "WilsonInterval");
  const double z =
      boost::math::quantile(boost::math::complement(boost::math::normal(), (1 - confidence) / 2));
  const double nn = n, p = k / nn, z2 = z * z;
  const double centre = (p + z2 / (2 * nn)) / (1 + z2 / nn);
  const double half = z * std::sqrt(p * (1 - p) / nn + z2 / (4 * nn * nn)) / (1 + z2 / nn);
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

}  // namespace hoof::stats
