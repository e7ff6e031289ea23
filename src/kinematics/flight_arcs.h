#pragma once
/// @file
/// The joint fit of a clip's free-flight arcs with one shared acceleration (docs/tracking.md,
/// "4. Kinematics", "Joint arcs"): the method for clips whose flights hold a few frames each
/// (25 to 60 fps), whose camera may be rolled, and whose scale may come from gravity itself.
///
/// Between contacts the centre of mass C follows p(t) = p_k + v_k (t - t_k) + a (t - t_k)^2 / 2:
/// every arc k has its own p_k and v_k (2-D), and all arcs share one acceleration a (2-D, its
/// magnitude and direction both fitted: "up" is -a / |a|). Given which frame belongs to which
/// arc this is one linear least-squares problem, weighted by the positions' covariances where
/// every sample has one, with the noise level fitted from the residuals. Which frame belongs
/// where is found from the motion: a contact is a velocity change against gravity far beyond
/// the noise where the motion along "up" reverses; frames off their arc are left out one at a
/// time (the largest studentized residual first), each with its reason.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/frames.h"
#include "kinematics/pose_sample.h"

namespace hoof::kinematics {

/// Settings of the joint arc fit and of the impacts measured from it.
struct ArcOptions {
  /// An arc with fewer samples is not fitted: the impacts beside it are found but not
  /// measured; >= 3 (two samples fix p_k and v_k with nothing left to check them).
  int min_arc_frames = 3;
  /// A contact: the velocity change across a frame interval, against the median acceleration,
  /// exceeds this many robust standard deviations of that change; > 0.
  double impulse_sigmas = 8.0;
  /// ... and the motion along "up" reverses there: down before and up after, each by more than
  /// this many standard deviations of a one-interval velocity; > 0.
  double reversal_sigmas = 3.0;
  /// A sample whose squared studentized residual (2 degrees of freedom, in units of the robust
  /// noise level) exceeds this is left out; > 0. 18.42 is chi^2_2's quantile at 1 - 1e-4.
  double outlier_chi2 = 18.42;
  /// The same for the samples beside a contact (the last of an arc before it, the first
  /// after): a frame whose exposure spans the contact, or that shows the body touching, is far
  /// more likely there; > 0. 9.21 is chi^2_2's quantile at 0.99.
  double contact_chi2 = 9.21;
  /// Where an arc stops and no arc follows, a run of 3 to this many samples off it followed by
  /// two on it are outliers, and the arc goes on (a ball cut by the frame's edge near its apex,
  /// or half hidden, for a few frames); >= 2 (2: no such runs, only the one or two that are
  /// always allowed).
  int max_outlier_run = 8;
  /// At most this fraction of the samples is left out as outliers or contact frames; in (0, 1).
  double max_excluded_fraction = 0.25;
  /// On a level surface mu_eff is measured only where the body moves along it before the
  /// impact by more than this fraction of its normal speed (and 3 standard errors); >= 0.
  double min_sideways_ratio = 0.05;
  /// Gravity's direction ("up", the camera's roll) is taken from the fitted acceleration when
  /// its s.e. is at most this (deg); else S is built on W's y (the stated gravity), as the arcs
  /// are too short in time for gravity to bend them measurably (high frame rates). MeasureTrial-
  /// Impacts (pipeline/trial_impacts.h) also uses it to choose the method; > 0.
  double max_roll_se_deg = 1.0;
  /// The image's principal point in W (the units of the positions): with the samples'
  /// apparent sizes it gives the depth correction (see `correct_depth`). nullopt: none.
  std::optional<Eigen::Vector2d> principal_point_W;
  /// Apply the depth correction to the reported fit when the apparent size changes
  /// significantly (beyond 3 standard errors in some arc). Off by default: the shift of e it
  /// would make is reported either way (ImpactLimits::e_depth_shift), and a silhouette's size
  /// also changes with blur and contact, not only with depth.
  bool correct_depth = false;
  /// Fit and apply the perspective of a plane seen at a slant (FlightArcs::perspective_*),
  /// where principal_point_W is given and it lowers the residuals' chi^2 by more than
  /// `perspective_chi2`; > 0. 10.83 is chi^2_1's quantile at 1 - 1e-3.
  bool correct_perspective = true;
  double perspective_chi2 = 10.83;

