#pragma once
/// @file
/// From body poses to impact physics (docs/tracking.md, "4. Kinematics"), the windows method:
/// gravity-aware fits of the free flight before and after the impact, a sub-frame impact time
/// where the fits meet, and the velocities, spin, e and mu_eff with standard errors propagated
/// from the fit residuals. (kinematics/arc_impacts.h measures every flight arc at once instead;
/// both give ImpactKinematics.)
///
/// Free flight is a parabola, not a line: the centre of mass C follows
/// p(t) = p* + v (t - t*) + g (t - t*)^2 / 2 with g known (9.81 m/s^2 along -y_W), and the
/// angle is linear, theta(t) = theta* + w (t - t*). Frames whose exposure may overlap the
/// contact are left out.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/frames.h"
#include "core/specimen.h"
#include "kinematics/flight_arcs.h"
#include "kinematics/pose_sample.h"

namespace hoof::kinematics {

/// How MeasureTrialImpacts (pipeline/trial_impacts.h) measures a clip's impacts.
enum class KinematicsMethod {
  /// The windows where every window holds fit_frames frames, the joint arcs otherwise.
  kAuto,
  kWindows,  ///< fit_frames frames before and after each impact, g known along -y_W
  kArcs,     ///< every flight arc at once with one fitted acceleration (flight_arcs.h)
};

/// "auto", "windows", "arcs".
const char* KinematicsMethodName(KinematicsMethod m);
/// The method named `name` ("auto", "windows" or "arcs"); throws std::invalid_argument naming
/// the value otherwise.
KinematicsMethod ParseKinematicsMethod(const std::string& name);

/// Settings of the impact measurement.
struct KinematicsOptions {
  int fit_frames = 20;           ///< frames per fit, before and after (the paper's 20); >= 3
  int min_fit_frames = 6;        ///< fewer usable frames than this is an error; >= 3
  double max_contact_s = 50e-6;  ///< longest contact assumed when leaving frames out (s); >= 0
  double exposure_s = -1.0;      ///< exposure time (s); < 0 means one frame period (worst case)
  double gravity_m_s2 = core::kStandardGravity_m_s2;  ///< g along -y_W
  double confidence = 0.95;  ///< level of the reported intervals; in (0, 1)
  /// Which method MeasureTrialImpacts uses (pipeline/trial_impacts.h).
  KinematicsMethod method = KinematicsMethod::kAuto;
  ArcOptions arcs;  ///< the joint arc fit's settings

  void Validate() const;
};

/// A fit of one free-flight window.
struct FlightFit {
  int first_frame = -1, last_frame = -1, n = 0;  ///< frames used (indices into the sequence)
  Eigen::Vector2d p_WC{0, 0};                    ///< position of C at the impact time (m)
  Eigen::Vector2d v_WC{0, 0};                    ///< velocity of C at the impact time (m/s), W
  Eigen::Matrix2d cov_v_WC = Eigen::Matrix2d::Zero();  ///< its covariance ((m/s)^2)
  double theta_W_rad = 0.0;                            ///< angle at the impact time
  double w_rad_s = 0.0;                                ///< angular velocity
  double w_se_rad_s = 0.0;
  double theta_se_rad = 0.0;
  double rms_residual_m = 0.0;  ///< of the position fit
  double rms_theta_residual_rad = 0.0;
};

/// What limited one impact's measurement. The joint arc fit fills every field; the window fits
/// fill the sample counts only.
struct ImpactLimits {
  int samples_before = 0, samples_after = 0;  ///< positions fitted before and after the impact
  /// Frames beside the contact and off both arcs (the body touching, or blurred across the
  /// contact), left out.
  std::vector<int> contact_frames;
  std::vector<int> outlier_frames;  ///< frames of the two arcs off them, left out
  /// Frames before the first arc or after the last that are not on it (held by a hand, rolling).
  std::vector<int> not_in_flight_frames;
  std::vector<int> missing_frames;   ///< frames within the two arcs without a position
  std::vector<int> repeated_frames;  ///< frames within them that repeat the previous image
  /// An arc beside the impact holds fewer than ArcOptions::min_arc_frames samples: the impact
  /// is found but not measured.
  bool short_arc = false;
  /// (dZ/dt) / Z (1/s) of the arcs before and after, from the apparent size; NaN without it.
  double depth_rate_before_per_s = core::kNaN, depth_rate_after_per_s = core::kNaN;
  bool depth_corrected = false;  ///< e and the velocities are corrected for the depth motion
  /// e corrected for the depth motion minus e uncorrected (the bias of the uncorrected e); NaN
  /// when the apparent size does not change significantly or no principal point is given.
  double e_depth_shift = core::kNaN;
  /// e from the arcs rectified for the perspective of a plane seen at a slant minus e from
  /// them as seen (FlightArcs::perspective_applied); NaN where it was not applied.
  double e_perspective_shift = core::kNaN;
  /// How far apart the two arcs are along the surface where they meet (0 for an instantaneous
  /// impact), and its standard error (m).
  double meeting_gap_m = core::kNaN, meeting_gap_se_m = core::kNaN;
  /// A ball's spin on each side: how it was measured from its texture, or why it was not
  /// (pipeline/impact_spin.h); empty for a body whose angle is tracked.
  std::string spin_before, spin_after;
};

/// Everything measured about one impact. Vectors in S are [along the surface, normal].
struct ImpactKinematics {
  bool success = false;
  std::string message;  ///< why it failed
  /// The failure is that the motion holds no impact (it does not come down and rebound with
  /// enough frames on each side), not a fault of the data.
  bool no_impact = false;
  std::vector<std::string> warnings;  ///< e.g. a second bounce, naming the frame
  std::vector<std::string> flags;     ///< short machine-readable tags ("second_bounce", ...)

