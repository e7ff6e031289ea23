#pragma once
/// @file
/// The one number-formatting policy of hoofimpact's text, tables, figures and report
/// (docs/cli.md, "Numbers"). Every human-readable number goes through these functions; the
/// machine-readable outputs (CSV, HDF5, JSON) keep full precision.
///
///  - Undefined (NaN, infinite) prints "n/a", everywhere.
///  - A quantity prints with the significant digits its Kind gives (Significant), in fixed
///    notation between 1e-4 and 1e6 and in scientific notation outside, never with trailing
///    zeros cut from a fixed count of digits ("0.7000" stays "0.7000" at 4 digits).
///  - A p-value prints as "< 0.001" below 0.001, else with 3 decimals ("0.017"); PValue gives
///    the phrase with its "p" ("p = 0.017", "p < 0.001"). Where a p is compared with a level
///    below 0.001 (discovery), PAgainstSmallLevel keeps its digits ("1.60e-08").
///  - A value with its uncertainty prints the uncertainty to 2 significant digits and the value
///    to the same last decimal ("0.712 ± 0.013").
///  - Durations print in s with 1 decimal ("4.9 s"), below 0.1 s in ms.
///
/// Built on {fmt} (Debian libfmt-dev).
#include <string>

namespace hoof::format {

/// How many significant digits a kind of quantity carries.
enum class Kind {
  kCoefficient,  ///< e, mu, zeta, mu_eff, eta^2: 4 digits
  kMeasured,     ///< velocities, lengths, angles, times: 4 digits
  kStatistic,    ///< F, t, K^2, z: 3 digits
  kSum,          ///< sums of squares, mean squares: 4 digits
  kError,        ///< a standard error or s.d. on its own: 2 digits
};

/// Significant digits of `kind`.
int DigitsOf(Kind kind);

/// "n/a" for a value that is not finite.
inline constexpr const char* kUndefined = "n/a";

/// `value` to `digits` significant digits (fixed between 1e-4 and 1e6, else scientific);
/// "n/a" when not finite. `digits` in 1..17.
std::string Significant(double value, int digits);

/// `value` with the digits of `kind`.
std::string Number(double value, Kind kind = Kind::kMeasured);

/// A p-value: "< 0.001", "0.017", "1.000"; "n/a" when not finite.
std::string P(double p);

/// "p < 0.001" or "p = 0.017" (or "p n/a").
std::string PValue(double p);

/// A p-value that is compared with a level below 0.001 (discovery's naming levels, which
/// multiplicity puts at 1e-4 and below, docs/discovery.md): "< 0.001" would hide whether it
/// passes, so below 0.001 it keeps 3 significant digits in scientific notation ("1.60e-08"),
/// "< 1e-300" below 1e-300; from 0.001 on, 2 significant digits ("0.2", "1"); "n/a" when not
/// finite. The one exception to P()'s style, used by the discovery text.
std::string PAgainstSmallLevel(double p);

/// "0.712 ± 0.013": the error to 2 significant digits, the value to the same decimal. Where
/// the error is not finite or not positive, the value alone with the digits of `kind`.
/// `plus_minus` is the separator (" ± " by default; the report passes " &plusmn; ").
std::string WithError(double value, double error, Kind kind = Kind::kMeasured,
                      const std::string& plus_minus = " \xC2\xB1 ");

/// "0.060 to 0.091" at the digits of `kind`, or "n/a" when either end is not finite.
std::string Interval(double low, double high, Kind kind = Kind::kMeasured);

/// A duration in seconds: "4.9 s", "35 ms" below 0.1 s, "n/a" when not finite.
std::string Seconds(double seconds);

}  // namespace hoof::format
