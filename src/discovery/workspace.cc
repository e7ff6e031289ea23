// The measured trials as the discovery workflow uses them, and its calls of the simulator
// (docs/discovery.md, "Data and residuals").
#include <algorithm>
#include <cmath>
#include <numeric>

#include "compare/trial_comparison.h"
#include "core/frames.h"
#include "core/parallel.h"
#include "discovery/internal.h"

namespace hoof::discovery::internal {
namespace {
constexpr double kG = dynamics::kStandardGravity_m_s2;

/// The variance of the measured velocities after impact, per component (v_x, v_y, w d_EC) and
/// over the impact speed `scale` squared. The prediction starts from the measured state before
/// the impact, so its error enters too (to first order with a gain of at most 1); a component
/// without an s.e. counts 0.
Eigen::Vector3d MeasurementVariance(const kinematics::ImpactKinematics& im, double d_EC_m,
                                    double scale) {
  const double d = d_EC_m;
  Eigen::Vector3d var = Eigen::Vector3d(im.v_SC_after_se.x() * im.v_SC_after_se.x() +
                                            im.v_SC_before_se.x() * im.v_SC_before_se.x(),
                                        im.v_SC_after_se.y() * im.v_SC_after_se.y() +
                                            im.v_SC_before_se.y() * im.v_SC_before_se.y(),
                                        d * d *
                                            (im.w_after_se_rad_s * im.w_after_se_rad_s +
                                             im.w_before_se_rad_s * im.w_before_se_rad_s)) /
                        (scale * scale);
  for (int c = 0; c < kComponents; ++c)
    if (!std::isfinite(var[c])) var[c] = 0.0;
  return var;
}

/// Image-level evidence: the mean and the slope in time of the marker distance ratio over the
/// flight windows of `t` (left as they are with fewer than three frames).
void MarkerRatioTrend(const pipeline::TrialAnalysis& t, Obs& o) {
  const auto& im = t.impact;
  std::vector<std::pair<double, double>> tr;
  for (const auto* fit : {&im.before, &im.after})
    for (int f = fit->first_frame; f <= fit->last_frame; ++f)
      if (f >= 0 && static_cast<std::size_t>(f) < t.marker_distance_ratio.size() &&
          std::isfinite(t.marker_distance_ratio[static_cast<std::size_t>(f)]))
        tr.emplace_back(f / t.spec.fps, t.marker_distance_ratio[static_cast<std::size_t>(f)]);
  if (tr.size() >= 3) {
    double mx = 0, my = 0;
    for (const auto& [x, y] : tr) mx += x, my += y;
    mx /= static_cast<double>(tr.size());
    my /= static_cast<double>(tr.size());
    double sxx = 0, sxy = 0;
    for (const auto& [x, y] : tr) sxx += (x - mx) * (x - mx), sxy += (x - mx) * (y - my);
    o.marker_ratio = my;
    o.marker_ratio_slope = sxx > 0 ? sxy / sxx : kNaN;
  }
}

/// The index of the surface of the model `m` in the workspace, which gets its starts (k, zeta,
/// mu) when it is new.
int SurfaceIndex(const compare::SurfaceModel& m, std::map<std::string, int>& surface_index,
                 Workspace& ws) {
  const auto [it, added] =
      surface_index.try_emplace(m.surface, static_cast<int>(ws.surfaces.size()));
  if (added) {
    ws.surfaces.push_back(m.surface);
    ws.k.push_back(m.k_N_m);
    ws.zeta_start.push_back(m.zeta_fit.zeta);
    ws.mu_start.push_back(std::isfinite(m.mu) ? m.mu : 0.3);
    ws.has_oblique.push_back(false);
    ws.mu_eff_max.push_back(0.0);
  }
  return it->second;
}

/// What the simulation of trial `t` starts from (the specimen, the touch time under the surface
/// model `m`, the measured state), and what it is compared with: the velocities after impact
/// and their variance.
void SimulationInputs(const pipeline::TrialAnalysis& t, const compare::SurfaceModel& m, Obs& o) {
  o.specimen = compare::SpecimenOf(t);
  dynamics::ContactParameters contact = m.Contact();
  if (!std::isfinite(contact.mu)) contact.mu = 0.3;
  o.t_touch_s = compare::SimulatedTouchTime(t, contact);
  o.conditions = compare::MeasuredConditions(t, o.t_touch_s);
  o.impact_time_s = t.impact.impact_time_s;
  o.phi = core::DegToRad(o.angle_deg);
  const auto& im = t.impact;
  o.measured = {im.v_SC_after.x(), im.v_SC_after.y(), im.w_after_rad_s * o.specimen.d_EC_m};
  o.measurement_var = MeasurementVariance(im, o.specimen.d_EC_m, o.scale);
}

/// Folds: trials in design order (surface, angle, speed, id) dealt round-robin, so that each
/// fold holds a share of every surface, angle and speed range, replicated or not.
void AssignFolds(int folds, Workspace& ws) {
  std::vector<std::size_t> order(ws.obs.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) {
    const Obs& x = ws.obs[a];
    const Obs& y = ws.obs[b];
    if (x.surface != y.surface) return x.surface < y.surface;
    if (x.angle_deg != y.angle_deg) return x.angle_deg < y.angle_deg;
    if (x.speed_m_s != y.speed_m_s) return x.speed_m_s < y.speed_m_s;
    return x.trial->spec.id < y.trial->spec.id;
  });
  int next = 0;
  for (std::size_t i : order) ws.obs[i].fold = next++ % folds;
}

}  // namespace

