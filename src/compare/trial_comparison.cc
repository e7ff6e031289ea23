#include "compare/trial_comparison.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <boost/math/tools/minima.hpp>

#include "core/frames.h"
#include "core/parallel.h"
#include "tracking/pose.h"

namespace hoof::compare {
namespace {

constexpr double kG = dynamics::kStandardGravity_m_s2;
const Eigen::Vector2d kGravity_W{0.0, -kG};

core::SurfaceRotation SurfaceAxes(const pipeline::TrialAnalysis& t) {
  return core::SurfaceRotation::FromDegrees(t.spec.surface_angle_deg);
}

/// The rigid body the trial is simulated as (without what the camera sees of it).
dynamics::SpecimenParameters Specimen(const pipeline::TrialAnalysis& t) {
  return BodyToSimulate(t).specimen;
}

/// "<trial folder>/trial.json, trial <id> (specimen: <origin>)": where a trial's failure
/// points to.
std::string TrialWhere(const pipeline::TrialAnalysis& t) {
  std::string s = (t.spec.dir / "trial.json").string() + ", trial " + t.spec.id;
  if (!t.spec.specimen_origin.empty()) s += " (specimen: " + t.spec.specimen_origin + ")";
  return s;
}

/// Height of the lowest point of the round end above the touch point, along y_S, for a body in
/// free flight from `state` after time `dt`.
double HeightOfT(const dynamics::BodyState& state, const Eigen::Vector2d& g_S, double dt,
                 const dynamics::SpecimenParameters& sp) {
  const dynamics::BodyState b = dynamics::PropagateFlight(state, g_S, dt);
  return b.p_SC.y() - sp.d_EC_m * std::sin(b.theta_S_rad) - sp.end_radius_m;
}

/// Time after first touch where the simulated before and after flights give T the same height
/// (as the measured fits define the impact time).
double SimulatedMeetingTime(const dynamics::ImpactResult& r, double phi,
                            const dynamics::SpecimenParameters& sp) {
  const Eigen::Vector2d g_S = dynamics::GravityInSurfaceFrame(phi, kG);
  auto f = [&](double tau) {
    return HeightOfT(r.at_touch, g_S, tau, sp) -
           HeightOfT(r.at_separation, g_S, tau - r.t_separation_s, sp);
  };
  double lo = 0.0, hi = r.t_separation_s;
  if (!(f(lo) >= 0 && f(hi) <= 0)) return 0.5 * r.t_separation_s;
  for (int i = 0; i < 100 && hi - lo > 1e-15; ++i)
    (f(0.5 * (lo + hi)) > 0 ? lo : hi) = 0.5 * (lo + hi);
  return 0.5 * (lo + hi);
}

/// The simulator for a trial's specimen and a contact law.
dynamics::ImpactSimulator Simulator(const pipeline::TrialAnalysis& t,
                                    const dynamics::ContactParameters& c) {
  return dynamics::ImpactSimulator(Specimen(t), c);
}

/// First-touch time such that the simulation's flights meet where the measured fits meet.
double TouchTime(const pipeline::TrialAnalysis& t, const dynamics::ImpactSimulator& sim) {
  const double t_star = t.impact.impact_time_s;
  double t_touch = t_star - 5e-6;
  for (int it = 0; it < 3; ++it) {
    const auto r = sim.Simulate(MeasuredConditions(t, t_touch));
    if (!r.success) break;
    t_touch = t_star - SimulatedMeetingTime(r, SurfaceAxes(t).phi_rad(), sim.specimen());
  }
  return t_touch;
}

/// Simulated velocity of C in S and spin after the impact, carried to the measured impact time.
std::pair<Eigen::Vector2d, double> AfterAtImpactTime(const pipeline::TrialAnalysis& t,
                                                     const dynamics::ImpactResult& r,
                                                     double t_touch) {
  const Eigen::Vector2d g_S = dynamics::GravityInSurfaceFrame(SurfaceAxes(t).phi_rad(), kG);
  const double dt = t.impact.impact_time_s - (t_touch + r.t_separation_s);
  return {r.at_separation.v_SC + g_S * dt, r.at_separation.w_rad_s};
}

tracking::ImageToWorld Camera(const pipeline::TrialAnalysis& t) {
  tracking::ImageToWorld cam;
  cam.m_per_px = t.m_per_px_used;
  cam.gravity_I = t.spec.camera.gravity_image;
  cam.camera_matrix = t.spec.camera.camera_matrix;
  cam.distortion = t.spec.camera.distortion;
  return cam;
}

}  // namespace

dynamics::ImpactConditions MeasuredConditions(const pipeline::TrialAnalysis& t, double t_touch_s) {
  const core::SurfaceRotation S = SurfaceAxes(t);
  const auto& b = t.impact.before;
  const double dt = t_touch_s - t.impact.impact_time_s;
  dynamics::ImpactConditions c;
  c.surface_angle_rad = S.phi_rad();
  c.v_SC_m_s = S.ToS(b.v_WC + kGravity_W * dt);
  c.w_rad_s = b.w_rad_s;
  c.theta_S_rad = S.AngleToS(b.theta_W_rad + b.w_rad_s * dt);
  return c;
}

SimulatedBody BodyToSimulate(const pipeline::TrialAnalysis& t) {
  SimulatedBody body;
  body.specimen = static_cast<const core::SpecimenParameters&>(t.spec.specimen);
  if (!t.spec.specimen.is_ball() || t.spec.specimen.mass_known()) return body;
  // A ball of unknown mass: the reference mass, and the inertia of its rule (a solid sphere's
  // when even that is unknown).
  body.mass_known = false;
  pipeline::BallInertia rule = t.spec.specimen.inertia;
  if (rule != pipeline::BallInertia::kSolid && rule != pipeline::BallInertia::kHollow) {
    rule = pipeline::BallInertia::kSolid;
    body.inertia_assumed = true;
  }
  const double R = body.specimen.end_radius_m;
  body.specimen.mass_kg = kReferenceMass_kg;
  body.specimen.inertia_kg_m2 = pipeline::BallInertiaFactor(rule) * kReferenceMass_kg * R * R;
  return body;
}

ModelUncertainty Uncertainty(const SurfaceModel& model) {
  ModelUncertainty u;
  u.zeta_se = std::isfinite(model.zeta_fit.zeta_se) ? model.zeta_fit.zeta_se : 0.0;
  u.mu_se = std::isfinite(model.mu_se) ? model.mu_se : 0.0;
  return u;
}

namespace {

/// Frame `f` of trial `t`: the simulation (`s`, in S with its origin at `p_WT`, T at first
/// touch) against the measured pose and markers, in W and in the image.
FrameComparison CompareFrame(const pipeline::TrialAnalysis& t, std::size_t f,
                             const dynamics::TrajectorySample& s, const Eigen::Vector2d& p_WT,
                             const core::SurfaceRotation& S, const dynamics::SpecimenParameters& sp,
                             const tracking::ImageToWorld& cam) {
  FrameComparison fc;
  fc.t_s = static_cast<double>(f) / t.spec.fps;
  fc.p_WC_sim = p_WT + S.ToW(s.body.p_SC);
  fc.theta_W_sim_rad = S.AngleToW(s.body.theta_S_rad);
  fc.kinetic_energy_sim_J = s.kinetic_energy_J;
  const core::BodyRotation R_WB_sim(fc.theta_W_sim_rad);
  const Eigen::Vector2d p_WE_sim = fc.p_WC_sim - sp.d_EC_m * R_WB_sim.x_B();
  const auto& pose = t.poses[f];
  fc.measured = pose.valid;
  fc.centre_px_sim = cam.ToImage(fc.p_WC_sim);
  if (pose.valid) {
    fc.p_WC_meas = pose.p_WE + sp.d_EC_m * core::BodyRotation(pose.theta_W_rad).x_B();
    fc.theta_W_meas_rad = pose.theta_W_rad;
    fc.centre_px_meas = cam.ToImage(fc.p_WC_meas);
    fc.centre_residual_px = (fc.centre_px_meas - fc.centre_px_sim).norm();
  }
  const auto markers = ComparedMarkers(t);
  for (std::size_t m = 0; m < markers.size(); ++m) {
    const Eigen::Vector2d sim_W = p_WE_sim + R_WB_sim.ToW(markers[m].second);
    fc.markers_W_sim.push_back(sim_W);
    const Eigen::Vector2d sim_px = cam.ToImage(sim_W);
    fc.markers_px_sim.push_back(sim_px);
    const bool found =
        f < t.tracks.frames.size() && m < t.tracks.frames[f].size() && t.tracks.frames[f][m].found;
    const Eigen::Vector2d meas =
        found ? t.tracks.frames[f][m].p_I : Eigen::Vector2d::Constant(core::kNaN);
    fc.markers_px_meas.push_back(meas);
    fc.marker_residual_px.push_back(found ? (meas - sim_px).norm() : core::kNaN);
  }
  return fc;
}

/// The velocities after the impact, simulated and measured, the simulated ones' uncertainty
/// from the measured state before and the model (one-sided differences of one standard error
/// in vx, vy, w, zeta and mu), and the z-scores of their differences.
void CompareAfter(const pipeline::TrialAnalysis& t, const dynamics::ContactParameters& contact,
                  const ModelUncertainty& uncertainty, const dynamics::SpecimenParameters& sp,
                  TrialComparison& out) {
  const auto& b = t.impact.before;
  const auto [v_sim, w_sim] = AfterAtImpactTime(t, out.sim, out.t_touch_s);
  out.v_SC_after_sim = v_sim;
  out.w_after_sim = w_sim;
  out.v_SC_after_meas = t.impact.v_SC_after;
  out.w_after_meas = t.impact.w_after_rad_s;
  Eigen::Vector2d var_v = Eigen::Vector2d::Zero();
  double var_w = 0.0;
  const double se_v = std::sqrt(b.cov_v_WC(0, 0));
  for (int k = 0; k < 5; ++k) {
    pipeline::TrialAnalysis shifted = t;  // cheap enough: a few per trial
    auto& sb = shifted.impact.before;
    dynamics::ContactParameters c = contact;
    if (k < 2) {
      sb.v_WC(k) += se_v;
    } else if (k == 2) {
      sb.w_rad_s += b.w_se_rad_s;
    } else if (k == 3) {
      if (uncertainty.zeta_se <= 0) continue;
      const double zeta = dynamics::DampingRatio(c.k_N_m, c.b_N_s_m, sp.mass_kg);
      c.b_N_s_m = dynamics::DampingForRatio(zeta + uncertainty.zeta_se, c.k_N_m, sp.mass_kg);
    } else {
      if (uncertainty.mu_se <= 0) continue;
      c.mu += uncertainty.mu_se;
    }
    const auto r =
        dynamics::ImpactSimulator(sp, c).Simulate(MeasuredConditions(shifted, out.t_touch_s));
    if (!r.success) continue;
    const auto [v2, w2] = AfterAtImpactTime(shifted, r, out.t_touch_s);
    var_v += (v2 - v_sim).cwiseAbs2();
    var_w += (w2 - w_sim) * (w2 - w_sim);
  }
  out.v_SC_after_sim_se = var_v.cwiseSqrt();
  out.w_after_sim_se = std::sqrt(var_w);
  const Eigen::Vector2d se_meas = t.impact.v_SC_after_se;
  for (int k = 0; k < 2; ++k)
    out.v_SC_after_z(k) =
        (out.v_SC_after_meas(k) - v_sim(k)) / std::sqrt(se_meas(k) * se_meas(k) + var_v(k));
  out.w_after_z = (out.w_after_meas - w_sim) /
                  std::sqrt(t.impact.w_after_se_rad_s * t.impact.w_after_se_rad_s + var_w);
}

/// A body of unknown mass has no kinetic energy in J: the simulation's, at the reference mass,
/// are not its own.
void ForgetEnergies(TrialComparison& out) {
  out.kinetic_energy_before_J = out.kinetic_energy_after_meas_J = out.kinetic_energy_after_sim_J =
      core::kNaN;
  for (auto& f : out.frames) f.kinetic_energy_sim_J = core::kNaN;
  for (double& e : out.contact_kinetic_energy_J) e = core::kNaN;
}

}  // namespace

TrialComparison CompareTrial(const pipeline::TrialAnalysis& t,
                             const dynamics::ContactParameters& contact,
                             const ModelUncertainty& uncertainty) {
  TrialComparison out;
  if (!t.success) {
    out.message = "the trial was not measured: " + t.error;
    return out;
  }
  try {
    const SimulatedBody body = BodyToSimulate(t);
    out.mass_known = body.mass_known;
    out.inertia_assumed = body.inertia_assumed;
    const dynamics::ImpactSimulator sim = Simulator(t, contact);
    const dynamics::SpecimenParameters& sp = sim.specimen();
    const core::SurfaceRotation S = SurfaceAxes(t);
    out.t_touch_s = TouchTime(t, sim);
    const dynamics::ImpactConditions ic = MeasuredConditions(t, out.t_touch_s);

    // Frame times, and samples through the contact for the energy (Figure 8).
    const std::size_t frames = t.poses.size();
    std::vector<double> times;
    for (std::size_t f = 0; f < frames; ++f)
      times.push_back(static_cast<double>(f) / t.spec.fps - out.t_touch_s);
    const auto first = sim.Simulate(ic);
    if (!first.success) {
      out.message = "simulation failed: " + first.message;
      return out;
    }
    const int n_contact = 101;
    for (int i = 0; i < n_contact; ++i)
      times.push_back(-10e-6 + (first.t_separation_s + 20e-6) * i / (n_contact - 1));
    out.sim = sim.Simulate(ic, times);

    // Where the simulation's S frame lies in W: its origin is T at first touch.
    const auto& b = t.impact.before;
    const double dt = out.t_touch_s - t.impact.impact_time_s;
    const Eigen::Vector2d p_WC_touch = b.p_WC + b.v_WC * dt + 0.5 * kGravity_W * dt * dt;
    const double theta_touch = b.theta_W_rad + b.w_rad_s * dt;
    const Eigen::Vector2d p_WT =
        p_WC_touch - sp.d_EC_m * core::BodyRotation(theta_touch).x_B() - sp.end_radius_m * S.y_S();
    const tracking::ImageToWorld cam = Camera(t);
    for (std::size_t f = 0; f < frames; ++f)
      out.frames.push_back(CompareFrame(t, f, out.sim.samples[f], p_WT, S, sp, cam));
    for (int i = 0; i < n_contact; ++i) {
      const auto& s = out.sim.samples[frames + static_cast<std::size_t>(i)];
      out.contact_t_s.push_back(s.t_s);
      out.contact_kinetic_energy_J.push_back(s.kinetic_energy_J);
    }
    CompareAfter(t, contact, uncertainty, sp, out);
    out.kinetic_energy_before_J = t.impact.kinetic_energy_before_J;
    out.kinetic_energy_after_meas_J = t.impact.kinetic_energy_after_J;
    out.kinetic_energy_after_sim_J = out.sim.kinetic_energy_after_J;
    if (!body.mass_known) ForgetEnergies(out);
    out.success = true;
  } catch (const std::exception& e) {
    out = {};
    out.message = TrialWhere(t) + ": " + e.what();
  }
  return out;
}

namespace {

/// zeta from the normal trials (k is not identified by velocities: the paper's for the surface,
/// else 1e8 N/m) and the damping it gives; false (with the message in `m`) when the fit fails.
bool FitZeta(const std::vector<const pipeline::TrialAnalysis*>& normal, SurfaceModel& m) {
  const dynamics::SpecimenParameters sp = Specimen(*normal.front());
  std::vector<dynamics::NormalImpact> impacts;
  for (const auto* t : normal)
    impacts.push_back({std::abs(t->impact.v_SC_before.y()), std::abs(t->impact.v_SC_after.y())});
  dynamics::ContactFitOptions fo;
  fo.map_points_k = fo.map_points_b = 0;
  m.zeta_fit = dynamics::FitNormalContact(impacts, sp, fo);
  if (!m.zeta_fit.success) {
    m.message = "zeta fit failed: " + m.zeta_fit.message;
    return false;
  }
  try {
    m.k_N_m = dynamics::PaperContact(dynamics::ParseSurface(m.surface)).k_N_m;
  } catch (const std::invalid_argument&) {
    m.k_N_m = 1e8;
  }
  m.b_N_s_m = dynamics::DampingForRatio(m.zeta_fit.zeta, m.k_N_m, sp.mass_kg);
  return true;
}

/// mu from the oblique trials (at least one), on `jobs` threads: a grid, then Brent about its
/// best point, with the s.e. from the curvature, or only a lower bound where contacts stick.
void FitMu(const std::vector<const pipeline::TrialAnalysis*>& oblique, int jobs, SurfaceModel& m) {
  // mu: least squares of the tangential velocity of C and the spin after the impact, weighted
  // by their standard errors; touch times fixed from a first simulation (they hardly depend on
  // mu).
  std::vector<double> touch(oblique.size());
  core::ParallelFor(oblique.size(), jobs, [&](std::size_t i) {
    touch[i] = TouchTime(*oblique[i], Simulator(*oblique[i], {m.k_N_m, m.b_N_s_m, 0.3}));
  });
  auto cost = [&](double mu) {
    double s = 0;
    for (std::size_t i = 0; i < oblique.size(); ++i) {
      const auto& t = *oblique[i];
      const auto r =
          Simulator(t, {m.k_N_m, m.b_N_s_m, mu}).Simulate(MeasuredConditions(t, touch[i]));
      if (!r.success) continue;
      const auto [v_sim, w_sim] = AfterAtImpactTime(t, r, touch[i]);
      const double se_v = std::max(t.impact.v_SC_after_se.x(), 1e-6);
      const double se_w = std::max(t.impact.w_after_se_rad_s, 1e-6);
      // A ball's spin is not seen: only its velocity speaks for mu. The two terms are summed
      // before they are added (one rounding): where every contact sticks the sum is flat in mu,
      // and the last bit decides where the search for mu ends.
      const double dv2 = std::pow((t.impact.v_SC_after.x() - v_sim.x()) / se_v, 2);
      s += std::isfinite(t.impact.w_after_rad_s)
               ? dv2 + std::pow((t.impact.w_after_rad_s - w_sim) / se_w, 2)
               : dv2;
    }
    return s;
  };
  // A grid first (the sum has kinks where trials change between sliding and sticking), then
  // Brent about the best grid point.
  constexpr double kStep = 0.01, kMax = 1.5;
  std::vector<double> at;
  for (double mu = 0; mu <= kMax + 1e-9; mu += kStep) at.push_back(mu);
  // Each point's sum is the same on any thread: the grid is the same for any `jobs`.
  std::vector<double> grid(at.size());
  core::ParallelFor(at.size(), jobs, [&](std::size_t i) { grid[i] = cost(at[i]); });
  const std::size_t best =
      static_cast<std::size_t>(std::min_element(grid.begin(), grid.end()) - grid.begin());
  const double lo = std::max(0.0, (static_cast<double>(best) - 1) * kStep);
  const double hi = std::min(kMax, (static_cast<double>(best) + 1) * kStep);
  const auto [mu, s_min] = boost::math::tools::brent_find_minima(cost, lo, hi, 30);
  m.mu = mu;
  m.mu_only_lower_bound = std::all_of(grid.begin() + static_cast<std::ptrdiff_t>(best), grid.end(),
                                      [&](double c) { return c <= s_min + 1.0; });
  const double h = 2e-3;
  const double curvature = (cost(mu + h) - 2 * s_min + cost(std::max(0.0, mu - h))) / (h * h);
  // Standard error from the curvature, scaled by the reduced chi-square (the usual least-squares
  // practice: when trials scatter more than their measurement errors, mu is less certain).
  double components = 0;  // v_x of each trial, and its spin where it is seen
  for (const auto* t : oblique) components += std::isfinite(t->impact.w_after_rad_s) ? 2 : 1;
  const double dof = std::max(1.0, components - 1.0);
  const double scale = std::max(1.0, s_min / dof);
  m.mu_se =
      curvature > 0 && !m.mu_only_lower_bound ? std::sqrt(2.0 / curvature * scale) : core::kNaN;
  if (m.mu_only_lower_bound)
    m.message = "every mu above " + std::to_string(mu) + " fits the oblique trials on " +
                m.surface + " as well: their contacts stick, so mu is bounded only from below";
}

/// The model of the surface `m.surface` fitted to its normal and oblique trials.
SurfaceModel FitSurfaceModelOf(SurfaceModel m,
                               const std::vector<const pipeline::TrialAnalysis*>& normal,
                               const std::vector<const pipeline::TrialAnalysis*>& oblique,
                               int jobs) {
  const std::string& surface = m.surface;
  m.normal_trials = static_cast<int>(normal.size());
  m.oblique_trials = static_cast<int>(oblique.size());
  if (normal.empty()) {
    m.message = "no measured normal (0 deg) trials on " + surface + " to fit zeta to";
    return m;
  }
  if (!FitZeta(normal, m)) return m;
  m.success = true;
  if (oblique.empty()) {
    m.mu = core::kNaN;
    m.mu_se = m.mu;
    m.message = "no oblique trials on " + surface + ": mu not fitted";
    return m;
  }
  FitMu(oblique, jobs, m);
  return m;
}

}  // namespace

SurfaceModel FitSurfaceModel(const std::string& surface,
                             const std::vector<pipeline::TrialAnalysis>& trials, int jobs) {
  SurfaceModel m;
  m.surface = surface;
  std::vector<const pipeline::TrialAnalysis*> normal, oblique;
  std::string left_out;
  for (const auto& t : trials) {
    if (!t.success || t.spec.surface != surface) continue;
    // A trial whose body cannot be simulated is left out of the fit, named; the others fit.
    try {
      BodyToSimulate(t).specimen.Validate();
    } catch (const std::exception& e) {
      left_out += (left_out.empty() ? "" : "; ") + TrialWhere(t) + ": " + e.what();
      continue;
    }
    m.mass_known = m.mass_known && BodyToSimulate(t).mass_known;
    (std::abs(t.spec.surface_angle_deg) < 1e-9 ? normal : oblique).push_back(&t);
  }
  if (!left_out.empty()) left_out = "left out of the fit: " + left_out;
  m = FitSurfaceModelOf(std::move(m), normal, oblique, jobs);
  if (!left_out.empty()) m.message += (m.message.empty() ? "" : "; ") + left_out;
  return m;
}

std::vector<std::pair<std::string, Eigen::Vector2d>> ComparedMarkers(
    const pipeline::TrialAnalysis& trial) {
  if (trial.spec.body.is_silhouette()) return {};
  return trial.spec.specimen.markers_B_m;
}

dynamics::SpecimenParameters SpecimenOf(const pipeline::TrialAnalysis& trial) {
  return Specimen(trial);
}

double SimulatedTouchTime(const pipeline::TrialAnalysis& trial,
                          const dynamics::ContactParameters& contact) {
  return TouchTime(trial, Simulator(trial, contact));
}

std::pair<Eigen::Vector2d, double> SimulatedAfterAtImpactTime(const pipeline::TrialAnalysis& trial,
                                                              const dynamics::ImpactResult& result,
                                                              double t_touch_s) {
  return AfterAtImpactTime(trial, result, t_touch_s);
}

}  // namespace hoof::compare
