#pragma once
/// @file
/// Two-way analysis of variance, factor A x factor B with interaction, for balanced or
/// unbalanced data in which every A x B cell holds at least one observation.
///
/// Model (cell means): y_ijr = mu_ij + e_ijr, e ~ N(0, sigma^2), a levels of A, b of B,
/// n_ij >= 1 observations in cell (i, j), N = sum n_ij, cell means m_ij.
///   SS_error = sum_ijr (y_ijr - m_ij)^2,  df_error = N - a b (must be >= 1).
///
/// Sums of squares for the effects, by type (TwoWayOptions::type):
///  * Type III (default; SAS PROC GLM Type III, R car::Anova(type = 3) with sum-to-zero
///    contrasts). Each effect is tested adjusted for all others, as the hypothesis on the
///    unweighted cell means
///      A:   (1/b) sum_j mu_ij equal for all i        (a - 1 df)
///      B:   (1/a) sum_i mu_ij equal for all j        (b - 1 df)
///      AxB: mu_ij - mu_ib - mu_aj + mu_ab = 0        ((a - 1)(b - 1) df)
///    each with SS = (L m)' (L D^-1 L')^-1 (L m), D = diag(n_ij), the usual sum of squares
///    of a linear hypothesis L mu = 0. Type III does not depend on the order of the factors;
///    with unbalanced data the effect SS need not add up to SS_total.
///  * Type I (sequential, R's anova(lm(y ~ A * B))): A, then B given A, then AxB given both:
///      SS_A  = sum_i n_i. (m_i.^w - m)^2 with the weighted marginal means m_i.^w;
///      SS_AB = the Type III AxB sum of squares (the last term is adjusted for everything);
///      SS_B|A = sum_ij n_ij (m_ij - m_i.^w)^2 - SS_AB.
///    The four SS add up to SS_total; the result depends on which factor comes first.
/// For balanced data (all n_ij equal) both types give the classical table:
///   SS_A = b n sum_i (m_i. - m)^2, SS_B = a n sum_j (m_.j - m)^2,
///   SS_AB = n sum_ij (m_ij - m_i. - m_.j + m)^2.
/// F = MS_effect / MS_error, p = P(F(df_effect, df_error) >= F).
///
/// Cell means come from moments.h (shifted, compensated long double), and the quadratic
/// forms are solved in long double, so data with many constant leading digits are handled
/// as in the one-way case.

#include <cstddef>
#include <string>
#include <vector>

namespace hoof::stats {

/// Which sums of squares (see the file comment).
enum class SumOfSquaresType { kTypeI, kTypeIII };

/// "Type I" or "Type III".
std::string ToString(SumOfSquaresType type);

/// Settings of the two-way table.
struct TwoWayOptions {
  SumOfSquaresType type = SumOfSquaresType::kTypeIII;
  std::string name_a = "A";  ///< Factor names, used for the row labels and in messages.
  std::string name_b = "B";
};

/// One row of the table. For the error row, f and p are not defined and are NaN.
struct TwoWayRow {
  std::string source;  ///< name_a, name_b, name_a + ":" + name_b, or "error".
  std::size_t df = 0;
  double ss = 0.0;  ///< Units of the response squared.
  double ms = 0.0;
  double f = 0.0;
  double p = 1.0;
};

/// The two-way ANOVA table.
struct TwoWayAnovaResult {
  SumOfSquaresType type = SumOfSquaresType::kTypeIII;
  std::vector<std::string> levels_a;  ///< In order of first appearance.
  std::vector<std::string> levels_b;
  std::vector<std::vector<std::size_t>> cell_counts;  ///< [i][j] = n_ij.
  std::vector<std::vector<double>> cell_means;        ///< [i][j] = m_ij.
  bool balanced = false;                              ///< All n_ij equal.
  TwoWayRow a, b, ab, error;
  std::size_t df_total = 0;  ///< N - 1.
  double ss_total = 0.0;     ///< sum (y - m)^2.
};

/// Two-way ANOVA of `response` by `factor_a` and `factor_b` (one label of each per
/// observation). Throws std::invalid_argument naming the problem when sizes differ, a value
/// is not finite, a label is empty, a factor has fewer than 2 levels, a cell is empty (it
/// names the cell), N - a b < 1, or every cell is constant (SS_error = 0).
TwoWayAnovaResult TwoWayAnova(const std::vector<double>& response,
                              const std::vector<std::string>& factor_a,
                              const std::vector<std::string>& factor_b,
                              const TwoWayOptions& options = {});

}  // namespace hoof::stats
