#include "studyfile/study_file.h"

#include <H5Cpp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <ctime>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "core/frames.h"
#include "io/atomic_file.h"
#include "io/csv.h"
#include "io/interrupt.h"
#include "studyfile/hdf5_util.h"
#include "studyfile/schema.h"

#ifndef HOOF_VERSION
#define HOOF_VERSION "unknown"
#endif

namespace hoof::studyfile {
namespace {

using core::kNaN;
using internal::GroupReader;
using internal::ShapeText;

std::string Join(const std::vector<std::string>& parts, const std::string& separator) {
  std::string out;
  for (std::size_t i = 0; i < parts.size(); ++i) out += (i ? separator : "") + parts[i];
  return out;
}

/// Throws std::runtime_error naming `path` for an HDF5 exception (which is no std::exception).
[[noreturn]] void RethrowHdf5(const H5::Exception& e, const std::filesystem::path& path) {
  // The commonest cause first: a file that is not HDF5 at all (HDF5 only says "H5Fopen failed").
  if (std::filesystem::is_regular_file(path) && H5Fis_hdf5(path.string().c_str()) == 0)
    throw std::runtime_error(path.string() +
                             " is not an HDF5 file (study files are written by hoofimpact "
                             "analyze and hoofimpact run)");
  // A file with HDF5's signature that does not open: most often one cut short by a copy or a
  // killed writer (hoofimpact itself only ever renames complete files into place).
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(path, ec);
  if (e.getFuncName().find("H5File") != std::string::npos)
    throw std::runtime_error(path.string() +
                             ": cannot be opened: the HDF5 file is damaged or cut short (" +
                             (ec ? std::string("size unknown") : std::to_string(bytes) + " bytes") +
                             "); write it again with hoofimpact analyze or run");
  throw std::runtime_error(path.string() + ": cannot be read, the HDF5 file is damaged (in " +
                           e.getFuncName() + ": " + e.getDetailMsg() + ")");
}

/// Runs `write` on a temporary file beside `path` and renames it over `path`; removes the
/// temporary file on any failure. `prepare(tmp)` makes the temporary file (copy or nothing).
void AtomicHdf5(const std::filesystem::path& path,
                const std::function<void(const std::filesystem::path&)>& prepare,
                const std::function<void(const std::filesystem::path&)>& write) {
  H5::Exception::dontPrint();
  // Held while the temporary is made and written (HDF5 creates it inside `write`): an interrupt
  // waits for it rather than leave one made after its removal.
  const io::CreatingTemporary creating;
  if (path.has_parent_path()) {
    std::error_code ec;
    std::filesystem::create_directories(path.parent_path(), ec);
    if (ec)
      throw std::runtime_error("cannot create directory " + path.parent_path().string() + ": " +
                               ec.message());
  }
  const std::filesystem::path tmp = io::TemporaryPathFor(path);
  try {
    try {
      prepare(tmp);
      write(tmp);  // every H5 object is closed when this returns or throws
    } catch (const H5::Exception& e) {
      RethrowHdf5(e, path);
    }
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw;
  }
  io::CommitTemporary(tmp, path);
}

// ------------------------------------------------------------------------------------------
// Study info
// ------------------------------------------------------------------------------------------

void WriteStudyInfo(H5::H5File& file, const StudyInfo& info) {
  const H5::Group root = file.openGroup("/");
  h5::SetAttr(root, "format", std::string(kStudyFileFormat));
  h5::SetAttr(root, "name", info.name);
  h5::SetAttr(root, "study_dir", info.study_dir.string());
  h5::SetAttr(
      root, "hoofimpact_version",
      info.hoofimpact_version.empty() ? std::string(HOOF_VERSION) : info.hoofimpact_version);
  h5::SetAttr(root, "created_utc", info.created_utc.empty() ? NowUtc() : info.created_utc);
  h5::SetAttr(root, "command_line", info.command_line);
  h5::SetAttr(root, "description",
              std::string("hoofimpact study file: hoof-wall impacts measured from high-speed "
                          "frames; layout in docs/hdf5-schema.md"));
  const H5::Group study = h5::MakeGroup(root, "study", "the study as a whole");
  h5::Texts(study, "warnings", info.warnings, {info.warnings.size()}, "study-level warnings");
  const H5::Group specimens = h5::MakeGroup(study, "specimens", "specimens of study.json");
  for (const auto& [id, spec] : info.specimens) {
    internal::H5Writer a(h5::MakeGroup(specimens, id, "specimen " + id));
    internal::Serialize(a, spec);
  }
  internal::H5Writer options(
      h5::MakeGroup(study, "analysis_options", "options every trial was analysed with"));
  internal::Serialize(options, info.options);
}

// ------------------------------------------------------------------------------------------
// One trial
// ------------------------------------------------------------------------------------------

void WriteTracks(const H5::Group& g, const pipeline::TrialAnalysis& r) {
  const auto& t = r.tracks;
  const std::size_t F = t.frames.size(), M = t.names.size();
  std::vector<double> p(F * M * 2, kNaN), quality(F * M, 0.0), radius(F * M, kNaN), time(F);
  std::vector<std::uint8_t> found(F * M, 0);
  std::vector<std::string> status(F * M);
  for (std::size_t f = 0; f < F; ++f) {
    time[f] = r.spec.fps > 0 ? static_cast<double>(f) / r.spec.fps : kNaN;
    for (std::size_t m = 0; m < M && m < t.frames[f].size(); ++m) {
      const auto& o = t.frames[f][m];
      const std::size_t i = f * M + m;
      found[i] = o.found ? 1 : 0;
      status[i] = o.status;
      quality[i] = o.quality;
      if (o.found) {
        p[2 * i] = o.p_I.x();
        p[2 * i + 1] = o.p_I.y();
        radius[i] = o.radius_px;
      }
    }
  }
  h5::Texts(g, "marker_names", t.names, {M}, "marker names, layout order");
  h5::Doubles(g, "t_s", time, {F}, "s", "frame time since frame 0 (frame index / fps)");
  h5::Doubles(g, "p_I_px", p, {F, M, 2}, "px",
              "marker centre in the image frame I (x right, y down), [frame, marker, (x, y)]; "
              "NaN when not found");
  h5::Bools(g, "found", found, {F, M}, "marker found, [frame, marker]");
  h5::Texts(g, "status", status, {F, M}, "ok, lost, merged or lost_for_good, [frame, marker]");
  h5::Doubles(g, "quality", quality, {F, M}, "1",
              "significance (contrast / noise), 0 when not found, [frame, marker]");
  h5::Doubles(g, "radius_px", radius, {F, M}, "px", "dot radius, NaN when not found");
  h5::Texts(g, "warnings", t.warnings, {t.warnings.size()}, "lost or merged markers, per frame");
}

void WritePoses(const H5::Group& g, const pipeline::TrialAnalysis& r) {
  const std::size_t F = r.poses.size();
  std::vector<double> time(F), p(2 * F, kNaN), theta(F, kNaN), rms(F, kNaN), dist(F, kNaN),
      ratio(F, kNaN);
  std::vector<std::uint8_t> valid(F);
  std::vector<std::int32_t> used(F);
  for (std::size_t f = 0; f < F; ++f) {
    const auto& q = r.poses[f];
    time[f] = r.spec.fps > 0 ? static_cast<double>(f) / r.spec.fps : kNaN;
    valid[f] = q.valid ? 1 : 0;
    used[f] = q.markers_used;
    if (q.valid) {
      p[2 * f] = q.p_WE.x();
      p[2 * f + 1] = q.p_WE.y();
      theta[f] = q.theta_W_rad;
      rms[f] = q.rms_residual_m;
      dist[f] = q.marker_distance_m > 0 ? q.marker_distance_m : kNaN;
    }
    if (f < r.marker_distance_ratio.size()) ratio[f] = r.marker_distance_ratio[f];
  }
  h5::Doubles(g, "t_s", time, {F}, "s", "frame time since frame 0");
  h5::Bools(g, "valid", valid, {F}, "pose measured (enough markers found)");
  h5::Doubles(g, "p_WE_m", p, {F, 2}, "m",
              "centre of the round end E in the world frame W (y up), [frame, (x, y)]; NaN when "
              "not valid");
  h5::Doubles(g, "theta_W_rad", theta, {F}, "rad", "angle of x_B from x_W, counter-clockwise");
  h5::Doubles(g, "rms_residual_m", rms, {F}, "m", "misfit of the marker layout to the markers");
  h5::Int32s(g, "markers_used", used, {F}, "1", "markers in the pose fit");
  h5::Doubles(g, "marker_distance_m", dist, {F}, "m",
              "projected distance between the first two markers");
  h5::Doubles(g, "marker_distance_ratio", ratio, {F}, "1",
              "projected / layout marker distance (out-of-plane rotation shrinks it); NaN = "
              "missing");
  h5::Scalar(g, "out_of_plane_change", r.out_of_plane_change, "1",
             "range of marker_distance_ratio over the fit windows");
  h5::Scalar(g, "out_of_plane_noise", r.out_of_plane_noise, "1",
             "noise standard deviation of marker_distance_ratio");
}

void WriteTrial(const H5::Group& trials, const std::string& group_name,
                const pipeline::TrialAnalysis& r) {
  const H5::Group g = h5::MakeGroup(trials, group_name, "trial " + r.spec.id);
  internal::H5Writer outcome(g);
  internal::SerializeOutcome(outcome, r);
  internal::H5Writer metadata(
      h5::MakeGroup(g, "metadata", "trial.json and the calibration checks"));
  internal::SerializeMetadata(metadata, r);
  WriteTracks(h5::MakeGroup(g, "tracks", "raw marker tracks"), r);
  WritePoses(h5::MakeGroup(g, "poses", "body pose per frame"), r);
  h5::Text(g, "impact_message", r.impact.message, "why the impact measurement failed, if it did");
  if (!r.impact.success) return;
  const H5::Group fits = h5::MakeGroup(g, "fits", "free-flight fits before and after the impact");
  internal::H5Writer before(h5::MakeGroup(fits, "before", "fit before the impact"));
  internal::Serialize(before, r.impact.before);
  internal::H5Writer after(h5::MakeGroup(fits, "after", "fit after the impact"));
  internal::Serialize(after, r.impact.after);
  internal::H5Writer results(h5::MakeGroup(g, "results", "the impact in the surface frame S"));
  internal::Serialize(results, r.impact);
}

// ------------------------------------------------------------------------------------------
// Tables
// ------------------------------------------------------------------------------------------

void WriteTable(const H5::Group& parent, const Table& table) {
  const H5::Group g = h5::MakeGroup(parent, table.name, table.description);
  std::vector<std::string> names;
  for (const Column& c : table.columns) {
    names.push_back(c.name);
    const hsize_t n = c.size();
    if (const auto* d = std::get_if<std::vector<double>>(&c.values))
      h5::Doubles(g, c.name, *d, {n}, c.units, c.description);
    else if (const auto* i = std::get_if<std::vector<std::int64_t>>(&c.values))
      h5::Integers(g, c.name, *i, {n}, c.units, c.description);
    else
      h5::Texts(g, c.name, std::get<std::vector<std::string>>(c.values), {n}, c.description);
  }
  h5::SetAttr(g, "columns", names);
  h5::SetAttr(g, "rows",
              static_cast<std::int64_t>(table.columns.empty() ? 0 : table.columns[0].size()));
}

Column ReadColumn(const H5::Group& g, const std::string& name, const std::string& where) {
  if (!g.nameExists(name)) throw std::runtime_error(where + " has no column \"" + name + "\"");
  const H5::DataSet d = g.openDataSet(name);
  const std::string here = where + "/" + name;
  Column c;
  c.name = name;
  c.units = d.attrExists("units") ? h5::GetAttrText(d, "units", here) : "";
  c.description = d.attrExists("description") ? h5::GetAttrText(d, "description", here) : "";
  if (h5::Shape(d).size() != 1) throw std::runtime_error(here + " is not one-dimensional");
  switch (d.getTypeClass()) {
    case H5T_STRING:
      c.values = h5::ReadTexts(d, here);
      break;
    case H5T_INTEGER:
      c.values = h5::ReadIntegers(d, here);
      break;
    default:
      c.values = h5::ReadDoubles(d, here);
      break;
  }
  return c;
}

std::vector<std::string> CheckedStrings(const Table& t, const std::string& name) {
  const Column& c = t.Get(name);
  if (const auto* v = std::get_if<std::vector<std::string>>(&c.values)) return *v;
  throw std::runtime_error(t.name + "/" + name + " is not text");
}

std::vector<double> CheckedNumbers(const Table& t, const std::string& name) {
  const Column& c = t.Get(name);
  if (const auto* v = std::get_if<std::vector<double>>(&c.values)) return *v;
  if (const auto* i = std::get_if<std::vector<std::int64_t>>(&c.values))
    return std::vector<double>(i->begin(), i->end());
  throw std::runtime_error(t.name + "/" + name + " is not numeric");
}

// ------------------------------------------------------------------------------------------
// Reading trials back
// ------------------------------------------------------------------------------------------

/// Throws std::runtime_error naming the file when its root attribute `format` is not ours.
void CheckFormat(const H5::Group& root, const std::filesystem::path& path) {
  const std::string format = h5::GetAttrText(root, "format", path.string());
  if (format != kStudyFileFormat)
    throw std::runtime_error(path.string() + ": format \"" + format + "\", expected \"" +
                             kStudyFileFormat + "\"");
}

tracking::MarkerTracks ReadTracks(const GroupReader& g) {
  tracking::MarkerTracks t;
  t.names = g.TextList("marker_names");
  const hsize_t F = g.Length("t_s"), M = t.names.size();
  const std::vector<double> p = g.Doubles("p_I_px", {F, M, 2});
  const std::vector<std::int64_t> found = g.Integers("found", {F, M});
  const std::vector<std::string> status = g.Texts("status", {F, M});
  const std::vector<double> quality = g.Doubles("quality", {F, M});
  const std::vector<double> radius = g.Doubles("radius_px", {F, M});
  t.frames.assign(F, std::vector<tracking::MarkerObservation>(M));
  for (std::size_t f = 0; f < F; ++f) {
    for (std::size_t m = 0; m < M; ++m) {
      const std::size_t i = f * M + m;
      tracking::MarkerObservation& o = t.frames[f][m];
      o.found = found[i] != 0;
      o.status = status[i];
      o.quality = quality[i];
      if (o.found) {  // the file holds no centre or radius for a marker not found
        o.p_I = {p[2 * i], p[2 * i + 1]};
        o.radius_px = radius[i];
      }
    }
  }
  t.warnings = g.TextList("warnings");
  return t;
}

void ReadPoses(const GroupReader& g, pipeline::TrialAnalysis& r) {
  const hsize_t F = g.Length("t_s");
  const std::vector<std::int64_t> valid = g.Integers("valid", {F});
  const std::vector<double> p = g.Doubles("p_WE_m", {F, 2});
  const std::vector<double> theta = g.Doubles("theta_W_rad", {F});
  const std::vector<double> rms = g.Doubles("rms_residual_m", {F});
  const std::vector<std::int64_t> used = g.Integers("markers_used", {F});
  const std::vector<double> distance = g.Doubles("marker_distance_m", {F});
  r.marker_distance_ratio = g.Doubles("marker_distance_ratio", {F});
  r.poses.assign(F, tracking::BodyPose{});
  for (std::size_t f = 0; f < F; ++f) {
    tracking::BodyPose& q = r.poses[f];
    q.valid = valid[f] != 0;
    q.markers_used = static_cast<int>(used[f]);
    if (q.valid) {  // an invalid pose's numbers are NaN in the file
      q.p_WE = {p[2 * f], p[2 * f + 1]};
      q.theta_W_rad = theta[f];
      q.rms_residual_m = rms[f];
      q.marker_distance_m = std::isnan(distance[f]) ? 0.0 : distance[f];
    }
  }
  r.out_of_plane_change = g.Scalar("out_of_plane_change");
  r.out_of_plane_noise = g.Scalar("out_of_plane_noise");
}

/// One `/trials/<id>` group; the specimen is filled in by the caller.
pipeline::TrialAnalysis ReadTrialGroup(const GroupReader& g) {
  pipeline::TrialAnalysis r;
  internal::SerializeOutcome(internal::H5Reader(g), r);
  internal::SerializeMetadata(internal::H5Reader(g.Group("metadata")), r);
  r.tracks = ReadTracks(g.Group("tracks"));
  ReadPoses(g.Group("poses"), r);
  r.impact.message = g.Text("impact_message");
  if (g.Has("results")) {  // written only when the impact was measured, with the fits
    r.impact.success = true;
    const GroupReader fits = g.Group("fits");
    internal::Serialize(internal::H5Reader(fits.Group("before")), r.impact.before);
    internal::Serialize(internal::H5Reader(fits.Group("after")), r.impact.after);
    internal::Serialize(internal::H5Reader(g.Group("results")), r.impact);
  }
  return r;
}

}  // namespace

StudyInfo StudyInfo::Of(const pipeline::StudySpec& study,
                        const pipeline::TrialAnalysisOptions& options, std::string command_line) {
  StudyInfo info;
  info.name = study.name;
  info.study_dir = std::filesystem::absolute(study.dir);
  info.specimens = study.specimens;
  info.options = options;
  info.warnings = study.warnings;
  info.command_line = std::move(command_line);
  return info;
}

// ------------------------------------------------------------------------------------------
// Column and Table
// ------------------------------------------------------------------------------------------

std::size_t Column::size() const {
  return std::visit([](const auto& v) { return v.size(); }, values);
}

std::string Column::CsvCell(std::size_t row) const {
  if (const auto* d = std::get_if<std::vector<double>>(&values)) return io::CsvNumber((*d)[row]);
  if (const auto* n = std::get_if<std::vector<std::int64_t>>(&values))
    return std::to_string((*n)[row]);
  return io::CsvEscape(std::get<std::vector<std::string>>(values)[row]);
}

Column Column::Numbers(std::string name, std::string units, std::string description,
                       std::vector<double> values) {
  return Column{std::move(name), std::move(units), std::move(description), std::move(values)};
}

Column Column::Integers(std::string name, std::string units, std::string description,
                        std::vector<std::int64_t> values) {
  return Column{std::move(name), std::move(units), std::move(description), std::move(values)};
}

Column Column::Texts(std::string name, std::string description, std::vector<std::string> values) {
  return Column{std::move(name), "", std::move(description), std::move(values)};
}

void Table::Validate() const {
  if (name.empty() || name.front() == '/')
    throw std::invalid_argument("table name \"" + name + "\" must be non-empty and relative");
  std::set<std::string> seen;
  for (const Column& c : columns) {
    if (c.name.empty() || c.name.find('/') != std::string::npos)
      throw std::invalid_argument("table \"" + name + "\": column name \"" + c.name +
                                  "\" must be non-empty without '/'");
    if (!seen.insert(c.name).second)
      throw std::invalid_argument("table \"" + name + "\": column \"" + c.name + "\" repeats");
    if (c.size() != columns.front().size())
      throw std::invalid_argument("table \"" + name + "\": column \"" + c.name + "\" has " +
                                  std::to_string(c.size()) + " rows, column \"" +
                                  columns.front().name + "\" has " +
                                  std::to_string(columns.front().size()));
  }
}

const Column& Table::Get(const std::string& column) const {
  for (const Column& c : columns)
    if (c.name == column) return c;
  throw std::out_of_range("table \"" + name + "\" has no column \"" + column + "\"");
}

// ------------------------------------------------------------------------------------------
// Writing
// ------------------------------------------------------------------------------------------

std::vector<std::string> TrialGroupNames(const std::vector<pipeline::TrialAnalysis>& trials) {
  std::vector<std::string> names;
  std::set<std::string> used;
  for (std::size_t i = 0; i < trials.size(); ++i) {
    std::string base = trials[i].spec.id;
    for (char& ch : base)
      if (ch == '/') ch = '_';
    if (base.empty() || base == "." || base == "..") base = "trial_" + std::to_string(i);
    std::string name = base;
    for (int k = 2; !used.insert(name).second; ++k) name = base + "_" + std::to_string(k);
    names.push_back(name);
  }
  return names;
}

Table ResultsTable(const std::vector<pipeline::TrialAnalysis>& trials) {
  const std::vector<std::string> groups = TrialGroupNames(trials);
  std::vector<std::string> id, group, dir, specimen, surface, error, flags;
  std::vector<std::int64_t> success;
  std::map<std::string, std::vector<double>> num;
  const auto put = [&](const char* key, double ok_value, bool measured) {
    num[key].push_back(measured ? ok_value : kNaN);
  };
  for (std::size_t i = 0; i < trials.size(); ++i) {
    const auto& r = trials[i];
    const auto& k = r.impact;
    const bool m = r.success && k.success;
    id.push_back(r.spec.id);
    group.push_back("/trials/" + groups[i]);
    dir.push_back(r.spec.dir.string());
    specimen.push_back(r.spec.specimen_id);
    surface.push_back(r.spec.surface);
    error.push_back(r.error);
    flags.push_back(Join(r.flags, ";"));
    success.push_back(r.success ? 1 : 0);
    put("surface_angle_deg", r.spec.surface_angle_deg, true);
    put("fps", r.spec.fps, true);
    put("nominal_speed_m_s", r.spec.nominal_speed_m_s.value_or(kNaN), true);
    put("impact_time_s", k.impact_time_s, m);
    put("e", k.e, m);
    put("e_se", k.e_se, m);
    put("e_ci_low", k.e_ci_low, m);
    put("e_ci_high", k.e_ci_high, m);
    put("mu_eff", k.mu_eff, m);
    put("mu_eff_se", k.mu_eff_se, m);
    put("mu_eff_ci_low", k.mu_eff_ci_low, m);
    put("mu_eff_ci_high", k.mu_eff_ci_high, m);
    put("v_SC_before_x_m_s", k.v_SC_before.x(), m);
    put("v_SC_before_y_m_s", k.v_SC_before.y(), m);
    put("v_SC_after_x_m_s", k.v_SC_after.x(), m);
    put("v_SC_after_y_m_s", k.v_SC_after.y(), m);
    put("v_SC_before_se_x_m_s", k.v_SC_before_se.x(), m);
    put("v_SC_before_se_y_m_s", k.v_SC_before_se.y(), m);
    put("v_SC_after_se_x_m_s", k.v_SC_after_se.x(), m);
    put("v_SC_after_se_y_m_s", k.v_SC_after_se.y(), m);
    put("w_before_rad_s", k.w_before_rad_s, m);
    put("w_after_rad_s", k.w_after_rad_s, m);
    put("w_before_se_rad_s", k.w_before_se_rad_s, m);
    put("w_after_se_rad_s", k.w_after_se_rad_s, m);
    put("kinetic_energy_before_J", k.kinetic_energy_before_J, m);
    put("kinetic_energy_after_J", k.kinetic_energy_after_J, m);
    put("m_per_px_used", r.m_per_px_used, true);
    put("m_per_px_from_markers", r.m_per_px_from_markers, r.m_per_px_from_markers != 0.0);
    put("surface_angle_measured_deg", r.surface_angle_measured_deg.value_or(kNaN), true);
    put("out_of_plane_change", r.out_of_plane_change, !r.poses.empty());
  }
  const std::string S = " (S: x along the surface, down-slope; y the outward normal)";
  const auto N = [&](const char* key, const char* units, const std::string& description) {
    return Column::Numbers(key, units, description, num[key]);
  };
  Table t{"results", "one row per trial, in study order; NaN where not measured", {}};
  t.columns = {
      Column::Texts("id", "trial id", id),
      Column::Texts("group", "the trial's group in this file", group),
      Column::Texts("dir", "trial folder", dir),
      Column::Texts("specimen", "specimen id", specimen),
      Column::Texts("surface", "surface name", surface),
      N("surface_angle_deg", "deg", "surface angle (trial.json)"),
      N("fps", "1/s", "frame rate"),
      N("nominal_speed_m_s", "m/s", "nominal impact speed (NaN when not given)"),
      Column::Integers("success", "", "1 when the impact was measured", success),
      Column::Texts("error", "why the trial failed (empty on success)", error),
      N("impact_time_s", "s", "impact time since frame 0"),
      N("e", "1", "normal coefficient of restitution"),
      N("e_se", "1", "standard error of e"),
      N("e_ci_low", "1", "lower end of the confidence interval of e"),
      N("e_ci_high", "1", "upper end of the confidence interval of e"),
      N("mu_eff", "1", "effective friction coefficient"),
      N("mu_eff_se", "1", "standard error of mu_eff"),
      N("mu_eff_ci_low", "1", "lower end of the confidence interval of mu_eff"),
      N("mu_eff_ci_high", "1", "upper end of the confidence interval of mu_eff"),
      N("v_SC_before_x_m_s", "m/s", "velocity of C before, along the surface" + S),
      N("v_SC_before_y_m_s", "m/s", "velocity of C before, normal" + S),
      N("v_SC_after_x_m_s", "m/s", "velocity of C after, along the surface" + S),
      N("v_SC_after_y_m_s", "m/s", "velocity of C after, normal" + S),
      N("v_SC_before_se_x_m_s", "m/s", "standard error of v_SC_before_x_m_s"),
      N("v_SC_before_se_y_m_s", "m/s", "standard error of v_SC_before_y_m_s"),
      N("v_SC_after_se_x_m_s", "m/s", "standard error of v_SC_after_x_m_s"),
      N("v_SC_after_se_y_m_s", "m/s", "standard error of v_SC_after_y_m_s"),
      N("w_before_rad_s", "rad/s", "angular velocity before"),
      N("w_after_rad_s", "rad/s", "angular velocity after"),
      N("w_before_se_rad_s", "rad/s", "standard error of w_before_rad_s"),
      N("w_after_se_rad_s", "rad/s", "standard error of w_after_rad_s"),
      N("kinetic_energy_before_J", "J", "kinetic energy before"),
      N("kinetic_energy_after_J", "J", "kinetic energy after"),
      N("m_per_px_used", "m/px", "scale the analysis used"),
      N("m_per_px_from_markers", "m/px", "scale from the marker spacing (NaN when not measured)"),
      N("surface_angle_measured_deg", "deg", "surface angle measured (NaN when not measured)"),
      N("out_of_plane_change", "1", "range of the projected marker distance ratio"),
      Column::Texts("flags", "flags joined with ';'", flags),
  };
  return t;
}

void WriteStudyFile(const std::filesystem::path& path, const StudyInfo& info,
                    const std::vector<pipeline::TrialAnalysis>& trials,
                    const std::function<void(std::size_t)>& after_trial) {
  const Table results = ResultsTable(trials);
  results.Validate();
  const std::vector<std::string> names = TrialGroupNames(trials);
  AtomicHdf5(
      path, [](const std::filesystem::path&) {},
      [&](const std::filesystem::path& tmp) {
        H5::H5File file(tmp.string(), H5F_ACC_TRUNC);
        WriteStudyInfo(file, info);
        const H5::Group root = file.openGroup("/");
        const H5::Group g = h5::MakeGroup(root, "trials", "one group per trial");
        for (std::size_t i = 0; i < trials.size(); ++i) {
          WriteTrial(g, names[i], trials[i]);
          if (after_trial) after_trial(i);
        }
        WriteTable(root, results);
        file.flush(H5F_SCOPE_GLOBAL);
      });
}

void WriteTables(const std::filesystem::path& path, const std::string& group,
                 const std::string& description, const std::vector<Table>& tables,
                 const std::function<void(std::size_t)>& after_table,
                 const std::vector<std::pair<std::string, std::string>>& soft_links) {
  if (group.size() < 2 || group.front() != '/')
    throw std::invalid_argument("group \"" + group + "\" must be an absolute path below /");
  for (const Table& t : tables) t.Validate();
  if (!std::filesystem::is_regular_file(path))
    throw std::runtime_error(path.string() + ": no such study file");
  AtomicHdf5(
      path,
      [&](const std::filesystem::path& tmp) {
        std::error_code ec;
        std::filesystem::copy_file(path, tmp, ec);
        if (ec)
          throw std::runtime_error("cannot copy " + path.string() + " to " + tmp.string() + ": " +
                                   ec.message());
      },
      [&](const std::filesystem::path& tmp) {
        H5::H5File file(tmp.string(), H5F_ACC_RDWR);
        const H5::Group root = file.openGroup("/");
        if (h5::GetAttrText(root, "format", path.string()) != kStudyFileFormat)
          throw std::runtime_error(path.string() + " is not a hoofimpact study file");
        if (h5::PathExists(root, group)) root.unlink(group);
        const H5::Group g = h5::MakeGroup(root, group, description);
        for (std::size_t i = 0; i < tables.size(); ++i) {
          WriteTable(g, tables[i]);
          if (after_table) after_table(i);
        }
        for (const auto& [link, target] : soft_links) {
          if (h5::PathExists(root, link)) root.unlink(link);
          if (H5Lcreate_soft(target.c_str(), root.getId(), link.c_str(), H5P_DEFAULT, H5P_DEFAULT) <
              0)
            throw std::runtime_error(path.string() + ": cannot link " + link + " to " + target);
        }
        file.flush(H5F_SCOPE_GLOBAL);
      });
}

// ------------------------------------------------------------------------------------------
// Reading
// ------------------------------------------------------------------------------------------

Table ReadTable(const std::filesystem::path& path, const std::string& table_path) {
  H5::Exception::dontPrint();
  if (!std::filesystem::is_regular_file(path))
    throw std::runtime_error(path.string() + ": no such file");
  const std::string where = path.string() + ":" + table_path;
  try {
    const H5::H5File file(path.string(), H5F_ACC_RDONLY);
    if (!h5::PathExists(file.openGroup("/"), table_path))
      throw std::runtime_error(where + " does not exist");
    const H5::Group g = file.openGroup(table_path);
    Table t;
    t.name = table_path.substr(table_path.find_first_not_of('/'));
    t.description = g.attrExists("description") ? h5::GetAttrText(g, "description", where) : "";
    for (const std::string& c : h5::GetAttrTexts(g, "columns", where))
      t.columns.push_back(ReadColumn(g, c, where));
    t.Validate();
    return t;
  } catch (const H5::Exception& e) {
    RethrowHdf5(e, path);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(where + ": " + e.what());
  }
}

StudyResults ReadStudyResults(const std::filesystem::path& path) {
  H5::Exception::dontPrint();
  if (!std::filesystem::is_regular_file(path))
    throw std::runtime_error(path.string() + ": no such file");
  StudyResults out;
  std::vector<std::string> group;
  try {
    const H5::H5File file(path.string(), H5F_ACC_RDONLY);
    const H5::Group root = file.openGroup("/");
    CheckFormat(root, path);
    out.name = h5::GetAttrText(root, "name", path.string());
    out.study_dir = h5::GetAttrText(root, "study_dir", path.string());
    out.hoofimpact_version = h5::GetAttrText(root, "hoofimpact_version", path.string());
    out.created_utc = h5::GetAttrText(root, "created_utc", path.string());
  } catch (const H5::Exception& e) {
    RethrowHdf5(e, path);
  }
  const Table t = ReadTable(path, "/results");
  const std::size_t n = t.columns.empty() ? 0 : t.columns[0].size();
  const auto texts = [&](const char* c) { return CheckedStrings(t, c); };
  const auto nums = [&](const char* c) { return CheckedNumbers(t, c); };
  try {
    const auto id = texts("id"), grp = texts("group"), dir = texts("dir"), sp = texts("specimen"),
               surface = texts("surface"), error = texts("error");
    const auto success = nums("success");
    std::map<std::string, std::vector<double>> v;
    for (const char* c : {"surface_angle_deg",
                          "fps",
                          "nominal_speed_m_s",
                          "impact_time_s",
                          "e",
                          "e_se",
                          "e_ci_low",
                          "e_ci_high",
                          "mu_eff",
                          "mu_eff_se",
                          "mu_eff_ci_low",
                          "mu_eff_ci_high",
                          "v_SC_before_x_m_s",
                          "v_SC_before_y_m_s",
                          "v_SC_after_x_m_s",
                          "v_SC_after_y_m_s",
                          "v_SC_before_se_x_m_s",
                          "v_SC_before_se_y_m_s",
                          "v_SC_after_se_x_m_s",
                          "v_SC_after_se_y_m_s",
                          "w_before_rad_s",
                          "w_after_rad_s",
                          "w_before_se_rad_s",
                          "w_after_se_rad_s",
                          "kinetic_energy_before_J",
                          "kinetic_energy_after_J",
                          "m_per_px_used",
                          "m_per_px_from_markers",
                          "surface_angle_measured_deg",
                          "out_of_plane_change"})
      v[c] = nums(c);
    for (std::size_t i = 0; i < n; ++i) {
      TrialResult r;
      r.id = id[i];
      r.group = grp[i];
      r.dir = dir[i];
      r.specimen = sp[i];
      r.surface = surface[i];
      r.success = success[i] != 0;
      r.error = error[i];
      r.surface_angle_deg = v["surface_angle_deg"][i];
      r.fps = v["fps"][i];
      r.nominal_speed_m_s = v["nominal_speed_m_s"][i];
      r.impact_time_s = v["impact_time_s"][i];
      r.e = v["e"][i];
      r.e_se = v["e_se"][i];
      r.e_ci_low = v["e_ci_low"][i];
      r.e_ci_high = v["e_ci_high"][i];
      r.mu_eff = v["mu_eff"][i];
      r.mu_eff_se = v["mu_eff_se"][i];
      r.mu_eff_ci_low = v["mu_eff_ci_low"][i];
      r.mu_eff_ci_high = v["mu_eff_ci_high"][i];
      r.v_SC_before_m_s = {v["v_SC_before_x_m_s"][i], v["v_SC_before_y_m_s"][i]};
      r.v_SC_after_m_s = {v["v_SC_after_x_m_s"][i], v["v_SC_after_y_m_s"][i]};
      r.v_SC_before_se_m_s = {v["v_SC_before_se_x_m_s"][i], v["v_SC_before_se_y_m_s"][i]};
      r.v_SC_after_se_m_s = {v["v_SC_after_se_x_m_s"][i], v["v_SC_after_se_y_m_s"][i]};
      r.w_before_rad_s = v["w_before_rad_s"][i];
      r.w_after_rad_s = v["w_after_rad_s"][i];
      r.w_before_se_rad_s = v["w_before_se_rad_s"][i];
      r.w_after_se_rad_s = v["w_after_se_rad_s"][i];
      r.kinetic_energy_before_J = v["kinetic_energy_before_J"][i];
      r.kinetic_energy_after_J = v["kinetic_energy_after_J"][i];
      r.m_per_px_used = v["m_per_px_used"][i];
      r.m_per_px_from_markers = v["m_per_px_from_markers"][i];
      r.surface_angle_measured_deg = v["surface_angle_measured_deg"][i];
      r.out_of_plane_change = v["out_of_plane_change"][i];
      out.trials.push_back(std::move(r));
    }
  } catch (const std::out_of_range& e) {
    throw std::runtime_error(path.string() + ": " + e.what());
  }
  try {
    const H5::H5File file(path.string(), H5F_ACC_RDONLY);
    for (TrialResult& r : out.trials) {
      const std::string where = path.string() + ":" + r.group;
      if (!h5::PathExists(file.openGroup("/"), r.group))
        throw std::runtime_error(where + " does not exist");
      const H5::Group g = file.openGroup(r.group);
      r.flags = h5::ReadTexts(g.openDataSet("flags"), where + "/flags");
      r.warnings = h5::ReadTexts(g.openDataSet("warnings"), where + "/warnings");
    }
  } catch (const H5::Exception& e) {
    RethrowHdf5(e, path);
  }
  return out;
}

kinematics::KinematicsOptions ReadKinematicsOptions(const std::filesystem::path& path) {
  H5::Exception::dontPrint();
  if (!std::filesystem::is_regular_file(path))
    throw std::runtime_error(path.string() + ": no such file");
  kinematics::KinematicsOptions k;
  try {
    const H5::H5File file(path.string(), H5F_ACC_RDONLY);
    const H5::Group root_group = file.openGroup("/");
    CheckFormat(root_group, path);
    const GroupReader g =
        GroupReader(root_group, path.string() + ":").Group("study").Group("analysis_options");
    internal::Serialize(internal::H5Reader(g), k);
  } catch (const H5::Exception& e) {
    RethrowHdf5(e, path);
  }
  try {
    k.Validate();
  } catch (const std::exception& e) {
    throw std::runtime_error(path.string() + ":/study/analysis_options: " + e.what());
  }
  return k;
}

std::vector<pipeline::TrialAnalysis> ReadTrialAnalyses(const std::filesystem::path& path) {
  H5::Exception::dontPrint();
  if (!std::filesystem::is_regular_file(path))
    throw std::runtime_error(path.string() + ": no such file");
  try {
    const H5::H5File file(path.string(), H5F_ACC_RDONLY);
    CheckFormat(file.openGroup("/"), path);
  } catch (const H5::Exception& e) {
    RethrowHdf5(e, path);
  }
  const Table results = ReadTable(path, "/results");
  std::vector<std::string> ids, groups;
  try {
    ids = CheckedStrings(results, "id");
    groups = CheckedStrings(results, "group");
  } catch (const std::exception& e) {
    throw std::runtime_error(path.string() + ": " + e.what());
  }
  std::vector<pipeline::TrialAnalysis> out;
  try {
    const H5::H5File file(path.string(), H5F_ACC_RDONLY);
    const H5::Group root_group = file.openGroup("/");
    const GroupReader root(root_group, path.string() + ":");
    std::map<std::string, pipeline::SpecimenSpec> specimens;  // read once each
    for (std::size_t i = 0; i < groups.size(); ++i) {
      const std::string where = path.string() + ":" + groups[i];
      if (groups[i].size() < 2 || groups[i].front() != '/')
        throw std::runtime_error(path.string() + ":/results/group row " + std::to_string(i) +
                                 " is \"" + groups[i] + "\", not a group path");
      if (!h5::PathExists(root_group, groups[i]))
        throw std::runtime_error(where + " does not exist");
      if (root_group.childObjType(groups[i]) != H5O_TYPE_GROUP)
        throw std::runtime_error(where + " is not a group");
      pipeline::TrialAnalysis r = ReadTrialGroup(GroupReader(file.openGroup(groups[i]), where));
      if (r.spec.id != ids[i])
        throw std::runtime_error(where + "/metadata/id is \"" + r.spec.id +
                                 "\", /results/id says \"" + ids[i] + "\"");
      if (!r.spec.specimen_id.empty()) {
        auto it = specimens.find(r.spec.specimen_id);
        if (it == specimens.end()) {
          const GroupReader g = root.Group("study").Group("specimens").Group(r.spec.specimen_id);
          pipeline::SpecimenSpec specimen;
          internal::Serialize(internal::H5Reader(g), specimen);
          it = specimens.emplace(r.spec.specimen_id, std::move(specimen)).first;
        }
        r.spec.specimen = it->second;
      }
      out.push_back(std::move(r));
    }
  } catch (const H5::Exception& e) {
    RethrowHdf5(e, path);
  }
  return out;
}

// ------------------------------------------------------------------------------------------
// CSV
// ------------------------------------------------------------------------------------------

void WriteResultsCsv(const std::filesystem::path& path,
                     const std::vector<pipeline::TrialAnalysis>& trials) {
  const Table t = ResultsTable(trials);
  io::WriteFileAtomically(path, [&](std::ostream& out) {
    for (std::size_t c = 0; c < t.columns.size(); ++c)
      out << (c ? "," : "") << io::CsvEscape(t.columns[c].name);
    out << "\n";
    for (std::size_t r = 0; r < trials.size(); ++r) {
      for (std::size_t c = 0; c < t.columns.size(); ++c) {
        if (c) out << ",";
        out << t.columns[c].CsvCell(r);
      }
      out << "\n";
    }
  });
}

void WriteTracksCsv(const std::filesystem::path& path,
                    const std::vector<pipeline::TrialAnalysis>& trials) {
  io::WriteFileAtomically(path, [&](std::ostream& out) {
    out << "trial,frame,t_s,marker,found,x_px,y_px,status,quality,pose_valid,p_WE_x_m,p_WE_y_m,"
           "theta_W_rad\n";
    for (const auto& r : trials) {
      const auto& t = r.tracks;
      for (std::size_t f = 0; f < t.frames.size(); ++f) {
        std::ostringstream pose;
        if (f < r.poses.size() && r.poses[f].valid)
          pose << "1," << io::CsvNumber(r.poses[f].p_WE.x()) << ","
               << io::CsvNumber(r.poses[f].p_WE.y()) << ","
               << io::CsvNumber(r.poses[f].theta_W_rad);
        else
          pose << "0,,,";
        const std::string t_s =
            r.spec.fps > 0 ? io::CsvNumber(static_cast<double>(f) / r.spec.fps) : "";
        for (std::size_t m = 0; m < t.names.size() && m < t.frames[f].size(); ++m) {
          const auto& o = t.frames[f][m];
          out << io::CsvEscape(r.spec.id) << "," << f << "," << t_s << ","
              << io::CsvEscape(t.names[m]) << "," << (o.found ? 1 : 0) << ",";
          if (o.found)
            out << io::CsvNumber(o.p_I.x()) << "," << io::CsvNumber(o.p_I.y());
          else
            out << ",";
          out << "," << io::CsvEscape(o.status) << "," << io::CsvNumber(o.quality) << ","
              << pose.str() << "\n";
        }
      }
    }
  });
}

std::string NowUtc() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  ::gmtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

}  // namespace hoof::studyfile
