// The effects beyond the paper's model (ContactExtensions; docs/science.md, "Effects the model
// lacks"), tested through ImpactSimulator against closed forms, conservation and their physical
// signatures.
#include "dynamics/equations_of_motion.h"

#include <cmath>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "dynamics/impact_simulator.h"

namespace hoof::dynamics {
namespace {

ImpactResult Impact(Surface surface, double mu, const ContactExtensions& ext, double speed,
                    double phi_deg, double gravity = kStandardGravity_m_s2,
                    std::span<const double> times = {}, double rtol = 1e-10) {
  ContactParameters contact = PaperContact(surface);
  contact.mu = mu;
  contact.extensions = ext;
  SimulatorOptions options;
  options.gravity_m_s2 = gravity;
  options.relative_tolerance = rtol;
  const ImpactSimulator sim(SpecimenParameters{}, contact, options);
  return sim.Simulate(ImpactConditions::Paper(speed, phi_deg), times);
}

std::vector<double> ContactTimes(double T, int n) {
  std::vector<double> t;
  for (int i = 0; i <= n; ++i) t.push_back(-1e-5 + (T + 2e-5) * i / n);
  return t;
}

/// Total energy (kinetic, gravity, contact springs) never rises along the trajectory, sampled
/// every ~10 ns through the dense output. Integrated at rtol 1e-12: the sampled energy then
/// rises by at most 5e-12 of itself in the Hertz case, far below the 1e-9 allowed. (At rtol
/// 1e-10 it rises by 2.5e-9 just before separation, from the interpolation error within the
/// last step, which is 25 rtol with the scaled error norm.)
void ExpectEnergyNeverRises(Surface surface, double mu, const ContactExtensions& ext, double speed,
                            double phi, const std::string& label) {
  constexpr double kRtol = 1e-12;
  const ImpactResult first = Impact(surface, mu, ext, speed, phi, kStandardGravity_m_s2, {}, kRtol);
  ASSERT_TRUE(first.success) << label << ": " << first.message;
  const auto times = ContactTimes(first.t_separation_s, 3000);
  const ImpactResult r = Impact(surface, mu, ext, speed, phi, kStandardGravity_m_s2, times, kRtol);
  const double e0 = r.samples.front().kinetic_energy_J + r.samples.front().potential_energy_J;
  double previous = e0;
  for (const auto& s : r.samples) {
    const double total = s.kinetic_energy_J + s.potential_energy_J;
    ASSERT_LE(total, previous + 1e-9 * e0) << label << " at t = " << s.t_s;
    previous = total;
  }
}

void ExpectSameImpact(const ImpactResult& a, const ImpactResult& b, double tol,
                      const std::string& label) {
  EXPECT_NEAR((a.at_separation.v_SC - b.at_separation.v_SC).norm(), 0.0,
              tol * b.at_separation.v_SC.norm())
      << label;
  EXPECT_NEAR(a.at_separation.w_rad_s, b.at_separation.w_rad_s,
              tol * std::max(1.0, std::abs(b.at_separation.w_rad_s)))
      << label;
}

TEST(ContactExtensionsTest, EachEffectTendsToTheBaselineAsItsParameterGoesToZero) {
  const ImpactResult base = Impact(Surface::kConcrete, 0.3, {}, 3.0, 10.0);
  ContactExtensions e;
  e.hunt_crossley_N_s_m2 = 1e-3;
  ExpectSameImpact(Impact(Surface::kConcrete, 0.3, e, 3.0, 10.0), base, 1e-8, "hunt-crossley");
  e = {};
  e.stiffness_exponent_extra = 1e-9;
  ExpectSameImpact(Impact(Surface::kConcrete, 0.3, e, 3.0, 10.0), base, 1e-7, "stiffness exponent");
  e = {};
  e.unloading_stiffness_ratio = 1e-9;
  ExpectSameImpact(Impact(Surface::kConcrete, 0.3, e, 3.0, 10.0), base, 1e-7, "unloading");
  e = {};
  e.static_friction_excess = 1e-9;
  ExpectSameImpact(Impact(Surface::kConcrete, 0.3, e, 3.0, 10.0), base, 1e-7, "static friction");
  e = {};
  e.rolling_resistance_m = 1e-12;
  ExpectSameImpact(Impact(Surface::kConcrete, 0.3, e, 3.0, 10.0), base, 1e-7, "rolling");
  e = {};
  e.tangential_compliance_ratio = 1e-3;  // a very stiff tangential spring is rigid stick
  ExpectSameImpact(Impact(Surface::kConcrete, 0.3, e, 3.0, 10.0), base, 2e-3, "compliance");
}

TEST(ContactExtensionsTest, HertzianContactMatchesItsClosedForm) {
  // Undamped, frictionless, no gravity: m delta'' = -K delta^(3/2), K = k / sqrt(delta_ref).
  // Energy gives delta_m = (5 m v^2 / (4 K))^(2/5) and contact time
  // T = 2 delta_m / v * integral_0^1 (1 - x^(5/2))^(-1/2) dx = 2 delta_m / v * (2/5) B(2/5, 1/2).
  ContactExtensions e;
  e.stiffness_exponent_extra = 0.5;
  e.stiffness_reference_depth_m = 1e-5;
  ContactParameters contact(4.24e8, 0.0, 0.0);
  contact.extensions = e;
  SimulatorOptions options;
  options.gravity_m_s2 = 0.0;
  options.relative_tolerance = 1e-10;
  const ImpactSimulator sim(SpecimenParameters{}, contact, options);
  for (double v : {1.5, 3.0, 4.0}) {
    const ImpactResult r = sim.Simulate(ImpactConditions::Paper(v, 0.0));
    ASSERT_TRUE(r.success);
    const double K = 4.24e8 / std::sqrt(1e-5);
    const double delta_m = std::pow(5 * 0.008 * v * v / (4 * K), 0.4);
    const double T = 2 * delta_m / v * 0.4 * std::beta(0.4, 0.5);
    EXPECT_NEAR(r.e, 1.0, 1e-7) << v;
    EXPECT_NEAR(r.max_penetration_m, delta_m, 1e-7 * delta_m) << v;
    EXPECT_NEAR(r.t_separation_s, T, 1e-7 * T) << v;
  }
}

TEST(ContactExtensionsTest, PlasticUnloadingLowersRestitutionBySqrtOfOnePlusR) {
  // Linear law, no gravity, normal: restitution returns k delta_m^2 / (2 (1 + r)) of the
  // k delta_m^2 / 2 stored at maximum compression, so e = e(zeta) / sqrt(1 + r), and the body
  // leaves an indentation delta_p = delta_m r / (1 + r).
  for (double r_unload : {0.2, 1.0, 3.0}) {
    ContactExtensions e;
    e.unloading_stiffness_ratio = r_unload;
    const ImpactResult r = Impact(Surface::kSteel, 0.0, e, 3.0, 0.0, 0.0);
    ASSERT_TRUE(r.success);
    const double zeta = DampingRatio(7.24e8, 531.65, 0.008);
    EXPECT_NEAR(r.e, RestitutionFromDampingRatio(zeta) / std::sqrt(1 + r_unload), 1e-7);
    const double delta_sep = r.at_separation.p_SC.y() - 0.009 - 0.0135;  // C above T
    EXPECT_NEAR(delta_sep, -r.max_penetration_m * r_unload / (1 + r_unload), 1e-12);
  }
}

TEST(ContactExtensionsTest, HuntCrossleyDampingMakesRestitutionFallWithSpeed) {
  // The baseline e does not depend on v; with damping ~ |delta| it falls as v rises.
  ContactExtensions e;
  e.hunt_crossley_N_s_m2 = 3e7;
  double previous = 1.0;
  for (double v : {1.5, 2.5, 4.0}) {
    const double e_hc = Impact(Surface::kConcrete, 0.0, e, v, 0.0, 0.0).e;
    const double e_base = Impact(Surface::kConcrete, 0.0, {}, v, 0.0, 0.0).e;
    EXPECT_LT(e_hc, e_base);
    EXPECT_LT(e_hc, previous - 0.005) << "v " << v;
    previous = e_hc;
  }
}

TEST(ContactExtensionsTest, StaticFrictionHoldsStickUntilTheStaticLimit) {
  // Steel, 5 deg, mu = 0.35 sticks early and slips just before separation. The switch to slip
  // happens exactly where |F| reaches (mu + excess) P, and afterwards F = mu P (kinetic).
  ContactExtensions e;
  e.static_friction_excess = 0.15;
  const ImpactResult r = Impact(Surface::kSteel, 0.35, e, 3.0, 5.0);
  ASSERT_TRUE(r.success);
  double t_slip = -1.0;
  for (const auto& ev : r.events)
    if (ev.what == "slip+" || ev.what == "slip-") t_slip = ev.t_s;
  ASSERT_GT(t_slip, 0.0);
  // The slip starts nanoseconds before separation, where P is small and F / P changes by
  // about 2e-4 per 1e-16 s, the event's time resolution.
  const std::vector<double> t = {t_slip - 1e-16, t_slip + 1e-16};
  const ImpactResult s = Impact(Surface::kSteel, 0.35, e, 3.0, 5.0, kStandardGravity_m_s2, t);
  EXPECT_NEAR(std::abs(s.samples[0].friction_force_N) / s.samples[0].normal_force_N, 0.50, 1e-3);
  EXPECT_NEAR(std::abs(s.samples[1].friction_force_N) / s.samples[1].normal_force_N, 0.35, 1e-9);
  // Higher static friction keeps the contact stuck longer.
  const ImpactResult base = Impact(Surface::kSteel, 0.35, {}, 3.0, 5.0);
  double t_slip_base = -1.0;
  for (const auto& ev : base.events)
    if (ev.what == "slip+" || ev.what == "slip-") t_slip_base = ev.t_s;
  EXPECT_GT(t_slip, t_slip_base);
}

TEST(ContactExtensionsTest, TangentialComplianceLetsTheContactPointVelocityReverse) {
  // Maw-Barber-Fawcett: with a tangential spring, T's tangential velocity changes sign during
  // a low-angle impact; rigid stick never lets it reverse.
  ContactExtensions e;
  e.tangential_compliance_ratio = 1.2;
  const ImpactResult first = Impact(Surface::kSteel, 0.5, e, 3.0, 3.0);
  ASSERT_TRUE(first.success) << first.message;
  const auto times = ContactTimes(first.t_separation_s, 2000);
  const ImpactResult r = Impact(Surface::kSteel, 0.5, e, 3.0, 3.0, kStandardGravity_m_s2, times);
  double v_min = 1e9, v_max = -1e9;
  for (const auto& s : r.samples) {
    if (s.phase != ContactPhase::kCompression && s.phase != ContactPhase::kRestitution) continue;
    v_min = std::min(v_min, s.v_ST.x());
    v_max = std::max(v_max, s.v_ST.x());
  }
  EXPECT_LT(v_min, -0.01);
  EXPECT_GT(v_max, 0.01);
  EXPECT_LT(first.steps, 500);
}

TEST(ContactExtensionsTest, RollingResistanceTakesSpinNotSpeed) {
  const ImpactResult base = Impact(Surface::kSteel, 0.12, {}, 3.28, 20.0);
  double previous_w = base.at_separation.w_rad_s;
  for (double rho : {2e-4, 6e-4}) {
    ContactExtensions e;
    e.rolling_resistance_m = rho;
    const ImpactResult r = Impact(Surface::kSteel, 0.12, e, 3.28, 20.0);
    ASSERT_TRUE(r.success);
    const double dw =
        (base.at_separation.w_rad_s - r.at_separation.w_rad_s) / base.at_separation.w_rad_s;
    EXPECT_LT(r.at_separation.w_rad_s, previous_w) << rho;
    const double dv =
        (r.at_separation.v_SC - base.at_separation.v_SC).norm() / base.at_separation.v_SC.norm();
    EXPECT_GT(dw, 0.02) << rho;      // spin drops by several percent
    EXPECT_LT(dv, dw / 5.0) << rho;  // the velocity of C changes far less
    previous_w = r.at_separation.w_rad_s;
  }
}

// ImpactSimulator runs the paper's model on equations with the extensions compiled out
// (Model<6, false>) and any effect on the general ones (Model<6, true>). With an effect that
// cannot act (static friction above kinetic, in a contact that slides throughout) the general
// equations must give the baseline's impact to round-off.
TEST(ContactExtensionsTest, GeneralEquationsWithNoEffectActingGiveTheBaseline) {
  for (const auto& [surface, mu, phi] :
       {std::tuple{Surface::kSteel, 0.19, 30.0}, std::tuple{Surface::kAsphalt, 0.3, 30.0},
        std::tuple{Surface::kConcrete, 0.0, 0.0}}) {
    const ImpactResult base = Impact(surface, mu, {}, 3.0, phi);
    ContactExtensions e;
    e.static_friction_excess = 0.2;
    ASSERT_TRUE(e.Any());
    const ImpactResult general = Impact(surface, mu, e, 3.0, phi);
    const std::string label = SurfaceName(surface);
    ASSERT_TRUE(base.success && general.success) << label;
    ASSERT_EQ(general.events.size(), base.events.size()) << label << ": it must not stick";
    ExpectSameImpact(general, base, 1e-13, label);
    EXPECT_NEAR(general.t_separation_s, base.t_separation_s, 1e-13 * base.t_separation_s) << label;
    EXPECT_EQ(general.steps, base.steps) << label;
  }
}

TEST(ContactExtensionsTest, EnergyNeverRisesWithAnyEffect) {
  ContactExtensions e;
  e.hunt_crossley_N_s_m2 = 3e7;
  ExpectEnergyNeverRises(Surface::kConcrete, 0.3, e, 3.0, 20, "hunt-crossley");
  e = {};
  e.stiffness_exponent_extra = 0.5;
  ExpectEnergyNeverRises(Surface::kAsphalt, 0.3, e, 3.0, 10, "hertz");
  e = {};
  e.unloading_stiffness_ratio = 0.5;
  ExpectEnergyNeverRises(Surface::kSteel, 0.2, e, 3.0, 20, "plastic");
  e = {};
  e.static_friction_excess = 0.2;
  ExpectEnergyNeverRises(Surface::kSteel, 0.35, e, 3.0, 5, "static friction");
  e = {};
  e.tangential_compliance_ratio = 1.2;
  ExpectEnergyNeverRises(Surface::kSteel, 0.5, e, 3.0, 3, "compliance");
  e = {};
  e.rolling_resistance_m = 5e-4;
  ExpectEnergyNeverRises(Surface::kSteel, 0.12, e, 3.28, 20, "rolling");
  e = {};
  e.stiffness_exponent_extra = 0.5;
  e.unloading_stiffness_ratio = 0.3;
  e.hunt_crossley_N_s_m2 = 1e7;
  e.tangential_compliance_ratio = 0.8;
  e.static_friction_excess = 0.1;
  ExpectEnergyNeverRises(Surface::kConcrete, 0.3, e, 2.5, 10, "all together");
}

TEST(ContactExtensionsTest, InvalidMagnitudesNameTheField) {
  ContactParameters c;
  c.extensions.stiffness_exponent_extra = 2.0;
  try {
    c.Validate();
    FAIL();
  } catch (const std::invalid_argument& err) {
    EXPECT_NE(std::string(err.what()).find("stiffness_exponent_extra"), std::string::npos);
  }
  c.extensions = {};
  c.extensions.rolling_resistance_m = -1e-3;
  EXPECT_THROW(c.Validate(), std::invalid_argument);
}

}  // namespace
}  // namespace hoof::dynamics
