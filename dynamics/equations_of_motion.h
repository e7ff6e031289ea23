#pragma once
/// @file
/// The equations of motion of the planar impact model (docs/science.md, "The rigid-body model") for
/// the integrator in impact_simulator.cc, with the effects of ContactExtensions. Internal to
/// hoof::dynamics: ImpactSimulator is the public face.
///
/// Generalized state x = (q1, q2, q3, q1', q2', q3'[, u]): T = (q1, q2) in S, delta = q2,
/// q3 the angle of x_B from x_S, and, with tangential compliance, u the stretch of the
/// tangential spring at T (N = 7).

#include <array>
#include <cmath>

#include <Eigen/Core>

#include "dynamics/impact_simulator.h"

namespace hoof::dynamics::internal {

/// sin and cos of an angle near a reference angle whose sin and cos are known. The body turns
/// by well under 4e-3 rad during a contact (w ~ 60 rad/s for ~30 us). There the Taylor
/// series of the offset u to degree 5 is exact to double precision (the remainders u^6/720
/// and u^7/5040 are below 6e-18 and 4e-21); farther away it falls back to std::sin/std::cos.
/// This takes the trigonometric calls off the integrator's critical path.
struct NearAngle {
  static constexpr double kMaxOffset = 4e-3;
  double ref = 0.0, s_ref = 0.0, c_ref = 1.0;

  void Reset(double angle) {
    ref = angle;
    s_ref = std::sin(angle);
    c_ref = std::cos(angle);
  }
  void Eval(double angle, double& s, double& c) const {
    const double u = angle - ref;
    if (std::abs(u) > kMaxOffset) [[unlikely]] {
      s = std::sin(angle);
      c = std::cos(angle);
      return;
    }
    const double u2 = u * u;
    const double cu = 1.0 - u2 * (0.5 - u2 * (1.0 / 24));
    const double su = u * (1.0 - u2 * (1.0 / 6 - u2 * (1.0 / 120)));
    s = s_ref * cu + c_ref * su;
    c = c_ref * cu - s_ref * su;
  }
};

/// x * |x|^p: a power that keeps the sign, so force laws stay smooth where a step overshoots
/// the end of a phase.
inline double SignedPow(double x, double p) { return x * std::pow(std::abs(x), p); }

/// Constants of one impact and the mode (phase, friction) the equations are in. With
/// kExtensions false the effects of ContactExtensions are compiled out: the paper's model, as
/// ImpactSimulator uses it when ContactExtensions::Any() is false, evaluates about a third
/// faster without their branches.
template <int N, bool kExtensions>
struct Model {
  static_assert(N == 6 || N == 7);
  static_assert(N == 6 || kExtensions, "a tangential spring is an extension");
  static constexpr int kStates = N;
  using State = std::array<double, N>;
  static constexpr bool kCompliant = N == 7;
  static constexpr double kRollingSpeed_rad_s = 1.0;  // w0 of the rolling-resistance law

  // Specimen, baseline law, gravity in S.
  double m = 0, inv_m = 0, inv_I = 0, R = 0, d = 0, k = 0, b = 0, mu = 0, mu_static = 0;
  Eigen::Vector2d g_S{0.0, 0.0};
  // Extensions (ContactExtensions); all zero is the baseline.
  double c_hc = 0, p_exp = 0, inv_delta_ref = 0, r_unload = 0, rho = 0, k_t = 0;
  double mu_slope = 0;  // mu s of speed-dependent friction (s/m); rigid stick only
  bool nonlinear = false, rolling = false, speed_friction = false;

  // Mode.
  bool compression = true;
  double delta_m = 0, P_m = 0, delta_p = 0;  // restitution law, set at maximum compression
  FrictionMode friction = FrictionMode::kNone;
  bool stick = false;
  double slip_coef = 0.0;   // F = slip_coef * P while sliding
  double slip_slope = 0.0;  // and, with speed-dependent friction, F gains -slip_slope v_T P
  NearAngle trig;

  void SetFriction(FrictionMode mode) {
    friction = mode;
    stick = mode == FrictionMode::kStick;
    slip_coef = mode == FrictionMode::kSlipPositive   ? -mu
                : mode == FrictionMode::kSlipNegative ? mu
                                                      : 0.0;
    slip_slope = slip_coef != 0.0 ? mu_slope : 0.0;
  }

  /// Enters restitution at maximum compression (delta' = 0, so P = elastic force there).
  void StartRestitution(double delta_max) {
    compression = false;
    delta_m = delta_max;
    P_m = Elastic(delta_max);
    delta_p = delta_max * r_unload / (1.0 + r_unload);
  }

  /// Elastic force k |delta| (|delta| / delta_ref)^p, as a signed power.
  double Elastic(double delta) const {
    if (!kExtensions || !nonlinear) return -k * delta;
    return -k * SignedPow(delta * inv_delta_ref, p_exp) / inv_delta_ref;
  }

