#include "compare/study_comparison.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "core/frames.h"
#include "core/parallel.h"

namespace hoof::compare {
namespace {

using core::kNaN;
using studyfile::Column;
using studyfile::Table;

}  // namespace

StudyComparison CompareStudy(const std::vector<pipeline::TrialAnalysis>& trials, int jobs) {
  StudyComparison out;
  std::set<std::string> surfaces;
  for (const auto& t : trials)
    if (t.success) surfaces.insert(t.spec.surface);
  for (const auto& s : surfaces) out.surfaces[s] = FitSurfaceModel(s, trials, std::max(1, jobs));
  out.trials.resize(trials.size());
  core::ParallelFor(trials.size(), std::max(1, jobs), [&](std::size_t i) {
    const auto& t = trials[i];
    if (!t.success) {
      out.trials[i].message = "not measured: " + t.error;
      return;
    }
    const SurfaceModel& m = out.surfaces.at(t.spec.surface);
    if (!m.success) {
      out.trials[i].message = "no model for " + t.spec.surface + ": " + m.message;
      return;
    }
    dynamics::ContactParameters c = m.Contact();
    if (std::isnan(c.mu)) c.mu = 0.0;  // no oblique trials on this surface: frictionless
    // One trial that cannot be simulated is recorded as such; it never sinks the study (nor,
    // thrown from a worker, the program).
    try {
      out.trials[i] = CompareTrial(t, c, Uncertainty(m));
    } catch (const std::exception& e) {
      out.trials[i] = {};
      out.trials[i].message = std::string("cannot be compared: ") + e.what();
    }
  });
  return out;
}

std::vector<Table> ComparisonTables(const std::vector<pipeline::TrialAnalysis>& trials,
                                    const StudyComparison& comparison) {
  std::vector<Table> tables;
  {
    std::vector<std::string> name, message;
    std::vector<std::int64_t> n_normal, n_oblique, ok, lower_bound;
    std::vector<double> zeta, zeta_se, zeta_lo, zeta_hi, k, b, mu, mu_se;
    for (const auto& [s, m] : comparison.surfaces) {
      name.push_back(s);
      message.push_back(m.message);
      n_normal.push_back(m.normal_trials);
      n_oblique.push_back(m.oblique_trials);
      ok.push_back(m.success ? 1 : 0);
      lower_bound.push_back(m.mu_only_lower_bound ? 1 : 0);
      zeta.push_back(m.success ? m.zeta_fit.zeta : kNaN);
      zeta_se.push_back(m.success ? m.zeta_fit.zeta_se : kNaN);
      zeta_lo.push_back(m.success ? m.zeta_fit.zeta_ci_low : kNaN);
      zeta_hi.push_back(m.success ? m.zeta_fit.zeta_ci_high : kNaN);
      k.push_back(m.success ? m.k_N_m : kNaN);
      b.push_back(m.success ? m.b_N_s_m : kNaN);
      mu.push_back(m.success ? m.mu : kNaN);
      mu_se.push_back(m.success ? m.mu_se : kNaN);
    }
    tables.push_back(Table{
        "surfaces",
        "Contact law per surface fitted to the measurements: zeta from the normal trials (k is "
        "not identified; the paper's k is used), mu from the oblique trials (least squares of "
        "tangential velocity and spin after impact)",
        {Column::Texts("surface", "surface name", name),
         Column::Integers("normal_trials", "1", "normal (0 deg) trials used", n_normal),
         Column::Integers("oblique_trials", "1", "oblique trials used", n_oblique),
         Column::Integers("success", "", "1 when the model could be fitted", ok),
         Column::Numbers("zeta", "1", "damping ratio", zeta),
         Column::Numbers("zeta_se", "1", "its standard error", zeta_se),
         Column::Numbers("zeta_ci_low", "1", "95 % interval, low", zeta_lo),
         Column::Numbers("zeta_ci_high", "1", "95 % interval, high", zeta_hi),
         Column::Numbers("k_N_m", "N/m", "stiffness used (not identified by velocities)", k),
         Column::Numbers("b_N_s_m", "N s/m", "damping b = 2 zeta sqrt(k m)", b),
         Column::Numbers("mu", "1", "friction coefficient", mu),
         Column::Numbers("mu_se", "1", "its standard error (NaN: only a lower bound)", mu_se),
         Column::Integers("mu_only_lower_bound", "",
                          "1 when sticking contacts bound mu from below only", lower_bound),
         Column::Texts("message", "notes", message)}});
  }
  {
    std::vector<std::string> id, message;
    std::vector<std::int64_t> ok;
    std::vector<double> touch, vxm, vym, vxs, vys, vxse, vyse, wm, ws, wse, zx, zy, zw, ke0, ke1m,
        ke1s;
    for (std::size_t i = 0; i < trials.size(); ++i) {
      const auto& c = comparison.trials[i];
      id.push_back(trials[i].spec.id);
      message.push_back(c.message);
      ok.push_back(c.success ? 1 : 0);
      const auto v = [&](double x) { return c.success ? x : kNaN; };
      touch.push_back(v(c.t_touch_s));
      vxm.push_back(v(c.v_SC_after_meas.x()));
      vym.push_back(v(c.v_SC_after_meas.y()));
      vxs.push_back(v(c.v_SC_after_sim.x()));
      vys.push_back(v(c.v_SC_after_sim.y()));
      vxse.push_back(v(c.v_SC_after_sim_se.x()));
      vyse.push_back(v(c.v_SC_after_sim_se.y()));
      wm.push_back(v(c.w_after_meas));
      ws.push_back(v(c.w_after_sim));
      wse.push_back(v(c.w_after_sim_se));
      zx.push_back(v(c.v_SC_after_z.x()));
      zy.push_back(v(c.v_SC_after_z.y()));
      zw.push_back(v(c.w_after_z));
      ke0.push_back(v(c.kinetic_energy_before_J));
      ke1m.push_back(v(c.kinetic_energy_after_meas_J));
      ke1s.push_back(v(c.kinetic_energy_after_sim_J));
    }
    tables.push_back(Table{
        "trials",
        "Per trial: velocities of C in S and spin after the impact, measured and simulated from "
        "the measured state before (at the measured impact time), their z-scores, and kinetic "
        "energies",
        {Column::Texts("id", "trial id", id),
         Column::Integers("success", "", "1 when compared", ok),
         Column::Texts("message", "why not", message),
         Column::Numbers("t_touch_s", "s", "first touch of the simulation, since frame 0", touch),
         Column::Numbers("v_SC_after_meas_x_m_s", "m/s", "measured, along the surface", vxm),
         Column::Numbers("v_SC_after_meas_y_m_s", "m/s", "measured, normal", vym),
         Column::Numbers("v_SC_after_sim_x_m_s", "m/s", "simulated, along the surface", vxs),
         Column::Numbers("v_SC_after_sim_y_m_s", "m/s", "simulated, normal", vys),
         Column::Numbers("v_SC_after_sim_se_x_m_s", "m/s", "standard error of the simulated value",
                         vxse),
         Column::Numbers("v_SC_after_sim_se_y_m_s", "m/s", "standard error of the simulated value",
                         vyse),
         Column::Numbers("w_after_meas_rad_s", "rad/s", "measured spin after", wm),
         Column::Numbers("w_after_sim_rad_s", "rad/s", "simulated spin after", ws),
         Column::Numbers("w_after_sim_se_rad_s", "rad/s", "standard error of the simulated spin",
                         wse),
         Column::Numbers("z_v_x", "1", "(measured - simulated) / combined standard error", zx),
         Column::Numbers("z_v_y", "1", "(measured - simulated) / combined standard error", zy),
         Column::Numbers("z_w", "1", "(measured - simulated) / combined standard error", zw),
         Column::Numbers("kinetic_energy_before_J", "J", "measured", ke0),
         Column::Numbers("kinetic_energy_after_meas_J", "J", "measured", ke1m),
         Column::Numbers("kinetic_energy_after_sim_J", "J", "simulated", ke1s)}});
  }
  for (std::size_t i = 0; i < trials.size(); ++i) {
    const auto& c = comparison.trials[i];
    if (!c.success) continue;
    const std::size_t markers = trials[i].spec.specimen.markers_B_m.size();
    std::vector<std::int64_t> frame, measured;
    std::vector<double> t, xs, ys, ths, xm, ym, thm, ke;
    std::vector<std::vector<double>> mxs(markers), mys(markers), mxm(markers), mym(markers),
        res(markers), mxw(markers), myw(markers);
    for (std::size_t f = 0; f < c.frames.size(); ++f) {
      const auto& fc = c.frames[f];
      frame.push_back(static_cast<std::int64_t>(f));
      measured.push_back(fc.measured ? 1 : 0);
      t.push_back(fc.t_s);
      xs.push_back(fc.p_WC_sim.x());
      ys.push_back(fc.p_WC_sim.y());
      ths.push_back(fc.theta_W_sim_rad);
      xm.push_back(fc.measured ? fc.p_WC_meas.x() : kNaN);
      ym.push_back(fc.measured ? fc.p_WC_meas.y() : kNaN);
      thm.push_back(fc.measured ? fc.theta_W_meas_rad : kNaN);
      ke.push_back(fc.kinetic_energy_sim_J);
      for (std::size_t m = 0; m < markers; ++m) {
        mxw[m].push_back(fc.markers_W_sim[m].x());
        myw[m].push_back(fc.markers_W_sim[m].y());
        mxs[m].push_back(fc.markers_px_sim[m].x());
        mys[m].push_back(fc.markers_px_sim[m].y());
        mxm[m].push_back(fc.markers_px_meas[m].x());
        mym[m].push_back(fc.markers_px_meas[m].y());
        res[m].push_back(fc.marker_residual_px[m]);
      }
    }
    Table ft{"frames/" + trials[i].spec.id,
             "Per frame: the simulation (from the measured state before impact) against the "
             "measurement, in W (m, rad) and in the image (px)",
             {Column::Integers("frame", "1", "frame index", frame),
              Column::Numbers("t_s", "s", "frame time since frame 0", t),
              Column::Integers("measured", "", "1 when the frame has a measured pose", measured),
              Column::Numbers("p_WC_sim_x_m", "m", "simulated centre of mass", xs),
              Column::Numbers("p_WC_sim_y_m", "m", "simulated centre of mass", ys),
              Column::Numbers("theta_W_sim_rad", "rad", "simulated angle", ths),
              Column::Numbers("p_WC_meas_x_m", "m", "measured centre of mass", xm),
              Column::Numbers("p_WC_meas_y_m", "m", "measured centre of mass", ym),
              Column::Numbers("theta_W_meas_rad", "rad", "measured angle", thm),
              Column::Numbers("kinetic_energy_sim_J", "J", "simulated kinetic energy", ke)}};
    for (std::size_t m = 0; m < markers; ++m) {
      const std::string n = trials[i].spec.specimen.markers_B_m[m].first;
      ft.columns.push_back(
          Column::Numbers(n + "_sim_x_m", "m", "simulated marker centre in W", mxw[m]));
      ft.columns.push_back(
          Column::Numbers(n + "_sim_y_m", "m", "simulated marker centre in W", myw[m]));
      ft.columns.push_back(
          Column::Numbers(n + "_sim_x_px", "px", "simulated marker centre", mxs[m]));
      ft.columns.push_back(
          Column::Numbers(n + "_sim_y_px", "px", "simulated marker centre", mys[m]));
      ft.columns.push_back(Column::Numbers(n + "_meas_x_px", "px",
                                           "tracked marker centre (NaN: not found)", mxm[m]));
      ft.columns.push_back(Column::Numbers(n + "_meas_y_px", "px",
                                           "tracked marker centre (NaN: not found)", mym[m]));
      ft.columns.push_back(
          Column::Numbers(n + "_residual_px", "px", "|tracked - simulated|", res[m]));
    }
    tables.push_back(std::move(ft));
    tables.push_back(
        Table{"energy/" + trials[i].spec.id,
              "Simulated kinetic energy through the contact (paper Figure 8)",
              {Column::Numbers("t_since_touch_s", "s", "time since first touch", c.contact_t_s),
               Column::Numbers("kinetic_energy_J", "J", "kinetic energy of the body",
                               c.contact_kinetic_energy_J)}});
  }
  return tables;
}

std::vector<std::pair<std::string, std::string>> ComparisonLinks(
    const std::vector<pipeline::TrialAnalysis>& trials, const StudyComparison& comparison) {
  std::vector<std::pair<std::string, std::string>> links;
  const std::vector<std::string> groups = studyfile::TrialGroupNames(trials);
  for (std::size_t i = 0; i < trials.size(); ++i) {
    if (!comparison.trials[i].success) continue;
    const std::string trial = "/trials/" + groups[i];
    links.emplace_back(trial + "/comparison_frames", "/comparison/frames/" + trials[i].spec.id);
    links.emplace_back(trial + "/comparison_energy", "/comparison/energy/" + trials[i].spec.id);
  }
  return links;
}

}  // namespace hoof::compare
