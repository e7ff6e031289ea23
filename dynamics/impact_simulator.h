#pragma once
/// @file
/// The planar two-phase impact model of the seed paper (section 2.2), written out in
/// docs/science.md, "The rigid-body model", integrated with Boost.Odeint's dense-output
/// Dormand-Prince 5(4) stepper. Phase changes (maximum compression, separation) and stick/slip
/// switches are located as events on the dense output. Free flight before and after contact is
/// analytic.
///
/// Frames: S is the surface frame (origin at the contact point at first touch, x_S down-slope
/// along the surface, y_S the outward normal). Time 0 is first touch.

#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "dynamics/parameters.h"

namespace hoof::dynamics {

/// Pose and twist of the rigid specimen in the surface frame S.
struct BodyState {
  Eigen::Vector2d p_SC{0.0, 0.0};  ///< Position of the centre of mass C in S (m).
  Eigen::Vector2d v_SC{0.0, 0.0};  ///< Velocity of C in S (m/s).
  double theta_S_rad = 0.0;        ///< q3: angle of x_B from x_S, counter-clockwise (rad).
  double w_rad_s = 0.0;            ///< q3': angular velocity, counter-clockwise (rad/s).
};

/// The state of the body at first touch (t = 0), when the round end touches the surface at the
/// origin of S.
struct ImpactConditions {
  double surface_angle_rad = 0.0;           ///< phi, the surface angle to the horizontal (rad).
  Eigen::Vector2d v_SC_m_s{0.0, -3.0};      ///< Velocity of C in S at first touch (m/s).
  double w_rad_s = 0.0;                     ///< Angular velocity at first touch (rad/s).
  double theta_S_rad = 1.5707963267948966;  ///< q3 at first touch (rad).

  /// The paper's initial conditions (section 2.2.1): a vertical drop at `speed_m_s` onto a
  /// surface at `surface_angle_deg`, long axis vertical, no spin. So q1' = v sin(phi),
  /// q2' = -v cos(phi), q3 = phi + 90 deg, q3' = 0.
  static ImpactConditions Paper(double speed_m_s, double surface_angle_deg);

  /// Throws std::invalid_argument naming the field when a value is not finite, the surface
  /// angle is outside (-90, 90) deg, or the contact point is not approaching the surface.
  void Validate(const SpecimenParameters& specimen) const;
};

/// Integration settings.
struct SimulatorOptions {
  /// Relative error per step; in (0, 1e-3]. Each state's error estimate is held below
  /// absolute_tolerance + relative_tolerance max(|x_i|, s_i), where s_i is the state's scale in
  /// this impact: the normal approach speed V for velocities, V / omega_n for positions, and
  /// these over R + d for the angular velocity and the angle (docs/science.md).
  double relative_tolerance = 1e-8;
  double absolute_tolerance = 1e-15;            ///< Absolute error per step (SI units); > 0.
  double gravity_m_s2 = kStandardGravity_m_s2;  ///< g, in m/s^2; >= 0 (0 turns gravity off).
  int max_steps = 20000;                        ///< Bound on accepted steps during contact; > 0.

  /// Throws std::invalid_argument naming the field.
  void Validate() const;
};

/// Where in the impact a time falls.
enum class ContactPhase { kFlightBefore, kCompression, kRestitution, kFlightAfter };
/// How the contact point T moves along the surface.
enum class FrictionMode {
  kNone,          ///< mu = 0, or not in contact.
  kSlipPositive,  ///< T slides toward +x_S; friction pushes toward -x_S.
  kSlipNegative,  ///< T slides toward -x_S.
  kStick,         ///< T does not slide; |F| <= mu P.
};
const char* ToString(ContactPhase phase);
const char* ToString(FrictionMode mode);

/// A located change of phase or friction mode.
struct ContactEvent {
  double t_s = 0.0;  ///< Time since first touch (s).
  std::string what;  ///< "max_compression", "separation", "stick", "slip+", "slip-".
};

/// The model evaluated at one requested time.
struct TrajectorySample {
  double t_s = 0.0;                ///< Time since first touch (s).
  BodyState body;                  ///< Pose and twist of the body in S.
  Eigen::Vector2d p_SE{0.0, 0.0};  ///< Centre E of the round end in S (m).
  Eigen::Vector2d v_ST{0.0, 0.0};  ///< Velocity of the body point at T in S (m/s).
  double delta_m = 0.0;            ///< q2: penetration, negative inside the surface (m).
  double normal_force_N = 0.0;     ///< P, along y_S (N).
  double friction_force_N = 0.0;   ///< F, along x_S (N).
  double kinetic_energy_J = 0.0;   ///< m |v_SC|^2 / 2 + I_C w^2 / 2 (J).
  /// Gravitational energy (relative to the origin of S) plus the elastic energy k delta^2 / 2
  /// stored in the contact (J). Kinetic plus potential never rises.
  double potential_energy_J = 0.0;
  ContactPhase phase = ContactPhase::kFlightBefore;
  FrictionMode friction = FrictionMode::kNone;
};

/// Everything one impact gives (docs/science.md, "The rigid-body model", for the definitions).
struct ImpactResult {
  bool success = false;  ///< False when the integration failed; see message.
  std::string message;   ///< Why it failed, or empty.

