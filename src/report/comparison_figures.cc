#include "report/comparison_figures.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

#include "compare/comparison_tables.h"
#include "compare/trial_comparison.h"
#include "io/atomic_file.h"
#include "report/gnuplot.h"
#include "studyfile/study_file.h"

namespace hoof::report {
namespace {

void Render(const Plot& plot, const std::filesystem::path& dir, const std::string& name,
            std::vector<std::filesystem::path>& written) {
  for (auto& path : WriteFigure(plot, dir, name)) written.push_back(std::move(path));
}

Series Styled(std::string title, std::vector<double> x, std::vector<double> y, std::string style,
              std::string options) {
  Series s;
  s.title = std::move(title);
  s.x = std::move(x);
  s.y = std::move(y);
  s.style = std::move(style);
  s.options = std::move(options);
  return s;
}

std::vector<std::string> SurfacesOf(const studyfile::StudyResults& study) {
  std::vector<std::string> surfaces;
  for (const auto& t : study.trials)
    if (std::find(surfaces.begin(), surfaces.end(), t.surface) == surfaces.end() &&
        !t.surface.empty())
      surfaces.push_back(t.surface);
  return surfaces;
}

}  // namespace

VelocityPlots MakeVelocityPlots(const studyfile::StudyResults& study, const ComparedById& row) {
  const std::vector<std::string> surfaces = SurfacesOf(study);
  VelocityPlots plots;
  Plot& normal = plots.normal;
  Plot& oblique = plots.oblique;
  normal.title =
      "Velocity of C after normal impacts: measured and simulated\n"
      "bars ±1 s.e. (measured: flight fits; simulated: propagated)";
  normal.x_label = "normal impact speed of C before (m/s)";
  normal.y_label = "normal velocity of C after (m/s)";
  normal.key = "outside right top";
  oblique.title =
      "Velocity of C after oblique impacts: measured against simulated\n"
      "bars ±1 s.e. (measured: flight fits; simulated: propagated)";
  oblique.x_label = "simulated velocity of C after (m/s)";
  oblique.y_label = "measured velocity of C after (m/s)";
  oblique.key = "outside right top";
  double lo = 1e9, hi = -1e9;
  for (std::size_t s = 0; s < surfaces.size(); ++s) {
    static const char* const kColours[] = {"#1f77b4", "#d62728", "#2ca02c",
                                           "#9467bd", "#ff7f0e", "#8c564b"};
    const std::string colour = kColours[s % 6];
    Series nm =
        Styled(surfaces[s] + " measured", {}, {}, "points", "pt 7 ps 1.0 lc rgb '" + colour + "'");
    Series ns =
        Styled(surfaces[s] + " simulated", {}, {}, "points", "pt 6 ps 2.0 lc rgb '" + colour + "'");
    Series ox = Styled(surfaces[s] + " along the surface", {}, {}, "points",
                       "pt 5 ps 1.0 lc rgb '" + colour + "'");
    Series oy =
        Styled(surfaces[s] + " normal", {}, {}, "points", "pt 9 ps 1.2 lc rgb '" + colour + "'");
    for (const auto& t : study.trials) {
      const auto it = row.find(t.id);
      if (t.surface != surfaces[s] || !t.success || it == row.end() ||
          !std::isfinite(it->second.v_SC_after_sim.y()))
        continue;
      const Eigen::Vector2d& meas = it->second.v_SC_after_meas;
      const Eigen::Vector2d& sim = it->second.v_SC_after_sim;
      const Eigen::Vector2d& meas_se = t.v_SC_after_se_m_s;
      const Eigen::Vector2d& sim_se = it->second.v_SC_after_sim_se;
      const auto add = [](Series& series, double x, double x_se, double y, double y_se) {
        series.x.push_back(x);
        series.x_error.push_back(x_se);
        series.y.push_back(y);
        series.y_error.push_back(y_se);
      };
      if (std::abs(t.surface_angle_deg) < 1e-9) {
        const double speed = std::abs(t.v_SC_before_m_s.y()), speed_se = t.v_SC_before_se_m_s.y();
        add(nm, speed, speed_se, meas.y(), meas_se.y());
        add(ns, speed, speed_se, sim.y(), sim_se.y());
      } else {
        add(ox, sim.x(), sim_se.x(), meas.x(), meas_se.x());
        add(oy, sim.y(), sim_se.y(), meas.y(), meas_se.y());
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
  if (!oblique.series.empty()) {
    const double pad = 0.05 * (hi - lo + 1e-9);
    oblique.series.push_back(Styled("measured = simulated", {lo - pad, hi + pad},
                                    {lo - pad, hi + pad}, "lines", "dt 2 lc rgb '#777777'"));
  }
  return plots;
}

namespace {

/// Figures 6 and 7 (MakeVelocityPlots), each when it has a point.
void VelocityFigures(const studyfile::StudyResults& study, const ComparedById& row,
                     const std::filesystem::path& dir,
                     std::vector<std::filesystem::path>& written) {
  const VelocityPlots plots = MakeVelocityPlots(study, row);
  if (!plots.normal.series.empty()) Render(plots.normal, dir, "velocity_normal", written);
  if (!plots.oblique.series.empty()) Render(plots.oblique, dir, "velocity_oblique", written);
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
    // No error bars: the study file keeps no standard error of a kinetic energy.
    p.title = t.id + ": kinetic energy through the impact";
    p.x_label = "time since first touch (µs)";
    p.y_label = "kinetic energy (mJ)";
    p.key = "outside right top";
    Series sim = Styled("simulated", {}, {}, "lines", "lw 2 lc rgb '#1f77b4'");
    for (std::size_t k = 0; k < c.contact_t_s.size(); ++k) {
      sim.x.push_back(1e6 * c.contact_t_s[k]);
      sim.y.push_back(1e3 * c.contact_kinetic_energy_J[k]);
    }
    const double t0 = sim.x.front(), t1 = sim.x.back();
    Series before = Styled("measured before", {t0, 0.0}, {1e3 * ke0, 1e3 * ke0}, "lines",
                           "lw 2 dt 2 lc rgb '#d62728'");
    Series after = Styled("measured after", {0.5 * t1, t1}, {1e3 * ke1, 1e3 * ke1}, "lines",
                          "lw 2 dt 2 lc rgb '#2ca02c'");
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
  std::vector<std::filesystem::path> written;
  io::CreateFolder(dir);  // `dir` may be the report's temporary folder
  VelocityFigures(study, row, dir, written);
  EnergyFigures(study_h5, study, row, dir, written);
  return written;
}

}  // namespace hoof::report