dynamics::ContactExtensions Workspace::Extensions(const Model& m, int surface) const {
  dynamics::ContactExtensions x;
  for (const auto& [key, p] : m.effects) Apply(key, p.At(surface), x);
  return x;
}

Eigen::Vector3d Workspace::Predict(const Obs& o, double zeta, double mu,
                                   const dynamics::ContactExtensions& x, bool* ok) const {
  const double k_s = k[static_cast<std::size_t>(o.surface)];
  dynamics::ContactParameters c(k_s, dynamics::DampingForRatio(zeta, k_s, o.specimen.mass_kg), mu);
  c.extensions = x;
  dynamics::SimulatorOptions so;
  so.relative_tolerance = rtol;
  ++(counted_in ? counted_in->simulations : simulations);
  *ok = false;
  try {
    const auto r = dynamics::ImpactSimulator(o.specimen, c, so).Simulate(o.conditions);
    *ok = r.success;
    if (!r.success) return {0, 0, 0};
    const Eigen::Vector2d g_S = dynamics::GravityInSurfaceFrame(o.phi, kG);
    // Carried under gravity from the separation to the measured impact time, where the
    // measured velocities after the impact are quoted.
    const Eigen::Vector2d v =
        r.at_separation.v_SC + g_S * (o.impact_time_s - (o.t_touch_s + r.t_separation_s));
    return {v.x(), v.y(), r.at_separation.w_rad_s * o.specimen.d_EC_m};
  } catch (const std::exception&) {
    return {0, 0, 0};
  }
}

std::vector<Eigen::Vector3d> Workspace::Residuals(const Model& m,
                                                  const std::vector<int>& which) const {
  std::vector<Eigen::Vector3d> out(which.size(), Eigen::Vector3d::Constant(kNaN));
  ParallelFor(which.size(), [&](std::size_t i) {
    const Obs& o = obs[static_cast<std::size_t>(which[i])];
    const auto s = static_cast<std::size_t>(o.surface);
    bool ok = false;
    const Eigen::Vector3d p = Predict(o, m.zeta[s], m.mu[s], Extensions(m, o.surface), &ok);
    for (int c = 0; c < kComponents; ++c)
      if (o.used[static_cast<std::size_t>(c)])
        out[i][c] = ok ? (o.measured[c] - p[c]) / o.scale : 1.0;
  });
  return out;
}

