#pragma once
/// @file
/// Specimen and contact parameters of the planar impact model (docs/science.md, "The rigid-body
/// model" and "Specimen defaults").
/// Plain option structs with documented SI units, paper defaults and Validate().

#include <string>
#include <string_view>
#include <vector>

#include "core/frames.h"
#include "core/specimen.h"

namespace hoof::dynamics {

/// Standard gravity used by the paper (m/s^2).
inline constexpr double kStandardGravity_m_s2 = core::kStandardGravity_m_s2;

/// The rigid specimen: the one type the whole project shares (src/core/specimen.h).
using SpecimenParameters = core::SpecimenParameters;

/// The impact surfaces of the study.
enum class Surface { kSteel, kConcrete, kAsphalt };

/// Parses "steel", "concrete" or "asphalt" (case-insensitive). Throws std::invalid_argument
/// naming the value otherwise.
Surface ParseSurface(std::string_view name);
/// Lower-case name of a surface.
std::string SurfaceName(Surface surface);

/// Physical effects the paper's model lacks (docs/science.md, "Effects the model lacks"). Each is a
/// nested extension with one parameter whose default 0 gives back the baseline exactly. The
/// renderer hides them in synthetic trials; the discovery workflow names them.
struct ContactExtensions {
  /// Hunt-Crossley (velocity-dependent) damping in compression: P gains -c |delta| delta'
  /// (c in N s/m^2; >= 0). Dissipation grows with impact speed, so e falls as v rises.
  double hunt_crossley_N_s_m2 = 0.0;
  /// Nonlinear stiffness: the elastic term becomes k |delta| (|delta| / delta_ref)^p in both
  /// phases (p >= 0, at most 1; p = 0.5 is Hertzian contact). Dimensionless.
  double stiffness_exponent_extra = 0.0;
  /// delta_ref of the nonlinear stiffness (m; > 0): k keeps its meaning at this depth.
  double stiffness_reference_depth_m = 1e-5;
  /// Dissipative (plastic) restitution: unloading is stiffer, k_u = k (1 + r) (r >= 0), along
  /// P = k_u (delta_p - delta) with delta_p set so P is continuous at maximum compression. The
  /// body separates where P reaches 0, leaving an indentation delta_p.
  double unloading_stiffness_ratio = 0.0;
  /// Static friction above kinetic: stick holds while |F| <= (mu + this) P (>= 0).
  double static_friction_excess = 0.0;
  /// Tangential contact compliance (Maw-Barber-Fawcett): a tangential spring k_t = k / c at T
  /// in place of rigid stick (c >= 0; 0 is rigid). T's tangential velocity can reverse.
  double tangential_compliance_ratio = 0.0;
  /// Rolling resistance: a contact torque -rho P w / (|w| + 1 rad/s) about T (rho in m; >= 0).
  /// Less spin after impact, v_C nearly unchanged.
  double rolling_resistance_m = 0.0;
  /// Speed-dependent (velocity-strengthening) kinetic friction: while T slides, the friction
  /// magnitude is mu (1 + s |v_T.x_S|) P (s in s/m; >= 0). Stick and the static cone are
  /// unchanged: at zero slip speed the limit is mu P (plus static_friction_excess), so the
  /// slip-to-stick switch at v_T.x_S = 0 is the baseline's. mu_eff rises with the sliding
  /// speed. Needs rigid stick: not combinable with tangential_compliance_ratio > 0.
  /// Deliberately NOT in the discovery library: it stands for an effect nobody listed, so
  /// discovery must report it as unexplained disagreement rather than name it.
  double friction_speed_slope_s_m = 0.0;

