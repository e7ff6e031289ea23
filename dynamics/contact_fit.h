#pragma once
/// @file
/// Fitting the two-phase contact law to normal impacts, honestly (docs/science.md, "What
/// velocities can and cannot tell").
///
/// The paper varied k in [1e5, 1e9] N/m and b in [0, 2000] N s/m to minimise the mean
/// percentage error (MPE) of the post-impact velocity. But velocities determine only the
/// damping ratio zeta = b / (2 sqrt(k m)): k sets the contact duration (10-32 us, far below
/// the 125 us frame period), which frames cannot see. So the objective has a flat valley
/// along constant zeta. This module fits zeta with a 95 % interval (Ceres), traces the valley
/// over k, maps the objective over (k, b), and says in words that k is not identified.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "dynamics/parameters.h"

namespace hoof::dynamics {

/// One measured normal impact: speeds of C along the surface normal, as magnitudes.
struct NormalImpact {
  double v_before_m_s = 0.0;  ///< Approach speed at first touch (m/s); > 0.
  double v_after_m_s = 0.0;   ///< Rebound speed after separation (m/s); > 0.
};

/// Settings of the contact-law fit. Bounds are the paper's.
struct ContactFitOptions {
  double k_min_N_m = 1e5;       ///< Lower bound of k (N/m); > 0.
  double k_max_N_m = 1e9;       ///< Upper bound of k (N/m); > k_min_N_m.
  double b_min_N_s_m = 0.0;     ///< Lower bound of b (N s/m); >= 0.
  double b_max_N_s_m = 2000.0;  ///< Upper bound of b (N s/m); > b_min_N_s_m.
  /// k at which zeta is fitted (N/m). Any point of the valley gives the same zeta to well
  /// within its interval; the valley trace shows by how much.
  double k_reference_N_m = 1e8;
  double confidence = 0.95;  ///< Level of the zeta interval; in (0, 1).
  int valley_points = 9;     ///< k values (log-spaced over the bounds) on the valley; >= 2.
  int map_points_k = 41;     ///< Grid of the objective map, along log k; >= 2 (0: no map).
  int map_points_b = 41;     ///< Grid of the objective map, along b; >= 2 (0: no map).
  double gravity_m_s2 = kStandardGravity_m_s2;  ///< g in the simulations (m/s^2).

  /// Throws std::invalid_argument naming the field.
  void Validate() const;
};

/// A point on the valley: the best b for a given k.
struct ValleyPoint {
  double k_N_m = 0.0;
  double b_N_s_m = 0.0;             ///< Minimises the squared percentage errors at this k.
  double zeta = 0.0;                ///< b / (2 sqrt(k m)).
  double mpe_percent = 0.0;         ///< Mean |percentage error| of the post-impact speed here.
  double contact_duration_s = 0.0;  ///< Of a normal impact at the mean approach speed.
  bool within_bounds = false;       ///< b within [b_min, b_max].
};

/// What the fit found, and what it could not.
struct ContactFitSummary {
  bool success = false;
  std::string message;  ///< Why it failed, or empty.
  int n = 0;            ///< Number of impacts.

  double zeta = 0.0;          ///< Least-squares estimate of the damping ratio.
  double zeta_se = 0.0;       ///< Standard error from the residuals (NaN when n < 2).
  double zeta_ci_low = 0.0;   ///< Lower end of the interval (Student t, n - 1 dof).
  double zeta_ci_high = 0.0;  ///< Upper end of the interval.
  double e_normal = 0.0;      ///< Closed-form e(zeta) without gravity.
  double mpe_percent = 0.0;   ///< Mean |percentage error| at the estimate (paper's objective).
  double rms_percent = 0.0;   ///< Root-mean-square percentage error at the estimate.

  std::vector<ValleyPoint> valley;         ///< Best b along k, log-spaced over the k bounds.
  double valley_zeta_spread = 0.0;         ///< max - min of zeta along the in-bounds valley.
  double valley_mpe_spread_percent = 0.0;  ///< max - min of the MPE along the in-bounds valley.
  double valley_k_min_N_m = 0.0;  ///< Range of k where the valley lies within the b bounds.
  double valley_k_max_N_m = 0.0;

  /// MPE (%) over a grid: map_mpe_percent(i, j) at k = map_k_N_m[i], b = map_b_N_s_m[j].
  std::vector<double> map_k_N_m;
  std::vector<double> map_b_N_s_m;
  Eigen::MatrixXd map_mpe_percent;

  /// Plain-language statement of what was identified and what was not.
  std::string Explanation() const;
};

/// Fits zeta to normal impacts of `specimen` (paper section 2.2 and docs/science.md, "What
/// velocities can and cannot tell").
/// Throws std::invalid_argument for invalid options or impacts (naming the field or index);
/// solver trouble is reported in the summary.
ContactFitSummary FitNormalContact(const std::vector<NormalImpact>& impacts,
                                   const SpecimenParameters& specimen,
                                   const ContactFitOptions& options = {});

}  // namespace hoof::dynamics