std::vector<Sensitivity> Workspace::Sensitivities(const Model& m,
                                                  const std::vector<int>& which) const {
  std::vector<Sensitivity> out(which.size(), Sensitivity::Zero());
  ParallelFor(which.size(), [&](std::size_t i) {
    const Obs& o = obs[static_cast<std::size_t>(which[i])];
    const auto s = static_cast<std::size_t>(o.surface);
    const dynamics::ContactExtensions x = Extensions(m, o.surface);
    const double zeta = m.zeta[s], mu = m.mu[s];
    bool ok1 = false, ok2 = false;
    // zeta: central differences of a relative step.
    const double hz = 1e-4 * std::max(zeta, 0.01);
    const Eigen::Vector3d zp = Predict(o, zeta + hz, mu, x, &ok1);
    const Eigen::Vector3d zm = Predict(o, std::max(1e-6, zeta - hz), mu, x, &ok2);
    if (ok1 && ok2) out[i].col(0) = (zp - zm) / (zeta + hz - std::max(1e-6, zeta - hz)) / o.scale;
    // mu: only oblique impacts feel it; forward differences at the bound 0.
    if (!o.normal) {
      const double hm = 1e-4;
      const double lo = std::max(0.0, mu - hm);
      const Eigen::Vector3d mp = Predict(o, zeta, mu + hm, x, &ok1);
      const Eigen::Vector3d mm = Predict(o, zeta, lo, x, &ok2);
      if (ok1 && ok2) out[i].col(1) = (mp - mm) / (mu + hm - lo) / o.scale;
    }
    for (int c = 0; c < kComponents; ++c)
      if (!o.used[static_cast<std::size_t>(c)]) out[i].row(c).setZero();
  });
  return out;
}

void Workspace::ParallelFor(std::size_t n, const std::function<void(std::size_t)>& f) const {
  core::ParallelFor(n, threads, f);
}

std::vector<int> Workspace::All() const {
  std::vector<int> all(obs.size());
  std::iota(all.begin(), all.end(), 0);
  return all;
}

void Build(const std::vector<pipeline::TrialAnalysis>& trials, const DiscoveryOptions& options,
           int* skipped, Workspace& ws) {
  ws.rtol = options.relative_tolerance;
  ws.measurement_floor = options.measurement_floor;
  ws.threads = core::ResolveJobs(options.jobs);
  std::map<std::string, int> surface_index, cell_index;
  *skipped = 0;
  std::vector<const pipeline::TrialAnalysis*> used;
  for (const auto& t : trials) {
    if (!t.success) {
      ++*skipped;
      continue;
    }
    used.push_back(&t);
  }
  // Start per surface from the comparison's rules (zeta from normal trials, mu from oblique).
  std::map<std::string, compare::SurfaceModel> base;
  for (const auto* t : used)
    if (!base.count(t->spec.surface))
      base[t->spec.surface] = compare::FitSurfaceModel(t->spec.surface, trials, ws.threads);
  for (const auto* t : used) {
    const auto& m = base.at(t->spec.surface);
    if (!m.success) {
      ++*skipped;
      continue;
    }
    Obs o;
    o.trial = t;
    o.trial_index = static_cast<std::size_t>(t - trials.data());
    o.scale = t->impact.v_SC_before.norm();
    if (!(o.scale > 0)) {
      ++*skipped;
      continue;
    }
    o.surface = SurfaceIndex(m, surface_index, ws);
    o.angle_deg = t->spec.surface_angle_deg;
    o.normal = std::abs(o.angle_deg) < 1e-9;
    if (!o.normal) {
      ws.has_oblique[static_cast<std::size_t>(o.surface)] = true;
      auto& most = ws.mu_eff_max[static_cast<std::size_t>(o.surface)];
      if (std::isfinite(t->impact.mu_eff)) most = std::max(most, std::abs(t->impact.mu_eff));
    }
    // The measured impact speed (continuous speeds have no nominal level).
    o.speed_m_s = t->spec.nominal_speed_m_s.value_or(o.scale);
    SimulationInputs(*t, m, o);
    // Normal impacts carry no information about the contact law in v_x and w; nor does a
    // ball's spin, which is not seen (NaN), and would be w d = 0 with d = 0 anyway.
    const bool spin_seen = std::isfinite(o.measured[2]) && o.specimen.d_EC_m > 0;
    o.used = {!o.normal, true, !o.normal && spin_seen};
    const std::string cell_key =
        t->spec.surface + "|" + Fmt(o.angle_deg, 6) + "|" + Fmt(o.speed_m_s, 6);
    o.cell = cell_index.try_emplace(cell_key, static_cast<int>(cell_index.size())).first->second;
    MarkerRatioTrend(*t, o);
    ws.obs.push_back(o);
  }
  AssignFolds(options.folds, ws);
}

}  // namespace hoof::discovery::internal
