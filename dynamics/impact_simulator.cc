#include "dynamics/impact_simulator.h"

#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "dynamics/impact_run.h"

namespace hoof::dynamics {
namespace {

[[noreturn]] void ThrowField(std::string_view field, double value, std::string_view why) {
  std::ostringstream os;
  os << field << " = " << value << " is invalid: " << why;
  throw std::invalid_argument(os.str());
}

}  // namespace

const char* ToString(ContactPhase phase) {
  switch (phase) {
    case ContactPhase::kFlightBefore:
      return "flight_before";
    case ContactPhase::kCompression:
      return "compression";
    case ContactPhase::kRestitution:
      return "restitution";
    case ContactPhase::kFlightAfter:
      return "flight_after";
  }
  return "?";
}

const char* ToString(FrictionMode mode) {
  switch (mode) {
    case FrictionMode::kNone:
      return "none";
    case FrictionMode::kSlipPositive:
      return "slip+";
    case FrictionMode::kSlipNegative:
      return "slip-";
    case FrictionMode::kStick:
      return "stick";
  }
  return "?";
}

ImpactConditions ImpactConditions::Paper(double speed_m_s, double surface_angle_deg) {
  const auto R_WS = core::SurfaceRotation::FromDegrees(surface_angle_deg);
  ImpactConditions c;
  c.surface_angle_rad = R_WS.phi_rad();
  c.v_SC_m_s = R_WS.ToS({0.0, -speed_m_s});  // dropped: straight down in W
  c.w_rad_s = 0.0;
  c.theta_S_rad = R_WS.AngleToS(0.5 * std::numbers::pi);  // held upright in W
  return c;
}

void ImpactConditions::Validate(const SpecimenParameters& specimen) const {
  if (!std::isfinite(surface_angle_rad) || std::abs(surface_angle_rad) >= 0.5 * std::numbers::pi)
    ThrowField("conditions.surface_angle_rad", surface_angle_rad,
               "must be finite and within (-pi/2, pi/2)");
  if (!v_SC_m_s.allFinite()) ThrowField("conditions.v_SC_m_s", v_SC_m_s.norm(), "must be finite");
  if (!std::isfinite(w_rad_s)) ThrowField("conditions.w_rad_s", w_rad_s, "must be finite");
  if (!std::isfinite(theta_S_rad))
    ThrowField("conditions.theta_S_rad", theta_S_rad, "must be finite");
  // The contact point must approach the surface: v_ST.y = v_SC.y - d cos(q3) w < 0.
  const double v_ST_y = v_SC_m_s.y() - specimen.d_EC_m * std::cos(theta_S_rad) * w_rad_s;
  if (!(v_ST_y < 0.0))
    ThrowField("conditions.v_SC_m_s (normal velocity of T)", v_ST_y,
               "the contact point must move into the surface (v_ST.y < 0)");
}

void SimulatorOptions::Validate() const {
  if (!(relative_tolerance > 0.0 && relative_tolerance <= 1e-3))
    ThrowField("options.relative_tolerance", relative_tolerance, "must be in (0, 1e-3]");
  if (!(absolute_tolerance > 0.0 && std::isfinite(absolute_tolerance)))
    ThrowField("options.absolute_tolerance", absolute_tolerance, "must be > 0");
  if (!(gravity_m_s2 >= 0.0 && std::isfinite(gravity_m_s2)))
    ThrowField("options.gravity_m_s2", gravity_m_s2, "must be finite and >= 0");
  if (max_steps <= 0) ThrowField("options.max_steps", max_steps, "must be > 0");
}

Eigen::Vector2d GravityInSurfaceFrame(double surface_angle_rad, double gravity_m_s2) {
  return core::SurfaceRotation(surface_angle_rad).GravityInS(gravity_m_s2);
}

BodyState PropagateFlight(const BodyState& state, const Eigen::Vector2d& g_S_m_s2, double t_s) {
  BodyState out = state;
  out.p_SC = state.p_SC + state.v_SC * t_s + 0.5 * g_S_m_s2 * t_s * t_s;
  out.v_SC = state.v_SC + g_S_m_s2 * t_s;
  out.theta_S_rad = state.theta_S_rad + state.w_rad_s * t_s;
  return out;
}

double KineticEnergy(const SpecimenParameters& specimen, const BodyState& state) {
  return 0.5 * specimen.mass_kg * state.v_SC.squaredNorm() +
         0.5 * specimen.inertia_kg_m2 * state.w_rad_s * state.w_rad_s;
}

ImpactSimulator::ImpactSimulator(const SpecimenParameters& specimen,
                                 const ContactParameters& contact, const SimulatorOptions& options)
    : specimen_(specimen), contact_(contact), options_(options) {
  specimen_.Validate();
  contact_.Validate();
  options_.Validate();
}

ImpactResult ImpactSimulator::Simulate(const ImpactConditions& conditions,
                                       std::span<const double> sample_times_s) const {
  conditions.Validate(specimen_);
  if (contact_.extensions.tangential_compliance_ratio > 0.0 && contact_.mu > 0.0)
    return internal::RunCompliant(specimen_, contact_, options_, conditions, sample_times_s);
  if (contact_.extensions.Any())
    return internal::RunExtended(specimen_, contact_, options_, conditions, sample_times_s);
  return internal::RunBaseline(specimen_, contact_, options_, conditions, sample_times_s);
}

}  // namespace hoof::dynamics
