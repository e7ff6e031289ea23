#pragma once
/// @file
/// The Box-Cox power transform, with lambda chosen by maximum likelihood under the one-way
/// model, used when Bartlett's test rejects equal variances (see one_way_analysis.h).
///
/// Transform (Box & Cox 1964), for y > 0:
///   y(lambda) = (y^lambda - 1) / lambda   (lambda != 0),     y(0) = ln y.
/// Model: y(lambda) follows the one-way model of one_way_anova.h with one variance for all
/// groups. Maximizing over the group means and the variance leaves the profile
/// log-likelihood (additive constants dropped)
///   l(lambda) = -(N/2) ln( SS_within(lambda) / N ) + (lambda - 1) sum ln y,
/// where SS_within(lambda) is the pooled within-group sum of squares of y(lambda) and the
/// last term is the log-Jacobian of the transform.
///
/// Rule (stated here, reported in BoxCoxResult::rule):
///  1. If min y <= 0, every value is shifted by s = 0.01 (max y - min y) - min y, so that the
///     smallest becomes 1 % of the range above zero. (Positive data: s = 0.) The shift is
///     arbitrary and changes the answer; it is reported so that the reader can judge.
///  2. lambda_ML maximizes l over [lambda_min, lambda_max] (grid of 121 points, then Brent's
///     method on the bracketing cell; at a search limit the limit is reported).
///  3. The profile-likelihood confidence interval is {lambda : l(lambda) >= l(lambda_ML) -
///     chi2_{1, confidence} / 2}, cut at the search limits.
///  4. With prefer_simple (the default), the lambda used is the value of
///     {-2, -1, -0.5, 0, 0.5, 1, 2} (1/y^2, 1/y, 1/sqrt y, ln y, sqrt y, none, y^2) that lies
///     in the interval and is nearest lambda_ML (ties: higher likelihood); with none in the
///     interval, or prefer_simple off, lambda_ML itself.
///
/// Numerics: with a reference c > 0 (the first shifted value) and u = ln(y / c) formed as
/// log1p((y - c) / c) in long double, y(lambda) = c^lambda expm1(lambda u) / lambda + const,
/// so SS_within(lambda) = c^(2 lambda) SS_within(expm1(lambda u) / lambda) without the
/// cancellation that y^lambda suffers when the data share many leading digits.

#include <string>

#include "stats/grouping.h"

namespace hoof::stats {

/// Settings of the lambda search.
struct BoxCoxOptions {
  double lambda_min = -3.0;   ///< Lower end of the search interval.
  double lambda_max = 3.0;    ///< Upper end; lambda_min < lambda_max, both finite.
  double confidence = 0.95;   ///< Level of the profile-likelihood interval, in (0, 1).
  bool prefer_simple = true;  ///< Round to a simple lambda inside the interval (rule 4).
  /// Throws std::invalid_argument naming the field that is out of range.
  void Validate() const;
};

/// The estimate and the choice.
struct BoxCoxResult {
  double shift = 0.0;              ///< s added to every value before transforming (rule 1).
  double lambda_ml = 1.0;          ///< Maximum-likelihood lambda.
  double log_likelihood_ml = 0.0;  ///< l(lambda_ML), constants dropped.
  double ci_low = 0.0;             ///< Profile-likelihood interval (rule 3).
  double ci_high = 0.0;
  bool ci_low_at_limit = false;   ///< The interval was cut at lambda_min.
  bool ci_high_at_limit = false;  ///< The interval was cut at lambda_max.
  double lambda = 1.0;            ///< The lambda to use (rule 4).
  std::string rule;               ///< How `lambda` was chosen, in words.
};

/// Estimates lambda for `data` (rules 1-4). Throws std::invalid_argument for what
/// ValidateOneWay rejects, when every group is constant, or for invalid options.
BoxCoxResult EstimateBoxCox(const GroupedData& data, const BoxCoxOptions& options = {});

/// The shift of rule 1 for `data`: 0 when all values are > 0.
double BoxCoxShift(const GroupedData& data);

/// l(lambda) of the file comment for the values of `data` plus `shift` (all must then be
/// > 0; throws std::invalid_argument otherwise). Constants dropped, as in BoxCoxResult.
double BoxCoxLogLikelihood(const GroupedData& data, double lambda, double shift);

/// (y + shift)(lambda) for every value, same groups and labels. Throws std::invalid_argument
/// when a shifted value is not > 0 (naming group and value).
GroupedData ApplyBoxCox(const GroupedData& data, double lambda, double shift);

/// The transform in words for reports: "ln(y)", "sqrt(y)", "1/y", "(y^0.37 - 1)/0.37", with
/// "y + s" in place of y when shift != 0.
std::string DescribeBoxCox(double lambda, double shift);

}  // namespace hoof::stats
