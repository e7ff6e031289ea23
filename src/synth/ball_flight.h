#pragma once
/// @file
/// The everyday-footage ball's motion, exact and analytic (docs/synthetic-trials.md, "Everyday
/// footage"): held, carried by the hand, released, ballistic flight under gravity, instantaneous
/// rigid-sphere impacts on the surface y_W = 0 (Newton restitution e along the normal, Coulomb
/// friction mu with rolling), then, once a rebound would be too small, sliding and rolling on
/// the surface. No air drag. Plain data on Eigen.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "synth/footage_options.h"

namespace hoof::synth {

/// What the ball is doing at a time.
enum class BallPhase {
  kAbsent,   ///< No ball in the clip (kHandOnly).
  kHeld,     ///< In the hand (at rest, or carried during a throw).
  kFlight,   ///< Free flight.
  kSliding,  ///< On the surface after the last bounce, slipping.
  kRolling,  ///< On the surface, rolling without slip.
  kRest,     ///< Lying still on the surface (kStill).
};
/// "absent", "held", "flight", "sliding", "rolling" or "rest".
const char* ToString(BallPhase phase);

/// The ball's state at one time, in W.
struct BallState {
  BallPhase phase = BallPhase::kAbsent;
  Eigen::Vector3d p_WC_m = Eigen::Vector3d::Zero();     ///< Centre (m).
  Eigen::Vector3d v_WC_m_s = Eigen::Vector3d::Zero();   ///< Centre's velocity (m/s).
  Eigen::Vector3d w_W_rad_s = Eigen::Vector3d::Zero();  ///< Angular velocity (rad/s).
  Eigen::Matrix3d R_WB = Eigen::Matrix3d::Identity();   ///< Orientation: body axes in W.
};

/// The outcome of one rigid-sphere impact on a plane.
struct SphereImpact {
  Eigen::Vector3d v_after_m_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_after_rad_s = Eigen::Vector3d::Zero();
  /// Impulse per unit mass on the ball (m/s): j_n n + j_t, with j_t tangential.
  Eigen::Vector3d impulse_per_kg_m_s = Eigen::Vector3d::Zero();
  double mu_eff = 0.0;   ///< |j_t| / j_n = |dv_t| / |dv_n|.
  bool rolling = false;  ///< The contact point leaves with no slip (|j_t| <= mu j_n needed).
};

/// The standard rigid-sphere impact of a sphere (radius r, I = k m r^2) on a fixed plane with
/// unit normal n, the sphere approaching (v.n < 0). Normal: j_n = -(1 + e) v.n. Tangential: the
/// contact point's slip u_t = v_t + w x (-r n) changes by j_t (1 + 1/k); if the impulse that
/// ends the slip, -u_t k / (1 + k), is within mu j_n the ball leaves rolling, else it slides
/// throughout and j_t = -mu j_n u_t / |u_t| (for a sphere the slip keeps its direction during the
/// impact). Spin: w' = w - n x j_t / (k r).
SphereImpact ResolveSphereImpact(const Eigen::Vector3d& v_m_s, const Eigen::Vector3d& w_rad_s,
                                 double radius_m, double inertia_factor, double e, double mu,
                                 const Eigen::Vector3d& n = Eigen::Vector3d::UnitY());

/// One bounce.
struct BallBounce {
  double t_s = 0.0;                                        ///< Contact time, since capture 0.
  Eigen::Vector3d p_WC_m = Eigen::Vector3d::Zero();        ///< Centre at contact (m).
  Eigen::Vector3d p_WT_m = Eigen::Vector3d::Zero();        ///< Contact point (m), y = 0.
  Eigen::Vector3d v_before_m_s = Eigen::Vector3d::Zero();  ///< Centre just before.
  Eigen::Vector3d v_after_m_s = Eigen::Vector3d::Zero();   ///< Centre just after.
  Eigen::Vector3d w_before_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_after_rad_s = Eigen::Vector3d::Zero();
  double e = 0.0;        ///< The restitution drawn for this bounce: -v_after.y / v_before.y.
  double mu_eff = 0.0;   ///< |dv_t| / |dv_n|.
  bool rolling = false;  ///< Left rolling (friction below mu).
};

/// One piece of the motion on which it is a polynomial: p = p0 + v0 s + a s^2 / 2 and
/// w = w0 + alpha s, s = t - t0, for t in [t0, t1).
struct PathSegment {
  double t0 = 0.0, t1 = 0.0;
  BallPhase phase = BallPhase::kHeld;
  Eigen::Vector3d p0 = Eigen::Vector3d::Zero(), v0 = Eigen::Vector3d::Zero();
  Eigen::Vector3d a = Eigen::Vector3d::Zero();
  Eigen::Vector3d w0 = Eigen::Vector3d::Zero(), alpha = Eigen::Vector3d::Zero();
  Eigen::Matrix3d R0 = Eigen::Matrix3d::Identity();
  /// With alpha != 0 (sliding), orientations every step_s from t0 (the spin turns).
  std::vector<Eigen::Matrix3d> R_steps;
  double step_s = 0.0;
};

/// The whole motion of the ball from -infinity to +infinity.
struct BallPath {
  double radius_m = 0.0;
  double inertia_factor = 0.4;
  double g_m_s2 = 9.81;
  bool present = true;  ///< false for kHandOnly.
  double release_time_s = 0.0;
  double carry_start_s = 0.0;  ///< When the hand starts carrying it (= release without a throw).
  /// The contact without rebound that ended the bouncing (NaN when the clip ends first), and
  /// when the sliding that follows it ends (rolling from then on; = settle_time_s without slip).
  double settle_time_s = 0.0;
  double rolling_time_s = 0.0;
  std::vector<BallBounce> bounces;    ///< Every bounce before end_s, in time order.
  std::vector<PathSegment> segments;  ///< Contiguous, in time order.
  double end_s = 0.0;                 ///< The planned horizon (the clip's end).
  /// The state at `t_s` (the first segment before it, the last after it). At a contact time the
  /// state is the one just after.
  BallState At(double t_s) const;
};

/// Plans the motion for a scenario from release to `end_s`; the per-bounce e are drawn from
/// `seed`. kStill lies at (x, r, z) of the launch; kHandOnly has no ball.
BallPath PlanBallPath(FootageScenario scenario, const BallOptions& ball,
                      const LaunchOptions& launch, const BounceOptions& bounce, double end_s,
                      std::uint64_t seed);

/// exp([w] s) R: the orientation after turning at constant w for s seconds.
Eigen::Matrix3d Turn(const Eigen::Matrix3d& R, const Eigen::Vector3d& w_rad_s, double s);

}  // namespace hoof::synth
