#include "format/number_format.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace hoof::format {

int DigitsOf(Kind kind) {
  switch (kind) {
    case Kind::kCoefficient:
    case Kind::kMeasured:
    case Kind::kSum:
      return 4;
    case Kind::kStatistic:
      return 3;
    case Kind::kError:
      return 2;
  }
  return 4;
}

namespace {

/// Decimals that give `digits` significant digits for `value` in fixed notation.
int DecimalsFor(double value, int digits) {
  if (value == 0.0) return digits - 1;
  const int exponent = static_cast<int>(std::floor(std::log10(std::abs(value))));
  return std::max(0, digits - 1 - exponent);
}

}  // namespace

std::string Significant(double value, int digits) {
  if (digits < 1 || digits > 17)
    throw std::invalid_argument("format::Significant: digits = " + std::to_string(digits) +
                                ": must be in 1..17");
  if (!std::isfinite(value)) return kUndefined;
  if (value == 0.0) return fmt::format("{:.{}f}", 0.0, digits - 1);
  const double a = std::abs(value);
  if (a < 1e-4 || a >= 1e6) return fmt::format("{:.{}e}", value, digits - 1);
  // Round to the digits first: 9.9996 at 4 digits is "10.00", not "9.9996" cut to "10.000".
  const std::string rounded = fmt::format("{:.{}e}", value, digits - 1);
  const double r = std::stod(rounded);
  return fmt::format("{:.{}f}", r, DecimalsFor(r, digits));
}

std::string Number(double value, Kind kind) { return Significant(value, DigitsOf(kind)); }

std::string P(double p) {
  if (!std::isfinite(p)) return kUndefined;
  if (p < 0.001) return "< 0.001";
  return fmt::format("{:.3f}", std::min(p, 1.0));
}

std::string PValue(double p) {
  if (!std::isfinite(p)) return std::string("p ") + kUndefined;
  const std::string s = P(p);
  return s.front() == '<' ? "p " + s : "p = " + s;
}

std::string PAgainstSmallLevel(double p) {
  if (!std::isfinite(p)) return kUndefined;
  if (p < 1e-300) return "< 1e-300";
  if (p < 1e-3) return fmt::format("{:.2e}", p);
  return fmt::format("{:.2g}", p);
}

std::string WithError(double value, double error, Kind kind, const std::string& plus_minus) {
  if (!std::isfinite(value)) return kUndefined;
  if (!std::isfinite(error) || error <= 0.0) return Number(value, kind);
  const std::string e = Significant(error, 2);
  if (error < 1e-4 || error >= 1e6 || std::abs(value) >= 1e6)
    return Number(value, kind) + plus_minus + e;
  const int decimals = DecimalsFor(std::stod(e), 2);
  return fmt::format("{:.{}f}", value, decimals) + plus_minus + e;
}

std::string Interval(double low, double high, Kind kind) {
  if (!std::isfinite(low) || !std::isfinite(high)) return kUndefined;
  return Number(low, kind) + " to " + Number(high, kind);
}

std::string Seconds(double seconds) {
  if (!std::isfinite(seconds)) return kUndefined;
  if (std::abs(seconds) < 0.1) return Significant(seconds * 1e3, 2) + " ms";
  return fmt::format("{:.1f} s", seconds);
}

}  // namespace hoof::format
