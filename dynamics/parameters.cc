#include "dynamics/parameters.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <boost/math/tools/roots.hpp>

namespace hoof::dynamics {
namespace {

[[noreturn]] void ThrowField(std::string_view owner, std::string_view field, double value,
                             std::string_view requirement) {
  std::ostringstream os;
  os << owner << "." << field << " = " << value << " is invalid: " << requirement;
  throw std::invalid_argument(os.str());
}

void RequireFinite(std::string_view owner, std::string_view field, double value) {
  if (!std::isfinite(value)) ThrowField(owner, field, value, "must be a finite number");
}

}  // namespace

const std::vector<ContactExtensionField>& ContactExtensionFields() {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  using X = ContactExtensions;
  static const std::vector<ContactExtensionField> fields = {
      {"hunt_crossley_N_s_m2", &X::hunt_crossley_N_s_m2, "--hunt-crossley-n-s-m2",
       "Hunt-Crossley damping c: P gains -c |delta| delta' in compression (N s/m^2; 0 to 1e11)",
       0.0, kInf, false, 0.0, 1e11, true},
      {"stiffness_exponent_extra", &X::stiffness_exponent_extra, "--stiffness-exponent-extra",
       "p in k |delta| (|delta|/delta_ref)^p; 0.5 is Hertzian (0 to 1)", 0.0, 1.0, false, 0.0, 1.0,
       true},
      {"stiffness_reference_depth_m", &X::stiffness_reference_depth_m,
       "--stiffness-reference-depth-m", "delta_ref of the nonlinear stiffness (m; 1e-9 to 10)", 0.0,
       kInf, true, 1e-9, 10.0, false},
      {"unloading_stiffness_ratio", &X::unloading_stiffness_ratio, "--unloading-stiffness-ratio",
       "r: plastic unloading with stiffness k (1 + r) (0 to 1e6)", 0.0, kInf, false, 0.0, 1e6,
       true},
      {"static_friction_excess", &X::static_friction_excess, "--static-friction-excess",
       "mu_static - mu: stick holds up to (mu + this) P (0 to 100)", 0.0, kInf, false, 0.0, 100.0,
       true},
      {"tangential_compliance_ratio", &X::tangential_compliance_ratio,
       "--tangential-compliance-ratio",
       "k / k_t of a tangential spring at T (0 = rigid stick; up to 100)", 0.0, kInf, false, 0.0,
       100.0, true},
      {"rolling_resistance_m", &X::rolling_resistance_m, "--rolling-resistance-m",
       "rho: rolling-resistance torque -rho P w / (|w| + 1 rad/s) (m; 0 to 1)", 0.0, kInf, false,
       0.0, 1.0, true},
      {"friction_speed_slope_s_m", &X::friction_speed_slope_s_m, "--friction-speed-slope-s-m",
       "s: sliding friction mu (1 + s |v_T|) P (s/m; 0 to 100); not in the discovery library", 0.0,
       kInf, false, 0.0, 100.0, true},
  };
  return fields;
}

const ContactExtensionField* FindContactExtension(std::string_view key) {
  for (const auto& f : ContactExtensionFields())
    if (key == f.key) return &f;
  return nullptr;
}

bool ContactExtensions::Any() const {
  for (const auto& f : ContactExtensionFields())
    if (f.effect && this->*f.member != 0) return true;
  return false;
}

void ContactExtensions::Validate() const {
  constexpr std::string_view kOwner = "contact.extensions";
  for (const auto& f : ContactExtensionFields()) RequireFinite(kOwner, f.key, this->*f.member);
  for (const auto& f : ContactExtensionFields()) {
    const double v = this->*f.member;
    if (!(v < f.valid_lower || (f.lower_open && v == f.valid_lower) || v > f.valid_upper)) continue;
    // Worded only on failure: discovery makes (and so validates) a simulator for every
    // simulation, and formatting the requirement each time took 3 us of its 7.6 us
    // (BM_ObliqueImpactMadeEachTime in bench/dynamics_bench.cc).
    std::ostringstream need;
    if (std::isfinite(f.valid_upper))
      need << "must be in [" << f.valid_lower << ", " << f.valid_upper << "]";
    else
      need << "must be " << (f.lower_open ? "> " : ">= ") << f.valid_lower;
    ThrowField(kOwner, f.key, v, need.str());
  }
  // With a tangential spring the slider, not the body point T, slides, and its speed would
  // need a state of its own; the speed-dependent law is defined for rigid stick only.
  if (friction_speed_slope_s_m > 0 && tangential_compliance_ratio > 0)
    ThrowField(kOwner, "friction_speed_slope_s_m", friction_speed_slope_s_m,
               "must be 0 when tangential_compliance_ratio > 0 (needs rigid stick)");
}

void ContactParameters::Validate() const {
  constexpr std::string_view kOwner = "contact";
  RequireFinite(kOwner, "k_N_m", k_N_m);
  RequireFinite(kOwner, "b_N_s_m", b_N_s_m);
  RequireFinite(kOwner, "mu", mu);
  if (k_N_m <= 0) ThrowField(kOwner, "k_N_m", k_N_m, "must be > 0");
  if (b_N_s_m < 0) ThrowField(kOwner, "b_N_s_m", b_N_s_m, "must be >= 0");
  if (mu < 0) ThrowField(kOwner, "mu", mu, "must be >= 0");
  extensions.Validate();
}

Surface ParseSurface(std::string_view name) {
  std::string lower(name);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (lower == "steel") return Surface::kSteel;
  if (lower == "concrete") return Surface::kConcrete;
  if (lower == "asphalt") return Surface::kAsphalt;
  throw std::invalid_argument("surface = \"" + std::string(name) +
                              "\" is invalid: expected steel, concrete or asphalt");
}

std::string SurfaceName(Surface surface) {
  switch (surface) {
    case Surface::kSteel:
      return "steel";
    case Surface::kConcrete:
      return "concrete";
    case Surface::kAsphalt:
      return "asphalt";
  }
  return "unknown";
}

ContactParameters PaperContact(Surface surface) {
  switch (surface) {
    case Surface::kSteel:
      return {7.24e8, 531.65, 0.19};
    case Surface::kConcrete:
      return {4.24e8, 932.20, 0.30};
    case Surface::kAsphalt:
      return {5.86e7, 822.78, 0.34};
  }
  return {};
}

double DampingRatio(double k_N_m, double b_N_s_m, double mass_kg) {
  return b_N_s_m / (2.0 * std::sqrt(k_N_m * mass_kg));
}

double DampingForRatio(double zeta, double k_N_m, double mass_kg) {
  return 2.0 * zeta * std::sqrt(k_N_m * mass_kg);
}

double RestitutionFromDampingRatio(double zeta) {
  if (!(zeta >= 0.0 && zeta < 1.0)) {
    std::ostringstream os;
    os << "zeta = " << zeta << " is invalid: the closed-form e(zeta) needs 0 <= zeta < 1";
    throw std::invalid_argument(os.str());
  }
  if (zeta == 0.0) return 1.0;
  const double root = std::sqrt(1.0 - zeta * zeta);
  return std::exp(-zeta / root * std::atan(root / zeta));
}

double RestitutionOfTwoPhaseLaw(double zeta) {
  if (!(zeta >= 0.0 && std::isfinite(zeta))) {
    std::ostringstream os;
    os << "zeta = " << zeta << " is invalid: needs a finite zeta >= 0";
    throw std::invalid_argument(os.str());
  }
  if (zeta < 1.0) return RestitutionFromDampingRatio(zeta);
  if (zeta == 1.0) return std::exp(-1.0);
  const double q = std::sqrt((zeta - 1.0) * (zeta + 1.0));
  const double log_r = std::log((zeta + q) / (zeta - q));
  return (std::exp(-(zeta - q) / (2 * q) * log_r) - std::exp(-(zeta + q) / (2 * q) * log_r)) /
         (2 * q);
}

double DampingRatioFromRestitution(double e) {
  if (!(e > 0.0 && e <= 1.0)) {
    std::ostringstream os;
    os << "e = " << e << " is invalid: needs 0 < e <= 1";
    throw std::invalid_argument(os.str());
  }
  if (e == 1.0) return 0.0;
  // e(zeta) falls monotonically from 1 at zeta = 0 toward 0; e ~ 1 / (2 zeta) for large zeta.
  auto f = [e](double z) { return RestitutionOfTwoPhaseLaw(z) - e; };
  const double hi = std::max(2.0, 2.0 / e);
  boost::math::tools::eps_tolerance<double> tol(50);
  std::uintmax_t max_iter = 200;
  const auto [lo_z, hi_z] =
      boost::math::tools::toms748_solve(f, 0.0, hi, 1.0 - e, f(hi), tol, max_iter);
  return 0.5 * (lo_z + hi_z);
}

}  // namespace hoof::dynamics
