#pragma once
/// @file
/// The integration of one impact (internal to hoof::dynamics): Odeint's dense-output
/// Dormand-Prince stepper with the scaled error norm, event location of the phase and friction
/// switches, and Run(), templated on the equations of motion (equations_of_motion.h).
/// ImpactSimulator is the public face.
///
/// Each instantiation of Run is compiled in a translation unit of its own
/// (impact_run_*.cc): GCC caps the inlining growth of a unit, and with all three models in
/// one unit it stopped inlining Odeint's stage arithmetic into the step, which cost the paper's
/// model 10 % (docs/performance.md).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numeric>
#include <span>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <boost/math/tools/roots.hpp>
#include <boost/numeric/odeint.hpp>

#include "core/frames.h"
#include "dynamics/equations_of_motion.h"
#include "dynamics/impact_simulator.h"

namespace hoof::dynamics::internal {

namespace odeint = boost::numeric::odeint;

/// Events are bracketed to this width: a hundredth of the 1e-12 s to which the tests hold the
/// event times (docs/science.md, "Numbers the tests hold the simulator to").
inline constexpr double kEventTimeTolerance_s = 1e-14;

/// Step-size control for Odeint's controlled stepper (its StepAdjuster concept): the standard
/// rule dt *= clamp(0.9 err^(-1/q), 0.2, 5) (Hairer, Norsett & Wanner, II.4), with err^(-1/q)
/// from std::exp(std::log()) of a float, since a controller factor needs no more digits.
/// Unlike Odeint's default it also grows the step for 0.5 < err < 1.
struct StepAdjuster {
  using time_type = double;
  using value_type = double;
  static double Factor(double error, int order) {
    const float f =
        0.9f * std::exp(-std::log(static_cast<float>(error)) / static_cast<float>(order));
    return std::clamp(static_cast<double>(f), 0.2, 5.0);
  }
  double decrease_step(double dt, double error, int error_order) const {
    return dt * std::min(Factor(error, error_order), 0.9);
  }
  double increase_step(double dt, double error, int stepper_order) const {
    return dt * Factor(std::max(error, 1e-12), stepper_order);
  }
  bool check_step_size_limit(double /*dt*/) const { return true; }
  double get_max_dt() const { return 0.0; }
};

/// Odeint error checker (the concept controlled_runge_kutta uses) with the scaled norm of
/// Hairer, Norsett & Wanner (II.4): the error estimate of state i is measured against
/// atol + rtol max(|x_i|, s_i), where s_i is the scale of that state in this impact (see
/// StateScales). Odeint's default, atol + rtol (|x_i| + dt |x_i'|), asks a state that starts at
/// zero (the depth, the angular velocity, T's travel) for a relative accuracy far beyond the
/// one asked of the velocities, so those states set the step while carrying no more of the
/// result.
template <int N>
struct ScaledErrorChecker {
  using value_type = double;
  using algebra_type = odeint::array_algebra;
  using operations_type = odeint::default_operations;

  double atol = 0.0, rtol = 0.0;
  std::array<double, N> scale{};

