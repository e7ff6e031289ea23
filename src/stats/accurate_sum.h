#pragma once
/// @file
/// Compensated summation in extended precision: the accumulator under every sum of squares in
/// hoof::stats. The NIST StRD ANOVA sets (SmLs07-09: 13 constant leading digits, up to 18009
/// values) are built to break naive one-pass formulas; centring plus this accumulator keeps
/// every sum to within a few units of the last place of `long double`.

#include <cmath>

namespace hoof::stats {

/// Neumaier's variant of Kahan-Babuska summation, accumulated in `long double` (64-bit
/// significand on x86-64, 113-bit on targets where long double is binary128).
/// The error bound is about 2 u |sum| + O(n u^2) sum|x_i| with u = 2^-64 on x86-64, instead of
/// the (n - 1) u sum|x_i| of the plain loop (Higham, Accuracy and Stability of Numerical
/// Algorithms, 2nd ed., section 4.3). Do not compile with -ffast-math: it would remove the
/// compensation.
class AccurateSum {
 public:
  /// Adds one term.
  void Add(long double x) {
    const long double t = sum_ + x;
    if (std::fabs(sum_) >= std::fabs(x)) {
      compensation_ += (sum_ - t) + x;
    } else {
      compensation_ += (x - t) + sum_;
    }
    sum_ = t;
  }
  /// The compensated sum so far.
  long double Value() const { return sum_ + compensation_; }

 private:
  long double sum_ = 0.0L;
  long double compensation_ = 0.0L;
};

}  // namespace hoof::stats
