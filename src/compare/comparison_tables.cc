#include "compare/comparison_tables.h"

#include <cmath>
#include <cstdint>
#include <type_traits>

#include "core/frames.h"
#include "studyfile/table_archive.h"

namespace hoof::compare {
namespace {

using core::kNaN;
using studyfile::Presence;
using studyfile::Table;
using studyfile::TableReader;
using studyfile::TableWriter;

constexpr const char* kGroup = "/comparison";

/// The columns of `/comparison/surfaces`.
template <class Archive, class M>
requires std::is_same_v<std::remove_const_t<M>, SurfaceModel>
void Serialize(Archive& a, M& m) {
  a.Text("surface", m.surface, "surface name");
  a.Integer("normal_trials", m.normal_trials, "1", "normal (0 deg) trials used");
  a.Integer("oblique_trials", m.oblique_trials, "1", "oblique trials used");
  a.Flag("success", m.success, "1 when the model could be fitted");
  a.Number("zeta", m.zeta_fit.zeta, "1", "damping ratio");
  a.Number("zeta_se", m.zeta_fit.zeta_se, "1", "its standard error");
  a.Number("zeta_ci_low", m.zeta_fit.zeta_ci_low, "1", "95 % interval, low");
  a.Number("zeta_ci_high", m.zeta_fit.zeta_ci_high, "1", "95 % interval, high");
  a.Number("k_N_m", m.k_N_m, "N/m",
           "stiffness used (not identified by velocities; NaN where the mass is unknown)");
  a.Number("b_N_s_m", m.b_N_s_m, "N s/m",
           "damping b = 2 zeta sqrt(k m) (NaN where the mass is unknown)");
  a.Flag("mass_known", m.mass_known,
         "1 when every trial's mass is known; 0: a ball of unknown mass, simulated at the "
         "reference mass (k and b not given)",
         Presence::kAddedLater);
  a.Number("mu", m.mu, "1", "friction coefficient");
  a.Number("mu_se", m.mu_se, "1", "its standard error (NaN: only a lower bound)");
  a.Flag("mu_only_lower_bound", m.mu_only_lower_bound,
         "1 when sticking contacts bound mu from below only");
  a.Text("message", m.message, "notes");
}

/// The columns of `/comparison/trials`.
template <class Archive, class T>
requires std::is_same_v<std::remove_const_t<T>, ComparedTrial>
void Serialize(Archive& a, T& t) {
  auto& c = t.comparison;
  a.Text("id", t.id, "trial id");
  a.Flag("success", c.success, "1 when compared");
  a.Text("message", c.message, "why not");
  a.Number("t_touch_s", c.t_touch_s, "s", "first touch of the simulation, since frame 0");
  a.Number("v_SC_after_meas_x_m_s", c.v_SC_after_meas[0], "m/s", "measured, along the surface");
  a.Number("v_SC_after_meas_y_m_s", c.v_SC_after_meas[1], "m/s", "measured, normal");
  a.Number("v_SC_after_sim_x_m_s", c.v_SC_after_sim[0], "m/s", "simulated, along the surface");
  a.Number("v_SC_after_sim_y_m_s", c.v_SC_after_sim[1], "m/s", "simulated, normal");
  a.Number("v_SC_after_sim_se_x_m_s", c.v_SC_after_sim_se[0], "m/s",
           "standard error of the simulated value");
  a.Number("v_SC_after_sim_se_y_m_s", c.v_SC_after_sim_se[1], "m/s",
           "standard error of the simulated value");
  a.Number("w_after_meas_rad_s", c.w_after_meas, "rad/s", "measured spin after");
  a.Number("w_after_sim_rad_s", c.w_after_sim, "rad/s", "simulated spin after");
  a.Number("w_after_sim_se_rad_s", c.w_after_sim_se, "rad/s",
           "standard error of the simulated spin");
  a.Number("z_v_x", c.v_SC_after_z[0], "1", "(measured - simulated) / combined standard error");
  a.Number("z_v_y", c.v_SC_after_z[1], "1", "(measured - simulated) / combined standard error");
  a.Number("z_w", c.w_after_z, "1", "(measured - simulated) / combined standard error");
  a.Number("kinetic_energy_before_J", c.kinetic_energy_before_J, "J", "measured");
  a.Number("kinetic_energy_after_meas_J", c.kinetic_energy_after_meas_J, "J", "measured");
  a.Number("kinetic_energy_after_sim_J", c.kinetic_energy_after_sim_J, "J", "simulated");
  a.Flag("mass_known", c.mass_known,
         "1 when the trial's mass is known (0: energies NaN, simulated at the reference mass)",
         Presence::kAddedLater);
  a.Flag("inertia_assumed", c.inertia_assumed,
         "1 when a ball of unknown inertia was simulated as a solid sphere (2/5 m R^2)",
         Presence::kAddedLater);
}

/// A row of `/comparison/frames/<id>`: the frame's index and its comparison.
struct FrameRow {
  std::int64_t frame = 0;
  FrameComparison f;
};

/// The columns of `/comparison/frames/<id>`; `markers` names the layout's markers, whose
/// columns follow the body's.
template <class Archive, class R>
requires std::is_same_v<std::remove_const_t<R>, FrameRow>
void Serialize(Archive& a, R& row, const std::vector<std::string>& markers) {
  auto& f = row.f;
  a.Integer("frame", row.frame, "1", "frame index");
  a.Number("t_s", f.t_s, "s", "frame time since frame 0");
  a.Flag("measured", f.measured, "1 when the frame has a measured pose");
  a.Number("p_WC_sim_x_m", f.p_WC_sim[0], "m", "simulated centre of mass");
  a.Number("p_WC_sim_y_m", f.p_WC_sim[1], "m", "simulated centre of mass");
  a.Number("theta_W_sim_rad", f.theta_W_sim_rad, "rad", "simulated angle");
  a.Number("p_WC_meas_x_m", f.p_WC_meas[0], "m", "measured centre of mass");
  a.Number("p_WC_meas_y_m", f.p_WC_meas[1], "m", "measured centre of mass");
  a.Number("theta_W_meas_rad", f.theta_W_meas_rad, "rad", "measured angle");
  a.Number("kinetic_energy_sim_J", f.kinetic_energy_sim_J, "J", "simulated kinetic energy");
  // Named so that no column of C ends like a marker's ("<marker>_sim_x_px").
  a.Number("centre_px_sim_x", f.centre_px_sim[0], "px", "simulated centre of mass C, image",
           Presence::kAddedLater);
  a.Number("centre_px_sim_y", f.centre_px_sim[1], "px", "simulated centre of mass C, image",
           Presence::kAddedLater);
  a.Number("centre_px_meas_x", f.centre_px_meas[0], "px",
           "measured centre of mass C, image (NaN: no measured pose)", Presence::kAddedLater);
  a.Number("centre_px_meas_y", f.centre_px_meas[1], "px",
           "measured centre of mass C, image (NaN: no measured pose)", Presence::kAddedLater);
  a.Number("centre_residual_px", f.centre_residual_px, "px", "|measured - simulated| of C",
           Presence::kAddedLater);
  for (std::size_t m = 0; m < markers.size(); ++m) {
    const std::string& n = markers[m];
    a.Number(n + "_sim_x_m", f.markers_W_sim[m][0], "m", "simulated marker centre in W");
    a.Number(n + "_sim_y_m", f.markers_W_sim[m][1], "m", "simulated marker centre in W");
    a.Number(n + "_sim_x_px", f.markers_px_sim[m][0], "px", "simulated marker centre");
    a.Number(n + "_sim_y_px", f.markers_px_sim[m][1], "px", "simulated marker centre");
    a.Number(n + "_meas_x_px", f.markers_px_meas[m][0], "px",
             "tracked marker centre (NaN: not found)");
    a.Number(n + "_meas_y_px", f.markers_px_meas[m][1], "px",
             "tracked marker centre (NaN: not found)");
    a.Number(n + "_residual_px", f.marker_residual_px[m], "px", "|tracked - simulated|");
  }
}

/// A row of `/comparison/energy/<id>`.
struct EnergyRow {
  double t_since_touch_s = 0.0, kinetic_energy_J = 0.0;
};

template <class Archive, class R>
requires std::is_same_v<std::remove_const_t<R>, EnergyRow>
void Serialize(Archive& a, R& row) {
  a.Number("t_since_touch_s", row.t_since_touch_s, "s", "time since first touch");
  a.Number("kinetic_energy_J", row.kinetic_energy_J, "J", "kinetic energy of the body");
}

/// "<file>: table <path>", how the readers name a table in errors.
std::string Where(const std::filesystem::path& h5, const std::string& path) {
  return h5.string() + ": table " + path;
}

std::vector<std::string> MarkerNames(const pipeline::TrialAnalysis& trial) {
  std::vector<std::string> names;
  for (const auto& [name, p_B] : ComparedMarkers(trial)) names.push_back(name);
  return names;
}

/// The rows of a frames table with the markers `markers`.
std::vector<FrameComparison> ReadFrames(const Table& table, const std::string& where,
                                        const std::vector<std::string>& markers) {
  const auto rows = TableReader::Read<FrameRow>(table, where, [&](auto& a, FrameRow& row) {
    row.f.markers_W_sim.resize(markers.size());
    row.f.markers_px_sim.resize(markers.size());
    row.f.markers_px_meas.resize(markers.size());
    row.f.marker_residual_px.resize(markers.size());
    Serialize(a, row, markers);
  });
  std::vector<FrameComparison> frames;
  for (const FrameRow& row : rows) frames.push_back(row.f);
  return frames;
}

}  // namespace

namespace {

/// The table `surfaces`: each surface's contact law (NaN where it could not be fitted).
Table SurfacesTable(const StudyComparison& comparison) {
  std::vector<SurfaceModel> surfaces;
  for (const auto& [name, model] : comparison.surfaces) {
    SurfaceModel m = model;
    m.surface = name;
    if (!m.success)  // a model that could not be fitted has no values
      m.zeta_fit.zeta = m.zeta_fit.zeta_se = m.zeta_fit.zeta_ci_low = m.zeta_fit.zeta_ci_high =
          m.k_N_m = m.b_N_s_m = m.mu = m.mu_se = kNaN;
    if (!m.mass_known)  // those of the reference mass, not the body's
      m.k_N_m = m.b_N_s_m = kNaN;
    surfaces.push_back(std::move(m));
  }
  return TableWriter::Of(
      "surfaces",
      "Contact law per surface fitted to the measurements: zeta from the normal trials (k is "
      "not identified; the paper's k is used), mu from the oblique trials (least squares of "
      "tangential velocity and spin after impact)",
      surfaces, [](auto& a, const SurfaceModel& m) { Serialize(a, m); });
}

/// The table `trials`: each trial's velocities after impact, measured and simulated, with z and
/// energies (NaN for a trial not compared).
Table TrialsTable(const std::vector<pipeline::TrialAnalysis>& trials,
                  const StudyComparison& comparison) {
  std::vector<ComparedTrial> rows;
  for (std::size_t i = 0; i < trials.size(); ++i) {
    const TrialComparison& c = comparison.trials[i];
    ComparedTrial row{trials[i].spec.id, {}};
    row.comparison.success = c.success;
    row.comparison.message = c.message;
    const auto v = [&](double x) { return c.success ? x : kNaN; };
    row.comparison.t_touch_s = v(c.t_touch_s);
    row.comparison.v_SC_after_meas = c.v_SC_after_meas.unaryExpr(v);
    row.comparison.v_SC_after_sim = c.v_SC_after_sim.unaryExpr(v);
    row.comparison.v_SC_after_sim_se = c.v_SC_after_sim_se.unaryExpr(v);
    row.comparison.w_after_meas = v(c.w_after_meas);
    row.comparison.w_after_sim = v(c.w_after_sim);
    row.comparison.w_after_sim_se = v(c.w_after_sim_se);
    row.comparison.v_SC_after_z = c.v_SC_after_z.unaryExpr(v);
    row.comparison.w_after_z = v(c.w_after_z);
    row.comparison.kinetic_energy_before_J = v(c.kinetic_energy_before_J);
    row.comparison.kinetic_energy_after_meas_J = v(c.kinetic_energy_after_meas_J);
    row.comparison.kinetic_energy_after_sim_J = v(c.kinetic_energy_after_sim_J);
    row.comparison.mass_known = c.mass_known;
    row.comparison.inertia_assumed = c.inertia_assumed;
    rows.push_back(std::move(row));
  }
  return TableWriter::Of(
      "trials",
      "Per trial: velocities of C in S and spin after the impact, measured and simulated from "
      "the measured state before (at the measured impact time), their z-scores, and kinetic "
      "energies",
      rows, [](auto& a, const ComparedTrial& t) { Serialize(a, t); });
}

/// The tables `frames/<id>` and `energy/<id>` of one compared trial.
void TrialTables(const pipeline::TrialAnalysis& trial, const TrialComparison& c,
                 std::vector<Table>& tables) {
  const std::vector<std::string> markers = MarkerNames(trial);
  std::vector<FrameRow> frames;
  for (std::size_t f = 0; f < c.frames.size(); ++f) {
    FrameRow row{static_cast<std::int64_t>(f), c.frames[f]};
    if (!row.f.measured) {  // no measured pose: NaN, whatever the struct holds
      row.f.p_WC_meas = {kNaN, kNaN};
      row.f.theta_W_meas_rad = kNaN;
    }
    frames.push_back(std::move(row));
  }
  // The column list of a frame names every marker, so the declaration visits a frame that has
  // them all.
  FrameRow declared;
  declared.f.markers_W_sim.resize(markers.size());
  declared.f.markers_px_sim.resize(markers.size());
  declared.f.markers_px_meas.resize(markers.size());
  declared.f.marker_residual_px.resize(markers.size());
  tables.push_back(TableWriter::Of(
      "frames/" + trial.spec.id,
      "Per frame: the simulation (from the measured state before impact) against the "
      "measurement, in W (m, rad) and in the image (px)",
      frames, [&](auto& a, const FrameRow& row) { Serialize(a, row, markers); }, declared));
  std::vector<EnergyRow> energy;
  for (std::size_t k = 0; k < c.contact_t_s.size(); ++k)
    energy.push_back({c.contact_t_s[k], c.contact_kinetic_energy_J[k]});
  tables.push_back(TableWriter::Of("energy/" + trial.spec.id,
                                   "Simulated kinetic energy through the contact (paper Figure 8)",
                                   energy, [](auto& a, const EnergyRow& e) { Serialize(a, e); }));
}

}  // namespace

std::vector<Table> ComparisonTables(const std::vector<pipeline::TrialAnalysis>& trials,
                                    const StudyComparison& comparison) {
  std::vector<Table> tables = {SurfacesTable(comparison), TrialsTable(trials, comparison)};
  for (std::size_t i = 0; i < trials.size(); ++i)
    if (comparison.trials[i].success) TrialTables(trials[i], comparison.trials[i], tables);
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

bool HasComparison(const std::filesystem::path& h5) {
  try {
    studyfile::ReadTable(h5, std::string(kGroup) + "/trials");
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

std::vector<SurfaceModel> ReadSurfaceModels(const std::filesystem::path& h5) {
  const std::string path = std::string(kGroup) + "/surfaces";
  return TableReader::Read<SurfaceModel>(studyfile::ReadTable(h5, path), Where(h5, path),
                                         [](auto& a, SurfaceModel& m) { Serialize(a, m); });
}

std::vector<ComparedTrial> ReadComparedTrials(const std::filesystem::path& h5) {
  const std::string path = std::string(kGroup) + "/trials";
  return TableReader::Read<ComparedTrial>(studyfile::ReadTable(h5, path), Where(h5, path),
                                          [](auto& a, ComparedTrial& t) { Serialize(a, t); });
}

std::vector<FrameComparison> ReadComparedFrames(const std::filesystem::path& h5,
                                                const std::string& id,
                                                const std::vector<std::string>& marker_names) {
  const std::string path = std::string(kGroup) + "/frames/" + id;
  return ReadFrames(studyfile::ReadTable(h5, path), Where(h5, path), marker_names);
}

ComparedFrames ReadComparedFrames(const std::filesystem::path& h5, const std::string& id) {
  const std::string path = std::string(kGroup) + "/frames/" + id;
  const Table table = studyfile::ReadTable(h5, path);
  ComparedFrames out;
  const std::string suffix = "_sim_x_px";  // the first pixel column of each marker's group
  for (const auto& c : table.columns)
    if (c.name.size() > suffix.size() && c.name.ends_with(suffix))
      out.markers.push_back(c.name.substr(0, c.name.size() - suffix.size()));
  out.frames = ReadFrames(table, Where(h5, path), out.markers);
  return out;
}

void ReadContactEnergy(const std::filesystem::path& h5, const std::string& id,
                       TrialComparison& comparison) {
  const std::string path = std::string(kGroup) + "/energy/" + id;
  const auto rows = TableReader::Read<EnergyRow>(studyfile::ReadTable(h5, path), Where(h5, path),
                                                 [](auto& a, EnergyRow& e) { Serialize(a, e); });
  comparison.contact_t_s.clear();
  comparison.contact_kinetic_energy_J.clear();
  for (const EnergyRow& e : rows) {
    comparison.contact_t_s.push_back(e.t_since_touch_s);
    comparison.contact_kinetic_energy_J.push_back(e.kinetic_energy_J);
  }
}

}  // namespace hoof::compare