  template <class State, class Deriv, class Err, class Time>
  double error(algebra_type& /*algebra*/, const State& x_old, const Deriv& /*dxdt_old*/, Err& x_err,
               Time /*dt*/) const {
    double max_ratio = 0.0;
    for (int i = 0; i < N; ++i) {
      const double allowed = atol + rtol * std::max(std::abs(x_old[i]), scale[i]);
      max_ratio = std::max(max_ratio, std::abs(x_err[i]) / allowed);
    }
    return max_ratio;
  }
};

/// Odeint's dense-output Dormand-Prince 5(4) (the analogue of MATLAB's ode45) on N states.
template <int N>
struct Integrator {
  using State = std::array<double, N>;
  using Stepper = odeint::runge_kutta_dopri5<State>;
  using ErrorChecker = ScaledErrorChecker<N>;
  using Controlled =
      odeint::controlled_runge_kutta<Stepper, ErrorChecker, StepAdjuster, odeint::initially_resizer,
                                     odeint::explicit_error_stepper_fsal_tag>;
  using Dense = odeint::dense_output_runge_kutta<Controlled>;
};

/// State in generalized coordinates -> body pose and twist in S. (model.trig gives sin and
/// cos: exact, and cheap near the touch angle; see NearAngle.)
template <class M>
BodyState ToBody(const M& model, const typename M::State& x) {
  double s, c;
  model.trig.Eval(x[2], s, c);
  BodyState body;
  body.p_SC = {x[0] + model.d * c, x[1] + model.R + model.d * s};
  body.v_SC = {x[3] - model.d * s * x[5], x[4] + model.d * c * x[5]};
  body.theta_S_rad = x[2];
  body.w_rad_s = x[5];
  return body;
}

/// Body pose and twist -> generalized coordinates (T is the point of the round end nearest
/// the surface, directly below E). The tangential spring, if any, starts unstretched.
template <class M>
typename M::State FromBody(const M& model, const BodyState& body) {
  double s, c;
  model.trig.Eval(body.theta_S_rad, s, c);
  const double w = body.w_rad_s;
  typename M::State x{};
  x[0] = body.p_SC.x() - model.d * c;
  x[1] = body.p_SC.y() - model.d * s - model.R;
  x[2] = body.theta_S_rad;
  x[3] = body.v_SC.x() + model.d * s * w;
  x[4] = body.v_SC.y() - model.d * c * w;
  x[5] = w;
  return x;
}

/// The friction force that would keep T from sliding in state x, under normal force P.
template <class M>
double StickFrictionAt(const M& model, const typename M::State& x, double P) {
  double s, c;
  model.trig.Eval(x[2], s, c);
  return model.StickFriction(s, c, x[5], P);
}

/// Event function of the current phase: the phase ends when it becomes positive. Compression
/// ends at delta' = 0; restitution where P returns to 0 (delta = delta_p, 0 unless unloading
/// is plastic).
template <class M>
double PhaseEvent(const M& model, const typename M::State& x) {
  return model.compression ? x[4] : x[1] - model.delta_p;
}

/// Event function of the current friction mode: the mode ends when it becomes positive.
template <class M>
double FrictionEvent(const M& model, const typename M::State& x) {
  using State = typename M::State;
  const double sigma = model.friction == FrictionMode::kSlipPositive ? 1.0 : -1.0;
  switch (model.friction) {
    case FrictionMode::kSlipPositive:
    case FrictionMode::kSlipNegative: {
      if constexpr (M::kCompliant) {
        // The slider stops when T's velocity equals the rate of the pinned spring stretch.
        State dxdt;
        model(x, dxdt, 0.0);
        const double stretch_rate = -model.slip_coef * model.NormalForceRate(x, dxdt) / model.k_t;
        return -sigma * (model.SlidingVelocity(x) - stretch_rate);
      }
      return -sigma * model.SlidingVelocity(x);
    }
    case FrictionMode::kStick: {
      const double P = model.NormalForce(x);
      if constexpr (M::kCompliant) return model.k_t * std::abs(x[6]) - model.mu_static * P;
      const double F = StickFrictionAt(model, x, P);
      return std::abs(F) - model.mu_static * P;
    }
    case FrictionMode::kNone:
      break;
  }
  return -1.0;
}

/// Friction mode for a rigid contact point that has (just) stopped sliding: stick if the
/// static friction cone can hold it, otherwise slide the way the unbalanced force pushes.
template <class M>
FrictionMode ModeAtRest(const M& model, const typename M::State& x) {
  const double P = model.NormalForce(x);
  const double F = StickFrictionAt(model, x, P);
  if (std::abs(F) <= model.mu_static * P) return FrictionMode::kStick;
  return F > 0.0 ? FrictionMode::kSlipNegative : FrictionMode::kSlipPositive;
}

template <class M>
TrajectorySample MakeSample(const M& model, const SpecimenParameters& specimen, double t,
                            const typename M::State& x, ContactPhase phase) {
  TrajectorySample sample;
  sample.t_s = t;
  sample.body = ToBody(model, x);
  sample.p_SE = {x[0], x[1] + model.R};
  sample.v_ST = {model.SlidingVelocity(x), x[4]};
  sample.delta_m = x[1];
  const bool in_contact =
      phase == ContactPhase::kCompression || phase == ContactPhase::kRestitution;
  sample.phase = phase;
  sample.kinetic_energy_J = KineticEnergy(specimen, sample.body);
  sample.potential_energy_J = -specimen.mass_kg * model.g_S.dot(sample.body.p_SC);
  if (in_contact) {
    double s, c;
    model.trig.Eval(x[2], s, c);
    sample.normal_force_N = std::max(0.0, model.NormalForce(x));
    sample.friction_force_N = model.Friction(x, s, c, sample.normal_force_N);
    sample.friction = model.friction;
    sample.potential_energy_J += model.StoredEnergy(x);
  }
  return sample;
}

/// Finds the first time in (t0, t1] where `event` of the dense output becomes positive,
/// given its values at the ends of the step (g_t1 > 0). Returns t0 when the event holds from
/// the start.
template <class Dense, class EventFn>
double LocateEvent(const Dense& stepper, double t0, double t1, double g_t0, double g_t1,
                   EventFn event) {
  typename Dense::state_type x;
  auto g = [&](double t) {
    stepper.calc_state(t, x);
    return event(x);
  };
  // Bracket: a point in [t0, t1) where the event function is not positive.
  double lo = t0;
  double g_lo = g_t0;
  for (int i = 1; g_lo > 0.0 && i < 8; ++i) {
    lo = t0 + (t1 - t0) * (1.0 - std::pow(0.5, i));
    g_lo = g(lo);
  }
  if (g_lo > 0.0) return t0;
  if (g_lo == 0.0 && lo == t0) {
    // Starting on the boundary (a mode just entered): step inside before bracketing.
    const double probe = t0 + (t1 - t0) * 1e-6;
    g_lo = g(probe);
    if (g_lo > 0.0) return t0;
    lo = probe;
  }
  std::uintmax_t max_iter = 100;
  auto tol = [](double a, double b) { return std::abs(b - a) <= kEventTimeTolerance_s; };
  const auto [a, b] = boost::math::tools::toms748_solve(g, lo, t1, g_lo, g_t1, tol, max_iter);
  (void)a;
  return b;  // The first time at which the event function is >= 0.
}

/// Scales of the states of one impact for the error norm (ScaledErrorChecker): the normal
/// approach speed V of T for the velocities, the penetration scale L = V / omega_n for the
/// positions (and the tangential spring), and V and L over the body's reach R + d for the
/// angular velocity and the angle.
template <class M>
std::array<double, M::kStates> StateScales(const M& model, const typename M::State& x_touch,
                                           double omega_n) {
  const double V = std::abs(x_touch[4]);
  const double L = V / omega_n;
  const double reach = model.R + model.d;
  std::array<double, M::kStates> scale{};
  scale[0] = L;
  scale[1] = L;
  scale[2] = L / reach;
  scale[3] = V;
  scale[4] = V;
  scale[5] = V / reach;
  if constexpr (M::kCompliant) scale[6] = L;
  return scale;
}

template <class M>
M MakeModel(const SpecimenParameters& specimen, const ContactParameters& contact,
            const SimulatorOptions& options, const ImpactConditions& conditions) {
  const ContactExtensions& ext = contact.extensions;
  M model;
  model.m = specimen.mass_kg;
  model.inv_m = 1.0 / specimen.mass_kg;
  model.inv_I = 1.0 / specimen.inertia_kg_m2;
  model.R = specimen.end_radius_m;
  model.d = specimen.d_EC_m;
  model.k = contact.k_N_m;
  model.b = contact.b_N_s_m;
  model.mu = contact.mu;
  model.mu_static = contact.mu + ext.static_friction_excess;
  model.g_S = GravityInSurfaceFrame(conditions.surface_angle_rad, options.gravity_m_s2);
  model.c_hc = ext.hunt_crossley_N_s_m2;
  model.p_exp = ext.stiffness_exponent_extra;
  model.nonlinear = ext.stiffness_exponent_extra != 0.0;
  model.inv_delta_ref = 1.0 / ext.stiffness_reference_depth_m;
  model.r_unload = ext.unloading_stiffness_ratio;
  model.rho = ext.rolling_resistance_m;
  model.rolling = ext.rolling_resistance_m != 0.0;
  model.mu_slope = contact.mu * ext.friction_speed_slope_s_m;
  model.speed_friction = model.mu_slope != 0.0;
  if (ext.tangential_compliance_ratio > 0.0)
    model.k_t = contact.k_N_m / ext.tangential_compliance_ratio;
  return model;
}

/// The samples a caller asked for, emitted in time order into their places in `result`.
template <class M>
class SampleEmitter {
 public:
  SampleEmitter(const M& model, const SpecimenParameters& specimen,
                std::span<const double> sample_times_s, ImpactResult& result)
      : model_(model),
        specimen_(specimen),
        times_(sample_times_s),
        result_(result),
        order_(sample_times_s.size()) {
    std::iota(order_.begin(), order_.end(), std::size_t{0});
    std::sort(order_.begin(), order_.end(),
              [&](std::size_t a, std::size_t b) { return times_[a] < times_[b]; });
    result_.samples.resize(times_.size());
  }
  /// Every sample up to `t_limit`, its state from `state_at(t)`, in `phase`.
  template <class StateAt>
  void Until(double t_limit, StateAt&& state_at, ContactPhase phase) {
    while (next_ < order_.size() && times_[order_[next_]] <= t_limit) {
      const double t = times_[order_[next_]];
      result_.samples[order_[next_]] = MakeSample(model_, specimen_, t, state_at(t), phase);
      ++next_;
    }
  }