  /// True when any effect is switched on.
  bool Any() const;
  /// Throws std::invalid_argument naming the field.
  void Validate() const;
};

/// One field of ContactExtensions, as every part of the program names, bounds and describes it.
/// ContactExtensionFields() is the one list of them: the command-line options, the hidden
/// effects of trial.json and study.json, the JSON the commands print, the validation and the
/// discovery library's effects are all made from it, so a new extension is one row here (and
/// its physics in the simulator).
struct ContactExtensionField {
  const char* key;  ///< name in JSON files and output, e.g. "rolling_resistance_m"
  double ContactExtensions::*member;  ///< the field
  const char* flag;                   ///< command-line option, e.g. "--rolling-resistance-m"
  const char* help;                   ///< for --help: the law, the unit and the option's range
  /// The model's valid range: Validate() refuses a value outside it.
  double valid_lower, valid_upper;
  bool lower_open;  ///< the lower bound itself is refused (> rather than >=)
  /// The command line's range: far beyond what a hoof, a ball or a specimen shows and inside
  /// what the integrator finishes; a value outside is a command-line error.
  double option_lower, option_upper;
  bool effect;  ///< non-zero switches an effect on (false for a shape parameter of one)
};
const std::vector<ContactExtensionField>& ContactExtensionFields();
/// The field named `key`, or nullptr.
const ContactExtensionField* FindContactExtension(std::string_view key);

/// Two-phase contact law (paper eqs. 1-2) and Coulomb friction.
/// Compression: P = -k delta - b delta'. Restitution: P = -k delta. P >= 0 always.
/// Friction: |F| <= mu P, with stick while the contact point T does not slide.
struct ContactParameters {
  ContactParameters() = default;
  /// The baseline law with stiffness k (N/m), damping b (N s/m) and friction mu.
  ContactParameters(double k, double b, double friction) : k_N_m(k), b_N_s_m(b), mu(friction) {}

  double k_N_m = 7.24e8;         ///< k, normal stiffness in N/m; > 0.
  double b_N_s_m = 531.65;       ///< b, normal damping in compression, in N s/m; >= 0.
  double mu = 0.19;              ///< Coulomb (kinetic = static) friction coefficient; >= 0.
  ContactExtensions extensions;  ///< Effects beyond the paper's model; all off by default.

  /// Throws std::invalid_argument naming the first invalid field and its value.
  void Validate() const;
};

/// The paper's contact coefficients for a surface (paper section 3.3): k and b fitted to
/// normal impacts. Friction mu is the paper's mean measured mu_eff at 30 deg (0.19, 0.30,
/// 0.34), where the contact point slides for the whole contact, so mu_eff equals mu.
ContactParameters PaperContact(Surface surface);

/// Damping ratio zeta = b / (2 sqrt(k m)) of the compression phase (docs/science.md, "Specimen
/// defaults").
double DampingRatio(double k_N_m, double b_N_s_m, double mass_kg);

/// Damping b (N s/m) that gives damping ratio zeta for stiffness k and mass m.
double DampingForRatio(double zeta, double k_N_m, double mass_kg);

/// Closed-form coefficient of restitution of the two-phase law for a normal impact without
/// gravity: e = exp(-zeta / sqrt(1 - zeta^2) * atan(sqrt(1 - zeta^2) / zeta)).
/// It depends on zeta alone (docs/science.md, "What velocities can and cannot tell"). Valid
/// for 0 <= zeta < 1; throws std::invalid_argument naming "zeta" otherwise. e(0) = 1.
double RestitutionFromDampingRatio(double zeta);

/// Coefficient of restitution of the two-phase law for a normal impact without gravity, for
/// any zeta >= 0: underdamped (the closed form above), critically damped (e = exp(-1)) and
/// overdamped, where compression ends at t_m = ln((zeta+q)/(zeta-q)) / (2 q wn), q =
/// sqrt(zeta^2 - 1), and the elastic restitution returns e = wn |delta_m| / v =
/// (r^(-(zeta-q)/(2q)) - r^(-(zeta+q)/(2q))) / (2q) with r = (zeta+q)/(zeta-q). e falls
/// monotonically from 1 to 0 (about 1 / (2 zeta) for large zeta). Throws naming "zeta" for a
/// negative or non-finite value.
double RestitutionOfTwoPhaseLaw(double zeta);

/// Inverse of RestitutionOfTwoPhaseLaw for 0 < e <= 1: the zeta >= 0 that gives e (zeta > 1
/// for e < exp(-1) = 0.368). Throws std::invalid_argument naming "e" outside (0, 1].
double DampingRatioFromRestitution(double e);

}  // namespace hoof::dynamics
