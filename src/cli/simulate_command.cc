// hoofimpact simulate: one impact of the two-phase model, as JSON, text and a trajectory CSV.
#include <cmath>
#include <iomanip>
#include <iostream>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/json_output.h"
#include "core/frames.h"
#include "dynamics/impact_simulator.h"
#include "format/number_format.h"
#include "io/atomic_file.h"
#include "io/csv.h"

namespace hoof::cli {
namespace {

using dynamics::ImpactResult;
using dynamics::TrajectorySample;

struct SimulateArgs {
  std::string surface = "steel";
  std::optional<double> k_N_m, b_N_s_m, zeta, mu;
  double angle_deg = 0.0;
  double speed_m_s = 3.0;
  dynamics::SpecimenParameters specimen;
  dynamics::ContactExtensions extensions;
  dynamics::SimulatorOptions sim;
  bool json = false;
  std::string trajectory_path;
  double fps = 8000.0;
  int frames_before = 30;
  int frames_after = 30;
  double touch_fraction = 0.5;
  int contact_samples = 0;
};

/// Frame times around the impact, touch at t = 0 between frames, plus optional samples
/// spread through the contact.
std::vector<double> SampleTimes(const SimulateArgs& a, double contact_s) {
  if (!(a.fps > 0)) throw std::invalid_argument("--fps must be > 0");
  if (a.frames_before < 0 || a.frames_after < 0)
    throw std::invalid_argument("--frames-before and --frames-after must be >= 0");
  if (!(a.touch_fraction >= 0 && a.touch_fraction < 1))
    throw std::invalid_argument("--touch-fraction must be in [0, 1)");
  std::vector<double> t;
  for (int i = -a.frames_before; i < a.frames_after; ++i)
    t.push_back((i + a.touch_fraction) / a.fps);
  for (int i = 0; i < a.contact_samples; ++i)
    t.push_back(contact_s * (i + 0.5) / a.contact_samples);
  std::sort(t.begin(), t.end());
  return t;
}

void WriteTrajectory(const std::string& path, const std::vector<TrajectorySample>& samples,
                     double phi) {
  // World frame W: origin at the first-touch contact point, x right, y up.
  const core::SurfaceRotation R_WS(phi);
  io::WriteFileAtomically(path, [&](std::ostream& out) {
    out << "t_s,phase,friction,p_SC_x_m,p_SC_y_m,theta_S_rad,v_SC_x_m_s,v_SC_y_m_s,w_rad_s,"
           "p_SE_x_m,p_SE_y_m,v_ST_x_m_s,v_ST_y_m_s,delta_m,normal_force_N,friction_force_N,"
           "kinetic_energy_J,potential_energy_J,p_WC_x_m,p_WC_y_m,theta_W_rad\n";
    for (const auto& p : samples) {
      const Eigen::Vector2d& q = p.body.p_SC;
      const Eigen::Vector2d p_WC = R_WS.ToW(q);
      const double values[] = {p.t_s,
                               q.x(),
                               q.y(),
                               p.body.theta_S_rad,
                               p.body.v_SC.x(),
                               p.body.v_SC.y(),
                               p.body.w_rad_s,
                               p.p_SE.x(),
                               p.p_SE.y(),
                               p.v_ST.x(),
                               p.v_ST.y(),
                               p.delta_m,
                               p.normal_force_N,
                               p.friction_force_N,
                               p.kinetic_energy_J,
                               p.potential_energy_J,
                               p_WC.x(),
                               p_WC.y(),
                               R_WS.AngleToW(p.body.theta_S_rad)};
      out << io::CsvNumber(values[0]) << "," << dynamics::ToString(p.phase) << ","
          << dynamics::ToString(p.friction);
      for (std::size_t i = 1; i < std::size(values); ++i) out << "," << io::CsvNumber(values[i]);
      out << "\n";
    }
  });
}

nlohmann::json ResultJson(const SimulateArgs& a, const dynamics::ContactParameters& contact,
                          const ImpactResult& r) {
  nlohmann::json events = nlohmann::json::array();
  for (const auto& e : r.events) events.push_back({{"t_s", e.t_s}, {"what", e.what}});
  return {
      {"surface", a.surface},
      {"angle_deg", a.angle_deg},
      {"speed_m_s", a.speed_m_s},
      {"specimen",
       {{"mass_kg", a.specimen.mass_kg},
        {"inertia_kg_m2", a.specimen.inertia_kg_m2},
        {"end_radius_m", a.specimen.end_radius_m},
        {"d_EC_m", a.specimen.d_EC_m}}},
      {"contact",
       {{"k_N_m", contact.k_N_m},
        {"b_N_s_m", contact.b_N_s_m},
        {"mu", contact.mu},
        {"zeta", dynamics::DampingRatio(contact.k_N_m, contact.b_N_s_m, a.specimen.mass_kg)},
        {"extensions", ExtensionsJson(contact.extensions)}}},
      {"gravity_m_s2", a.sim.gravity_m_s2},
      {"v_SC_before_m_s", JsonVector(r.at_touch.v_SC)},
      {"v_SC_after_m_s", JsonVector(r.at_separation.v_SC)},
      {"v_ST_before_m_s", JsonVector(r.v_ST_before)},
      {"v_ST_after_m_s", JsonVector(r.v_ST_after)},
      {"w_before_rad_s", r.at_touch.w_rad_s},
      {"w_after_rad_s", r.at_separation.w_rad_s},
      {"e", r.e},
      {"mu_eff", JsonNumber(r.mu_eff)},
      {"kinetic_energy_before_J", r.kinetic_energy_before_J},
      {"kinetic_energy_after_J", r.kinetic_energy_after_J},
      {"energy_loss_J", r.energy_loss_J},
      {"contact_duration_s", r.t_separation_s},
      {"t_max_compression_s", r.t_max_compression_s},
      {"max_penetration_m", r.max_penetration_m},
      {"peak_normal_force_N", r.peak_normal_force_N},
      {"events", events},
      {"steps", r.steps},
  };
}

void PrintText(const SimulateArgs& a, const dynamics::ContactParameters& contact,
               const ImpactResult& r) {
  using format::Kind;
  const auto num = [](double v, Kind kind = Kind::kMeasured) { return format::Number(v, kind); };
  const auto vec = [&](const Eigen::Vector2d& v) {
    return "[" + num(v.x()) + ", " + num(v.y()) + "]";
  };
  std::ostringstream os;
  const double zeta = dynamics::DampingRatio(contact.k_N_m, contact.b_N_s_m, a.specimen.mass_kg);
  os << "Impact on " << a.surface << " at " << num(a.angle_deg) << " deg, " << num(a.speed_m_s)
     << " m/s (k = " << num(contact.k_N_m) << " N/m, b = " << num(contact.b_N_s_m)
     << " N s/m, zeta = " << num(zeta, Kind::kCoefficient)
     << ", mu = " << num(contact.mu, Kind::kCoefficient) << ")\n";
  os << "  v_SC before   " << vec(r.at_touch.v_SC) << " m/s\n";
  os << "  v_SC after    " << vec(r.at_separation.v_SC) << " m/s\n";
  os << "  w after       " << num(r.at_separation.w_rad_s) << " rad/s\n";
  os << "  e             " << num(r.e, Kind::kCoefficient) << "\n";
  os << "  mu_eff        " << num(r.mu_eff, Kind::kCoefficient) << "\n";
  os << "  energy loss   " << num(r.energy_loss_J * 1e3) << " mJ (of "
     << num(r.kinetic_energy_before_J * 1e3) << " mJ)\n";
  os << "  contact       " << num(r.t_separation_s * 1e6) << " µs (max compression at "
     << num(r.t_max_compression_s * 1e6) << " µs, " << num(r.max_penetration_m * 1e6) << " µm)\n";
  os << "  events:";
  for (const auto& e : r.events) os << " " << e.what << "@" << num(e.t_s * 1e6) << " µs";
  os << "\n";
  std::cout << os.str();
}

void Simulate(SimulateArgs& a, RunState& state);

}  // namespace

void RegisterSimulate(CLI::App& app, RunState& state) {
  auto args = std::make_shared<SimulateArgs>();
  CLI::App* cmd = app.add_subcommand(
      "simulate", "Simulate one impact with the paper's two-phase contact model");
  cmd->add_option("--surface", args->surface, "steel, concrete or asphalt (sets k, b, mu)")
      ->capture_default_str();
  cmd->add_option("--k", args->k_N_m, "Contact stiffness k (N/m; 1 to 1e12); overrides the surface")
      ->check(InRange(1.0, 1e12, "N/m"));
  cmd->add_option("--b", args->b_N_s_m,
                  "Compression damping b (N s/m; 0 to 1e9); overrides the surface")
      ->check(InRange(0.0, 1e9, "N s/m"));
  cmd->add_option("--zeta", args->zeta, "Damping ratio (0 to 100); sets b = 2 zeta sqrt(k m)")
      ->check(InRange(0.0, 100.0))
      ->excludes("--b");
  cmd->add_option("--mu", args->mu, "Coulomb friction coefficient (0 to 10); overrides the surface")
      ->check(InRange(0.0, 10.0));
  cmd->add_option("--angle-deg", args->angle_deg, "Surface angle phi (deg; 0 to 80)")
      ->check(InRange(0.0, 80.0, "deg"))
      ->capture_default_str();
  cmd->add_option("--speed-m-s", args->speed_m_s, "Vertical impact speed (m/s; up to 100)")
      ->check(InRange(0.0, 100.0, "m/s"))
      ->capture_default_str();
  AddSpecimenOptions(cmd, args->specimen);
  AddExtensionOptions(cmd, args->extensions);
  cmd->add_option("--gravity-m-s2", args->sim.gravity_m_s2, "Gravity g (0 to 100); 0 turns it off")
      ->check(InRange(0.0, 100.0, "m/s^2"))
      ->capture_default_str();
  cmd->add_option("--rtol", args->sim.relative_tolerance,
                  "Integrator relative tolerance, per state against max(|x|, its scale in the "
                  "impact); in (0, 1e-3]")
      ->capture_default_str();
  AddJsonFlag(cmd, args->json);
  cmd->add_option("--trajectory", args->trajectory_path,
                  "Write the trajectory sampled at frame times as CSV");
  cmd->add_option("--fps", args->fps, "Frame rate for --trajectory (1/s)")->capture_default_str();
  cmd->add_option("--frames-before", args->frames_before, "Frames before touch (0 to 100000)")
      ->check(InRange(0, 100000))
      ->capture_default_str();
  cmd->add_option("--frames-after", args->frames_after, "Frames after touch (0 to 100000)")
      ->check(InRange(0, 100000))
      ->capture_default_str();
  cmd->add_option("--touch-fraction", args->touch_fraction,
                  "Where touch falls between two frames, in frame periods [0, 1)")
      ->capture_default_str();
  cmd->add_option("--contact-samples", args->contact_samples,
                  "Extra samples spread through the contact (0 to 100000)")
      ->check(InRange(0, 100000))
      ->capture_default_str();

  cmd->callback([args, &state, cmd] {
    SimulateArgs& a = *args;
    // Every value here comes from the command line: a bad one is a command-line error (exit 2),
    // worded in the option the user typed (the simulator's fields are named otherwise).
    ValidateOptions(cmd, [&] { Simulate(a, state); },
                    {{"relative_tolerance", "--rtol"},
                     {"surface_angle_rad", "--angle-deg"},
                     {"v_SC_m_s", "--speed-m-s"},
                     {"k_N_m", "--k"},
                     {"b_N_s_m", "--b"},
                     {"d_EC_m", "--d-ec-m"}});
  });
}

namespace {

void Simulate(SimulateArgs& a, RunState& state) {
  // The sampling options are checked whether or not --trajectory uses them.
  if (!(a.fps > 0))
    throw CLI::ValidationError("--fps", "must be > 0 (1/s), got " + BoundText(a.fps));
  if (!(a.touch_fraction >= 0 && a.touch_fraction < 1))
    throw CLI::ValidationError(
        "--touch-fraction", "must be in [0, 1) frame periods, got " + BoundText(a.touch_fraction));
  {
    dynamics::ContactParameters contact = dynamics::PaperContact(dynamics::ParseSurface(a.surface));
    if (a.k_N_m) contact.k_N_m = *a.k_N_m;
    if (a.b_N_s_m) contact.b_N_s_m = *a.b_N_s_m;
    if (a.zeta) {
      if (!(*a.zeta >= 0.0 && std::isfinite(*a.zeta)))
        throw std::invalid_argument("--zeta must be finite and >= 0");
      contact.b_N_s_m = dynamics::DampingForRatio(*a.zeta, contact.k_N_m, a.specimen.mass_kg);
    }
    if (a.mu) contact.mu = *a.mu;
    contact.extensions = a.extensions;
    if (!(a.speed_m_s > 0.0))
      throw CLI::ValidationError("--speed-m-s", "must be > 0 m/s, got " + BoundText(a.speed_m_s));
    const dynamics::ImpactSimulator sim(a.specimen, contact, a.sim);
    const auto conditions = dynamics::ImpactConditions::Paper(a.speed_m_s, a.angle_deg);
    ImpactResult r = sim.Simulate(conditions);
    if (!r.success) throw std::runtime_error("simulation failed: " + r.message);
    if (!a.trajectory_path.empty()) {
      const auto times = SampleTimes(a, r.t_separation_s);
      r = sim.Simulate(conditions, times);
      WriteTrajectory(a.trajectory_path, r.samples, conditions.surface_angle_rad);
    }
    state.exit_code = kExitOk;
    if (a.json) {
      nlohmann::json results = ResultJson(a, contact, r);
      results["trajectory_csv"] = a.trajectory_path;
      results["trajectory_samples"] = r.samples.size();
      PrintEnvelope("simulate", state.exit_code, std::move(results));
    } else {
      PrintText(a, contact, r);
      if (!a.trajectory_path.empty())
        std::cout << "  trajectory    " << a.trajectory_path << " (" << r.samples.size()
                  << " samples)\n";
    }
    state.exit_code = kExitOk;
  }
}

}  // namespace
}  // namespace hoof::cli