  /// P of the current phase without the clamp at zero. Within a phase the law is smooth, and
  /// the integrator needs a smooth right-hand side also in the part of a step that overshoots
  /// an event (a kink there spoils the step's error estimate and its dense output). The clamp
  /// never acts before an event ends the phase: in compression delta < 0 and delta' < 0, so
  /// every term pushes; in restitution P >= 0 until separation, where P = 0.
  double NormalForce(const State& x) const {
    if constexpr (!kExtensions) return compression ? -k * x[1] - b * x[4] : -k * x[1];
    if (compression) return Elastic(x[1]) - (b + c_hc * std::abs(x[1])) * x[4];
    if (r_unload == 0.0) return Elastic(x[1]);
    return P_m * SignedPow((delta_p - x[1]) / (delta_p - delta_m), p_exp);
  }

  /// dP/dt from the state and its derivative.
  double NormalForceRate(const State& x, const State& dxdt) const {
    const double delta = x[1], rate = x[4], accel = dxdt[4];
    const double slope =
        nonlinear ? -k * (1.0 + p_exp) * std::pow(std::abs(delta) * inv_delta_ref, p_exp) : -k;
    if (compression) {
      const double sgn = delta < 0 ? -1.0 : 1.0;
      return slope * rate - c_hc * sgn * rate * rate - (b + c_hc * std::abs(delta)) * accel;
    }
    if (r_unload == 0.0) return slope * rate;
    const double span = delta_p - delta_m;
    return -P_m * (1.0 + p_exp) * std::pow(std::abs((delta_p - delta) / span), p_exp) / span * rate;
  }

  /// Contact torque about T of the rolling resistance.
  double RollingTorque(double w, double P) const {
    if constexpr (!kExtensions) return 0.0;
    return rolling ? -rho * P * w / (std::abs(w) + kRollingSpeed_rad_s) : 0.0;
  }

  /// The friction force that keeps T from sliding (q1'' + R q3'' = 0), from the first and
  /// third rows of the equations of motion.
  double StickFriction(double s, double c, double w, double P) const {
    const double arm = R + d * s;
    const double M = RollingTorque(w, P);
    return (arm * (d * c * P - M) * inv_I - g_S.x() - d * c * w * w) / (inv_m + arm * arm * inv_I);
  }

  /// Friction along x_S. Sliding: -sign(v_T) mu P, or with speed-dependent friction
  /// -sign(v_T) mu (1 + s |v_T|) P = (slip_coef - mu s v_T) P. The speed term is written with
  /// the signed v_T, so the law stays smooth where a step overshoots the slip-to-stick event
  /// (v_T = 0, where the term vanishes).
  double Friction(const State& x, double s, double c, double P) const {
    if (!stick) {
      if (kExtensions && speed_friction) return (slip_coef - slip_slope * SlidingVelocity(x)) * P;
      return slip_coef * P;
    }
    if constexpr (kCompliant) return -k_t * x[6];
    return StickFriction(s, c, x[5], P);
  }

  /// The mass matrix (docs/science.md, "The rigid-body model") is upper triangular: solve from
  /// the bottom row.
  void operator()(const State& x, State& dxdt, double /*t*/) const {
    double s, c;
    trig.Eval(x[2], s, c);
    const double w = x[5];
    const double P = NormalForce(x);
    const double F = Friction(x, s, c, P);
    const double ds = d * s;
    const double dc = d * c;
    double torque = -dc * P + (R + ds) * F;
    if (kExtensions && rolling) torque += RollingTorque(w, P);
    const double a3 = torque * inv_I;
    dxdt[0] = x[3];
    dxdt[1] = x[4];
    dxdt[2] = w;
    dxdt[3] = g_S.x() + F * inv_m + dc * w * w + ds * a3;
    dxdt[4] = g_S.y() + P * inv_m + ds * w * w - dc * a3;
    dxdt[5] = a3;
    if constexpr (kCompliant) dxdt[6] = stick ? x[3] + R * w : 0.0;
  }

  double SlidingVelocity(const State& x) const { return x[3] + R * x[5]; }

  /// Stretch of the tangential spring (compliant model): a state while stuck, and pinned at
  /// the friction limit, -F / k_t, while the slider moves.
  double SpringStretch(const State& x) const {
    if constexpr (kCompliant) return stick ? x[6] : -slip_coef * NormalForce(x) / k_t;
    return 0.0;
  }

  /// Elastic energy stored in the contact (J): normal spring plus tangential spring.
  double StoredEnergy(const State& x) const {
    const double delta = x[1];
    double U = 0.0;
    if (compression || r_unload == 0.0) {
      if (delta < 0.0) {
        const double depth = -delta;
        U = nonlinear ? k * depth * depth * std::pow(depth * inv_delta_ref, p_exp) / (2.0 + p_exp)
                      : 0.5 * k * depth * depth;
      }
    } else if (delta < delta_p) {
      const double span = delta_p - delta_m;
      const double ratio = (delta_p - delta) / span;
      U = P_m * span * std::pow(ratio, 2.0 + p_exp) / (2.0 + p_exp);
    }
    if constexpr (kCompliant) {
      const double u = SpringStretch(x);
      U += 0.5 * k_t * u * u;
    }
    return U;
  }
};

}  // namespace hoof::dynamics::internal