 private:
  const M& model_;
  const SpecimenParameters& specimen_;
  std::span<const double> times_;
  ImpactResult& result_;
  std::vector<std::size_t> order_;  // requested samples in time order
  std::size_t next_ = 0;
};

/// The friction mode at first touch: the tangential spring starts unstretched (stick); a rigid
/// contact slides the way the contact point moves, or, at rest, sticks or slips as the forces
/// allow.
template <class M>
void SetInitialFriction(M& model, typename M::State& x) {
  if (!(model.mu > 0.0)) return;
  if constexpr (M::kCompliant) {
    model.SetFriction(FrictionMode::kStick);
  } else {
    const double v_slide = model.SlidingVelocity(x);
    const double scale = 1e-12 * std::max(1.0, std::abs(x[4]));
    if (v_slide > scale) {
      model.SetFriction(FrictionMode::kSlipPositive);
    } else if (v_slide < -scale) {
      model.SetFriction(FrictionMode::kSlipNegative);
    } else {
      x[3] = -model.R * x[5];
      model.SetFriction(ModeAtRest(model, x));
    }
  }
}

/// The event at `t_event` with state `xe`: maximum compression or separation (`phase_event`),
/// or a change of friction mode. Records it in `result`; true at separation.
template <class M>
bool HandleEvent(M& model, typename M::State& xe, double t_event, bool phase_event,
                 ImpactResult& result) {
  if (phase_event && model.compression) {
    xe[4] = 0.0;  // Exactly at maximum compression.
    model.StartRestitution(xe[1]);
    result.t_max_compression_s = t_event;
    result.at_max_compression = ToBody(model, xe);
    result.max_penetration_m = -xe[1];
    result.events.push_back({t_event, "max_compression"});
    return false;
  }
  if (phase_event) {
    xe[1] = model.delta_p;  // Exactly where the contact force returns to zero.
    result.t_separation_s = t_event;
    result.events.push_back({t_event, "separation"});
    return true;
  }
  if (model.friction == FrictionMode::kStick) {
    double push;  // sign of the force the contact can no longer hold, along x_S
    if constexpr (M::kCompliant) {
      push = xe[6];
    } else {
      const double P = model.NormalForce(xe);
      push = -StickFrictionAt(model, xe, P);
    }
    model.SetFriction(push > 0.0 ? FrictionMode::kSlipPositive : FrictionMode::kSlipNegative);
  } else {
    if constexpr (M::kCompliant) {
      xe[6] = model.SpringStretch(xe);  // the slider stops with the spring at the limit
      model.SetFriction(FrictionMode::kStick);
    } else {
      xe[3] = -model.R * xe[5];  // T has stopped sliding.
      model.SetFriction(ModeAtRest(model, xe));
    }
  }
  result.events.push_back({t_event, ToString(model.friction)});
  return false;
}

/// After separation at state `x`: the flight after, and the impact's measures (e, mu_eff,
/// energies) from the states at touch and at separation.
template <class M>
void FinishImpact(M& model, const SpecimenParameters& specimen, const typename M::State& x,
                  const BodyState& touch, SampleEmitter<M>& emit, ImpactResult& result) {
  const BodyState after = ToBody(model, x);
  result.at_separation = after;
  result.v_ST_after = {model.SlidingVelocity(x), x[4]};
  model.SetFriction(FrictionMode::kNone);
  emit.Until(
      std::numeric_limits<double>::infinity(),
      [&](double t) {
        return FromBody(model, PropagateFlight(after, model.g_S, t - result.t_separation_s));
      },
      ContactPhase::kFlightAfter);
  result.e = std::abs(result.v_ST_after.y() / result.v_ST_before.y());
  const Eigen::Vector2d dv = after.v_SC - touch.v_SC;
  result.mu_eff = dv.y() != 0.0 ? std::abs(dv.x() / dv.y()) : core::kNaN;
  result.kinetic_energy_before_J = KineticEnergy(specimen, touch);
  result.kinetic_energy_after_J = KineticEnergy(specimen, after);
  result.energy_loss_J = result.kinetic_energy_before_J - result.kinetic_energy_after_J;
  result.success = true;
}

/// Why a contact that did not end within `max_steps` steps (at `t_s` into it) failed.
inline std::string TooManySteps(int max_steps, double t_s, double omega_n) {
  std::ostringstream os;
  os << "the contact did not end within " << max_steps << " integration steps (t = " << t_s
     << " s into it, against a natural period of " << 2 * M_PI / omega_n
     << " s): the contact law is too stiff, too soft or too damped for this specimen's mass and "
        "inertia (options.max_steps)";
  return os.str();
}

/// The earliest event in (t0, t1] of the step the stepper just took, and whether it is a phase
/// event (else a friction event; the friction event wins only when strictly earlier); infinity
/// when there is none.
template <class M, class Stepper>
std::pair<double, bool> EarliestEvent(M& model, Stepper& stepper, double t0, double t1) {
  using State = typename M::State;
  const State& x0 = stepper.previous_state();
  const State& x1 = stepper.current_state();
  double t_event = std::numeric_limits<double>::infinity();
  bool phase_event = false;
  if (const double g1 = PhaseEvent(model, x1); g1 > 0.0) {
    t_event = LocateEvent(stepper, t0, t1, PhaseEvent(model, x0), g1,
                          [&](const State& s) { return PhaseEvent(model, s); });
    phase_event = true;
  }
  if (const double g1 = FrictionEvent(model, x1); g1 > 0.0) {
    const double t_f = LocateEvent(stepper, t0, t1, FrictionEvent(model, x0), g1,
                                   [&](const State& s) { return FrictionEvent(model, s); });
    if (t_f < t_event) {
      t_event = t_f;
      phase_event = false;
    }
  }
  return {t_event, phase_event};
}

/// One impact from first touch to separation, on N states (7 with a tangential spring).
template <class M>
ImpactResult Run(const SpecimenParameters& specimen, const ContactParameters& contact,
                 const SimulatorOptions& options, const ImpactConditions& conditions,
                 std::span<const double> sample_times_s) {
  using State = typename M::State;
  constexpr int N = M::kStates;
  M model = MakeModel<M>(specimen, contact, options, conditions);

  ImpactResult result;
  result.events.reserve(4);
  BodyState touch;
  touch.theta_S_rad = conditions.theta_S_rad;
  touch.w_rad_s = conditions.w_rad_s;
  touch.v_SC = conditions.v_SC_m_s;
  model.trig.Reset(touch.theta_S_rad);
  touch.p_SC = {specimen.d_EC_m * model.trig.c_ref,
                specimen.end_radius_m + specimen.d_EC_m * model.trig.s_ref};
  State x = FromBody(model, touch);
  result.at_touch = touch;
  result.v_ST_before = {model.SlidingVelocity(x), x[4]};

  SampleEmitter<M> emit(model, specimen, sample_times_s, result);
  // Flight before: t < 0. A sample at t = 0 belongs to the contact (P jumps to b |v| there).
  emit.Until(
      std::nextafter(0.0, -1.0),
      [&](double t) { return FromBody(model, PropagateFlight(touch, model.g_S, t)); },
      ContactPhase::kFlightBefore);
  SetInitialFriction(model, x);

  const double omega_n = std::sqrt(model.k * model.inv_m);
  typename Integrator<N>::ErrorChecker error_checker;
  error_checker.atol = options.absolute_tolerance;
  error_checker.rtol = options.relative_tolerance;
  error_checker.scale = StateScales(model, x, omega_n);
  typename Integrator<N>::Dense stepper(
      typename Integrator<N>::Controlled(error_checker, StepAdjuster()));
  stepper.initialize(x, 0.0, 0.02 / omega_n);
  result.peak_normal_force_N = model.NormalForce(x);

  bool separated = false;
  while (!separated) {
    if (++result.steps > options.max_steps) {
      result.message = TooManySteps(options.max_steps, stepper.current_time(), omega_n);
      return result;
    }
    // By reference: Odeint passes the system by value down its call chain.
    const auto [t0, t1] = stepper.do_step(std::ref(model));
    const State& x1 = stepper.current_state();
    const auto [t_event, phase_event] = EarliestEvent(model, stepper, t0, t1);
    const ContactPhase phase =
        model.compression ? ContactPhase::kCompression : ContactPhase::kRestitution;
    State xs;
    auto dense = [&](double t) {
      stepper.calc_state(t, xs);
      return xs;
    };
    if (!std::isfinite(t_event)) {
      result.peak_normal_force_N = std::max(result.peak_normal_force_N, model.NormalForce(x1));
      emit.Until(t1, dense, phase);
      continue;
    }
    emit.Until(t_event, dense, phase);
    State xe;
    stepper.calc_state(t_event, xe);
    result.peak_normal_force_N = std::max(result.peak_normal_force_N, model.NormalForce(xe));
    separated = HandleEvent(model, xe, t_event, phase_event, result);
    if (separated)
      x = xe;
    else
      stepper.initialize(xe, t_event, std::max(stepper.current_time_step(), 1e-3 / omega_n));
  }
  FinishImpact(model, specimen, x, touch, emit, result);
  return result;
}

/// The instantiations, one per translation unit.
ImpactResult RunBaseline(const SpecimenParameters& specimen, const ContactParameters& contact,
                         const SimulatorOptions& options, const ImpactConditions& conditions,
                         std::span<const double> sample_times_s);
ImpactResult RunExtended(const SpecimenParameters& specimen, const ContactParameters& contact,
                         const SimulatorOptions& options, const ImpactConditions& conditions,
                         std::span<const double> sample_times_s);
ImpactResult RunCompliant(const SpecimenParameters& specimen, const ContactParameters& contact,
                          const SimulatorOptions& options, const ImpactConditions& conditions,
                          std::span<const double> sample_times_s);

}  // namespace hoof::dynamics::internal