  double impact_time_s = 0.0;  ///< where the before and after fits of T's height meet
  int impact_frame = -1;       ///< last frame before the impact time
  /// The impact's place in the clip (0 = the first; MeasureImpact's is 0) and the frame where it
  /// was found (the lowest point of the round end near it; -1 when none was). An impact that
  /// MeasureImpacts found but could not measure (success false, `message` says why) has
  /// impact_time_s that frame's time and impact_frame that frame.
  int index = 0;
  int lowest_frame = -1;
  FlightFit before, after;

  Eigen::Vector2d v_SC_before{0, 0}, v_SC_after{0, 0};  ///< velocity of C in S (m/s)
  Eigen::Vector2d v_SC_before_se{0, 0}, v_SC_after_se{0, 0};
  Eigen::Vector2d v_ST_before{0, 0}, v_ST_after{0, 0};  ///< velocity of the body point at T
  double w_before_rad_s = 0.0, w_after_rad_s = 0.0;
  double w_before_se_rad_s = 0.0, w_after_se_rad_s = 0.0;
  double e = 0.0, e_se = 0.0, e_ci_low = 0.0, e_ci_high = 0.0;
  /// |dv_x / dv_y| over the impact; NaN on a level surface (a normal impact), where it is not
  /// defined.
  double mu_eff = 0.0, mu_eff_se = 0.0, mu_eff_ci_low = 0.0, mu_eff_ci_high = 0.0;
  double kinetic_energy_before_J = 0.0, kinetic_energy_after_J = 0.0;
  /// Their standard errors, from the velocity fits and the scale's (kinematics/gravity_scale.h,
  /// AddScaleUncertainty); NaN until it is called.
  double kinetic_energy_before_se_J = core::kNaN, kinetic_energy_after_se_J = core::kNaN;

  /// kWindows (MeasureImpact, MeasureImpacts) or kArcs (kinematics/arc_impacts.h).
  KinematicsMethod method = KinematicsMethod::kWindows;
  double impact_time_se_s = core::kNaN;  ///< s.e. of impact_time_s; NaN from the windows
  /// The surface's angle in W that S is built from (deg): trial.json's angle, plus the fitted
  /// roll of gravity for the joint arcs.
  double surface_angle_W_deg = core::kNaN;
  /// The contact point T where the arcs meet (m, W) and its covariance; NaN from the windows.
  Eigen::Vector2d p_WT{core::kNaN, core::kNaN};
  Eigen::Matrix2d cov_p_WT = Eigen::Matrix2d::Constant(core::kNaN);
  ImpactLimits limits;
};

/// Measures the impact in `poses` (one per frame, in frame order) for a surface at
/// `surface_angle_deg`. Expected failures (no impact, too few frames) come back in
/// ImpactKinematics::success and message; invalid options throw std::invalid_argument.
ImpactKinematics MeasureImpact(const std::vector<PoseSample>& poses, double fps,
                               double surface_angle_deg, const core::SpecimenParameters& body,
                               const KinematicsOptions& options = {});

/// Finds every impact in `poses` and measures each on its own, in time order; empty when the
/// clip holds none (MeasureImpact then says why). An impact is a frame where the round end E is
/// lowest along the surface normal near it, reached descending and left rising, as low as the
/// clip's lowest frame give or take how far E moves in a frame. The free flight between two
/// impacts is the fit after the first and the fit before the second, the frames whose exposure
/// may overlap either contact left out; an arc with fewer than min_fit_frames usable frames
/// leaves its impacts found but not measured (success false, `message` says why). With one
/// impact the result is MeasureImpact's, bit for bit. Invalid options throw
/// std::invalid_argument.
std::vector<ImpactKinematics> MeasureImpacts(const std::vector<PoseSample>& poses, double fps,
                                             double surface_angle_deg,
                                             const core::SpecimenParameters& body,
                                             const KinematicsOptions& options = {});

}  // namespace hoof::kinematics