  BodyState at_touch;                     ///< At first touch, t = 0.
  BodyState at_max_compression;           ///< Where delta' = 0.
  BodyState at_separation;                ///< Where delta returns to 0.
  Eigen::Vector2d v_ST_before{0.0, 0.0};  ///< Velocity of the body point at T, at touch.
  Eigen::Vector2d v_ST_after{0.0, 0.0};   ///< Velocity of the body point at T, at separation.

  double t_max_compression_s = 0.0;  ///< Time of maximum compression (s).
  double t_separation_s = 0.0;       ///< Time of separation = contact duration (s).
  double max_penetration_m = 0.0;    ///< |delta| at maximum compression (m).
  double peak_normal_force_N = 0.0;  ///< Largest P seen at step ends and events (N).

  /// e = |v_ST(t_f).y_S / v_ST(t_i).y_S| (paper section 2.2).
  double e = 0.0;
  /// mu_eff = |dv_SC.x_S / dv_SC.y_S| over the contact, an impulse ratio. NaN when the normal
  /// velocity does not change.
  double mu_eff = 0.0;
  double kinetic_energy_before_J = 0.0;
  double kinetic_energy_after_J = 0.0;
  double energy_loss_J = 0.0;  ///< kinetic_energy_before_J - kinetic_energy_after_J.

  std::vector<ContactEvent> events;       ///< Phase and friction changes, in time order.
  int steps = 0;                          ///< Accepted integration steps during contact.
  std::vector<TrajectorySample> samples;  ///< At the requested times, in their order.
};

/// Simulates impacts of one specimen with one contact law. Cheap to copy; thread-safe const.
class ImpactSimulator {
 public:
  /// Validates all three structs; throws std::invalid_argument naming the field.
  ImpactSimulator(const SpecimenParameters& specimen, const ContactParameters& contact,
                  const SimulatorOptions& options = {});

  /// Runs one impact from first touch to separation. `sample_times_s` (any order, any range,
  /// before, during or after contact) are evaluated on the analytic flight or the dense output.
  /// Throws std::invalid_argument for invalid conditions; integration trouble is reported in
  /// ImpactResult::success and message.
  ImpactResult Simulate(const ImpactConditions& conditions,
                        std::span<const double> sample_times_s = {}) const;

  const SpecimenParameters& specimen() const { return specimen_; }
  const ContactParameters& contact() const { return contact_; }
  const SimulatorOptions& options() const { return options_; }

 private:
  SpecimenParameters specimen_;
  ContactParameters contact_;
  SimulatorOptions options_;
};

/// Free flight of a rigid body under gravity g_S for time t from `state` (exact).
BodyState PropagateFlight(const BodyState& state, const Eigen::Vector2d& g_S_m_s2, double t_s);

/// Gravity in S for a surface at angle phi: (g sin(phi), -g cos(phi)).
Eigen::Vector2d GravityInSurfaceFrame(double surface_angle_rad, double gravity_m_s2);

/// Kinetic energy of the specimen (J).
double KineticEnergy(const SpecimenParameters& specimen, const BodyState& state);

}  // namespace hoof::dynamics