  /// Throws std::invalid_argument naming the field.
  void Validate() const;
};

/// What one frame is to the joint arc fit.
enum class ArcFrameRole {
  kArc,       ///< a sample of arc `arc`
  kNoSample,  ///< no position (PoseSample::valid false): not found by the tracker
  kRepeated,  ///< the image repeats the previous one (PoseSample::repeated): no sample
  kContact,   ///< at an arc's end beside a contact and off the arc: touching, or blurred across it
  kOutlier,   ///< off its arc by more than ArcOptions::outlier_chi2, away from any contact
  kNotInFlight,  ///< before the first arc or after the last one, and not on it (held, rolling)
  kShortArc,     ///< in a flight with fewer than min_arc_frames samples: not fitted
};

/// "arc", "no_sample", "repeated", "contact", "outlier", "not_in_flight", "short_arc".
const char* ArcFrameRoleName(ArcFrameRole role);

/// One frame of the clip as the fit saw it.
struct ArcFrame {
  ArcFrameRole role = ArcFrameRole::kNoSample;
  int arc = -1;  ///< the arc it belongs to (left out or not); -1 when none
  /// Its squared studentized residual over the robust noise level (2 dof), where it was tested;
  /// NaN otherwise.
  double residual_chi2 = core::kNaN;
};

/// One free-flight arc. Positions in the units of the input (m in W), times in s.
struct FlightArc {
  int first_frame = -1, last_frame = -1;  ///< first and last frame of its fitted samples
  int n = 0;                              ///< samples fitted
  bool fitted = false;                    ///< n >= min_arc_frames
  double t_ref_s = 0.0;                   ///< the time p_W and v_W refer to (its samples' mean)
  Eigen::Vector2d p_W{0, 0}, v_W{0, 0};   ///< position and velocity of C at t_ref_s
  /// Angle of x_B and its rate, a straight line in time fitted to the arc's samples, with
  /// standard errors (0 for a body whose angle does not change, as a ball's).
  double theta_W_rad = 0.0, w_rad_s = 0.0, theta_se_rad = 0.0, w_se_rad_s = 0.0;
  double rms_residual = 0.0;  ///< rms distance of its samples from the fitted arc
  /// The relative rate of change of the depth, (dZ/dt) / Z (1/s), from a straight line fitted
  /// to reference size / apparent size over its samples, and its standard error; NaN without
  /// apparent sizes.
  double depth_rate_per_s = core::kNaN, depth_rate_se_per_s = core::kNaN;
};

/// A contact between arc `before` and arc `before + 1`, found from the motion.
struct ArcContact {
  int before = -1;             ///< the arc before it (the one after is before + 1)
  int last_frame_before = -1;  ///< the last frame with a position before the velocity change
  int first_frame_after = -1;  ///< the first frame with a position after it
  double impulse_sigmas = core::kNaN;  ///< the change against gravity, in robust s.d.
};

/// Outcome of the joint fit.
enum class ArcFitStatus {
  kFitted,        ///< the arcs and the shared acceleration are fitted
  kTooFewFrames,  ///< too few samples (or no arc with min_arc_frames) to fit and check a model
};

/// The joint fit. Parameters `x` are, for each fitted arc in order, p_W (2) then v_W (2), and
/// last a_W (2); `cov_x` is their covariance (the noise level fitted from the residuals).
struct FlightArcs {
  ArcFitStatus status = ArcFitStatus::kTooFewFrames;
  std::string message;  ///< why it was not fitted
  std::vector<FlightArc> arcs;
  std::vector<ArcContact> contacts;  ///< in time order
  std::vector<ArcFrame> frames;      ///< one per input pose
  Eigen::Vector2d a_W{0, 0};         ///< the shared acceleration (input units / s^2)
  Eigen::Matrix2d cov_a_W = Eigen::Matrix2d::Zero();
  double a_norm = core::kNaN, a_norm_se = core::kNaN;  ///< |a| and its standard error
  /// Angle of "up" (-a / |a|) from y_W (deg), positive leaning toward +x_W, and its s.e.: the
  /// camera's roll when W's y is the image's up. The surface's angle in W is the stated one
  /// plus this.
  double roll_deg = core::kNaN, roll_se_deg = core::kNaN;
  /// The noise: without covariances, the s.d. of one coordinate of a position (input units);
  /// with them (`weighted`), the factor they are multiplied by to fit the residuals.
  double sigma = core::kNaN;
  bool weighted = false;
  int samples_used = 0;
  int dof = 0;  ///< 2 samples_used - parameters
  Eigen::VectorXd x;
  Eigen::MatrixXd cov_x;
  /// Slot of each arc in x (p_W at 4 slot, v_W at 4 slot + 2); -1 for an arc not fitted.
  std::vector<int> slot;
  /// The depth correction (ArcOptions::principal_point_W, apparent sizes): `depth_measured`
  /// when it was computed (some arc's apparent size changes beyond 3 s.e.), `depth_applied`
  /// when x is the corrected fit. `x_other` is the other fit (uncorrected when applied,
  /// corrected when not), on the same samples; `x_depth_perturbed` (when applied) holds the
  /// fits with arc k's depth line moved by one s.e., its level (2 k) and its rate (2 k + 1), to
  /// carry the correction's uncertainty into what is measured from x.
  bool depth_measured = false, depth_applied = false;
  Eigen::VectorXd x_other;
  std::vector<Eigen::VectorXd> x_depth_perturbed;
  /// The perspective of the plane the body moves in, seen at a slant (a camera tilted toward
  /// the floor, or turned from the plane): 1 / depth is affine in the image, proportional to
  /// 1 - h . (p - c) for a position p and the principal point c (both in W). Where applied
  /// (ArcOptions::correct_perspective), every position is moved to the depth of the lowest
  /// sample, c + (p - c) z with z = depth / that depth, and the arcs are fitted there: x is the
  /// rectified fit, `x_unrectified` the fit of the same samples as given, and
  /// `x_perspective_perturbed` the fits with h moved by one s.e. along each principal axis of
  /// its covariance. `perspective_chi2_drop` is how much it lowers the residuals' chi^2 (in
  /// units of the fitted noise), `perspective_depth_range` the spread of z over the samples.
  bool perspective_applied = false;
  Eigen::Vector2d perspective_h{0, 0};  ///< h (1 / input units)
  Eigen::Matrix2d perspective_cov_h = Eigen::Matrix2d::Zero();
  double perspective_chi2_drop = 0.0, perspective_depth_range = 0.0;
  Eigen::VectorXd x_unrectified;
  std::vector<Eigen::VectorXd> x_perspective_perturbed;
};

/// Fits the flight arcs of `poses` (one per frame, in frame order; times in PoseSample::t_s):
/// the path of C = p_WE + d_EC_m x_B(theta). Contacts are with a surface at
/// `surface_angle_deg` from gravity's perpendicular (deg, positive descending toward +x): the
/// velocity along its normal reverses there. Expected failures are in FlightArcs::status and
/// message; invalid options throw std::invalid_argument.
FlightArcs FitFlightArcs(const std::vector<PoseSample>& poses, double d_EC_m,
                         double surface_angle_deg, const ArcOptions& options = {});

/// The position of C on arc `k` of `arcs` at time `t_s`, from the parameters `x` (laid out as
/// FlightArcs::x).
Eigen::Vector2d ArcPosition(const FlightArcs& arcs, const Eigen::VectorXd& x, int k, double t_s);
/// Its velocity.
Eigen::Vector2d ArcVelocity(const FlightArcs& arcs, const Eigen::VectorXd& x, int k, double t_s);

}  // namespace hoof::kinematics
