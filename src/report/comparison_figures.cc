#include "report/comparison_figures.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

#include "compare/comparison_tables.h"
#include "io/atomic_file.h"
#include "report/gnuplot.h"
#include "studyfile/study_file.h"

namespace hoof::report {
namespace {

void Render(const Plot& plot, const std::filesystem::path& dir, const std::string& name,
            std::vector<std::filesystem::path>& written) {
  for (const char* ext : {".png", ".svg"}) {
    const auto path = dir / (name + ext);
    RenderPlot(plot, path);
    written.push_back(path);
  }
}

/// Velocities after impact by trial id, from /comparison/trials.
using ComparedById = std::map<std::string, compare::TrialComparison>;

/// Figures 6 and 7 (the paper's): the velocity of C after normal impacts against the impact
/// speed, measured and simulated; and after oblique impacts, measured against simulated.
void VelocityFigures(const studyfile::StudyResults& study, const ComparedById& row,
                     const std::vector<std::string>& surfaces, const std::filesystem::path& dir,
                     std::vector<std::filesystem::path>& written) {
  Plot normal;
  normal.title = "Velocity of C after normal impacts: measured and simulated";
  normal.x_label = "impact speed |v_{C,y}| before (m/s)";
  normal.y_label = "normal velocity of C after (m/s)";
  normal.key = "outside right top";
  Plot oblique;
  oblique.title = "Velocity of C after oblique impacts: measured against simulated";
  oblique.x_label = "simulated (m/s)";
  oblique.y_label = "measured (m/s)";
  oblique.key = "outside right top";
  double lo = 1e9, hi = -1e9;
  for (std::size_t s = 0; s < surfaces.size(); ++s) {
    Series nm{surfaces[s] + " measured", {}, {}, {}, "points", ""};
    Series ns{surfaces[s] + " simulated", {}, {}, {}, "points", ""};
    Series ox{surfaces[s] + " along the surface", {}, {}, {}, "points", ""};
    Series oy{surfaces[s] + " normal", {}, {}, {}, "points", ""};
    const std::string colour = s == 0 ? "#1f77b4" : s == 1 ? "#d62728" : "#2ca02c";
    nm.options = "pt 7 ps 1.2 lc rgb '" + colour + "'";
    ns.options = "pt 6 ps 1.6 lc rgb '" + colour + "'";
    ox.options = "pt 5 ps 1.0 lc rgb '" + colour + "'";
    oy.options = "pt 9 ps 1.2 lc rgb '" + colour + "'";
    for (const auto& t : study.trials) {
      const auto it = row.find(t.id);
      if (t.surface != surfaces[s] || !t.success || it == row.end() ||
          !std::isfinite(it->second.v_SC_after_sim.y()))
        continue;
      const Eigen::Vector2d& meas = it->second.v_SC_after_meas;
      const Eigen::Vector2d& sim = it->second.v_SC_after_sim;
      if (std::abs(t.surface_angle_deg) < 1e-9) {
        nm.x.push_back(std::abs(t.v_SC_before_m_s.y()));
        nm.y.push_back(meas.y());
        ns.x.push_back(std::abs(t.v_SC_before_m_s.y()));
        ns.y.push_back(sim.y());
      } else {
        ox.x.push_back(sim.x());
        ox.y.push_back(meas.x());
        oy.x.push_back(sim.y());
        oy.y.push_back(meas.y());
        for (double v : {sim.x(), meas.x(), sim.y(), meas.y()}) {
          lo = std::min(lo, v);
          hi = std::max(hi, v);
        }
      }
    }
    if (!nm.x.empty()) {
      normal.series.push_back(nm);
      normal.series.push_back(ns);
    }
    if (!ox.x.empty()) {
      oblique.series.push_back(ox);
      oblique.series.push_back(oy);
    }
  }
  if (!normal.series.empty()) Render(normal, dir, "velocity_normal", written);
  if (!oblique.series.empty()) {
    const double pad = 0.05 * (hi - lo + 1e-9);
    oblique.series.push_back(
        {"measured = simulated", {lo - pad, hi + pad}, {lo - pad, hi + pad}, {}, "lines", ""});
    oblique.series.back().options = "dt 2 lc rgb '#777777'";
    Render(oblique, dir, "velocity_oblique", written);
  }
}

/// Figure 8: the kinetic energy through the contact, simulated, against the measured energies
/// before and after, for the first oblique trial of each surface.
void EnergyFigures(const std::filesystem::path& study_h5, const studyfile::StudyResults& study,
                   const ComparedById& row, const std::filesystem::path& dir,
                   std::vector<std::filesystem::path>& written) {
  std::set<std::string> done;
  for (const auto& t : study.trials) {
    const auto it = row.find(t.id);
    if (!t.success || it == row.end() || std::abs(t.surface_angle_deg) < 1e-9 ||
        done.count(t.surface))
      continue;
    compare::TrialComparison c = it->second;
    const double ke0 = c.kinetic_energy_before_J, ke1 = c.kinetic_energy_after_meas_J;
    if (!std::isfinite(ke0)) continue;
    try {
      compare::ReadContactEnergy(study_h5, t.id, c);
    } catch (const std::runtime_error&) {
      continue;
    }
    done.insert(t.surface);
    Plot p;
    p.title = t.id + ": kinetic energy through the impact";
    p.x_label = "time since first touch (µs)";
    p.y_label = "kinetic energy (mJ)";
    p.key = "outside right top";
    Series sim{"simulated", {}, {}, {}, "lines", ""};
    sim.options = "lw 2 lc rgb '#1f77b4'";
    for (std::size_t k = 0; k < c.contact_t_s.size(); ++k) {
      sim.x.push_back(1e6 * c.contact_t_s[k]);
      sim.y.push_back(1e3 * c.contact_kinetic_energy_J[k]);
    }
    const double t0 = sim.x.front(), t1 = sim.x.back();
    Series before{"measured before", {t0, 0.0}, {1e3 * ke0, 1e3 * ke0}, {}, "lines", ""};
    before.options = "lw 2 dt 2 lc rgb '#d62728'";
    Series after{"measured after", {0.5 * t1, t1}, {1e3 * ke1, 1e3 * ke1}, {}, "lines", ""};
    after.options = "lw 2 dt 2 lc rgb '#2ca02c'";
    p.series = {sim, before, after};
    Render(p, dir, "energy_" + t.id, written);
  }
}

}  // namespace

std::vector<std::filesystem::path> WriteComparisonFigures(const std::filesystem::path& study_h5,
                                                          const std::filesystem::path& dir) {
  const studyfile::StudyResults study = studyfile::ReadStudyResults(study_h5);
  ComparedById row;
  for (compare::ComparedTrial& t : compare::ReadComparedTrials(study_h5))
    row[t.id] = std::move(t.comparison);
  std::vector<std::string> surfaces;
  for (const auto& t : study.trials)
    if (std::find(surfaces.begin(), surfaces.end(), t.surface) == surfaces.end() &&
        !t.surface.empty())
      surfaces.push_back(t.surface);
  std::vector<std::filesystem::path> written;
  io::CreateFolder(dir);  // `dir` may be the report's temporary folder
  VelocityFigures(study, row, surfaces, dir, written);
  EnergyFigures(study_h5, study, row, dir, written);
  return written;
}

}  // namespace hoof::report
