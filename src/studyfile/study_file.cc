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

#ifndef HOOF_VERSION
#define HOOF_VERSION "unknown"
#endif

namespace hoof::studyfile {
namespace {

using core::kNaN;

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

void WriteSpecimen(const H5::Group& g, const pipeline::SpecimenSpec& s) {
  h5::Scalar(g, "mass_kg", s.mass_kg, "kg", "specimen mass");
  h5::Scalar(g, "inertia_kg_m2", s.inertia_kg_m2, "kg m^2",
             "moment of inertia about the centre of mass C, out of the image plane");
  h5::Scalar(g, "end_radius_m", s.end_radius_m, "m", "radius of the round end (centre E)");
  h5::Scalar(g, "d_EC_m", s.d_EC_m, "m", "distance from E to the centre of mass C");
  h5::Scalar(g, "length_m", s.length_m, "m", "specimen length (0 when not given)");
  h5::Scalar(g, "width_m", s.width_m, "m", "specimen width (0 when not given)");
  h5::Scalar(g, "thickness_m", s.thickness_m, "m", "specimen thickness (0 when not given)");
  std::vector<std::string> names;
  std::vector<double> p;
  for (const auto& [name, p_B] : s.markers_B_m) {
    names.push_back(name);
    p.push_back(p_B.x());
    p.push_back(p_B.y());
  }
  h5::Texts(g, "marker_names", names, {names.size()}, "marker names, layout order");
  h5::Doubles(g, "markers_B_m", p, {names.size(), 2}, "m",
              "marker centres in the body frame B (origin E, x toward C), [marker, (x, y)]");
}

void WriteOptions(const H5::Group& g, const pipeline::TrialAnalysisOptions& o) {
  const auto& k = o.kinematics;
  const auto& t = o.tracker;
  h5::Text(g, "centre_method",
           t.detector.method == tracking::CentreMethod::kEllipseFit ? "ellipse" : "centroid",
           "sub-pixel dot centre method");
  h5::Scalar(g, "min_significance", t.detector.min_significance, "1",
             "dot contrast over noise for a dot to count");
  h5::Integers(g, "centroid_iterations", {t.detector.centroid_iterations}, {}, "1",
               "re-centring passes of the weighted centroid");
  h5::Scalar(g, "min_radius_px", t.detector.min_radius_px, "px",
             "smallest dot radius the full-frame search considers");
  h5::Scalar(g, "max_radius_px", t.detector.max_radius_px, "px",
             "largest dot radius the full-frame search considers");
  h5::Scalar(g, "search_radius_px", t.search_radius_px, "px",
             "tracker search radius (0 = automatic)");
  h5::Integers(g, "max_consecutive_misses", {t.max_consecutive_misses}, {}, "frame",
               "a marker missing this many frames in a row is lost for good");
  h5::Scalar(g, "layout_tolerance", t.layout_tolerance, "1",
             "largest relative mismatch of the marker layout in the first frame");
  h5::Integers(g, "fit_frames", {k.fit_frames}, {}, "frame", "frames per flight fit");
  h5::Integers(g, "min_fit_frames", {k.min_fit_frames}, {}, "frame",
               "fewest usable frames per fit");
  h5::Scalar(g, "max_contact_s", k.max_contact_s, "s", "longest contact assumed");
  h5::Scalar(g, "exposure_s", k.exposure_s, "s", "exposure time; < 0 = one frame period");
  h5::Scalar(g, "gravity_m_s2", k.gravity_m_s2, "m/s^2", "g along -y_W");
  h5::Scalar(g, "confidence", k.confidence, "1", "level of the reported intervals");
  h5::Bools(g, "scale_from_markers", {o.scale_from_markers ? std::uint8_t{1} : std::uint8_t{0}}, {},
            "scale taken from the marker spacing instead of camera.m_per_px");
  h5::Scalar(g, "out_of_plane_threshold", o.out_of_plane_threshold, "1",
             "relative change of the projected marker distance that flags out-of-plane rotation");
  h5::Scalar(g, "surface_angle_tolerance_deg", o.surface_angle_tolerance_deg, "deg",
             "largest accepted difference between measured and stated surface angle");
}

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
  for (const auto& [id, spec] : info.specimens)
    WriteSpecimen(h5::MakeGroup(specimens, id, "specimen " + id), spec);
  WriteOptions(h5::MakeGroup(study, "analysis_options", "options every trial was analysed with"),
               info.options);
}

// ------------------------------------------------------------------------------------------
// One trial
// ------------------------------------------------------------------------------------------

double NaNIfZero(double v) { return v == 0.0 ? kNaN : v; }

void WriteTrialMetadata(const H5::Group& g, const pipeline::TrialAnalysis& r) {
  const pipeline::TrialSpec& s = r.spec;
  h5::Text(g, "id", s.id, "trial id (trial.json)");
  h5::Text(g, "dir", s.dir.string(), "trial folder");
  h5::Text(g, "specimen", s.specimen_id, "specimen id (study.json)");
  h5::Text(g, "surface", s.surface, "surface name");
  h5::Scalar(g, "surface_angle_deg", s.surface_angle_deg, "deg", "surface angle (trial.json)");
  h5::Scalar(g, "fps", s.fps, "1/s", "frame rate");
  h5::Scalar(g, "nominal_speed_m_s", s.nominal_speed_m_s.value_or(kNaN), "m/s",
             "nominal impact speed (trial.json; NaN when not given)");
  h5::Text(g, "frames_source", s.frames.is_video() ? s.frames.video : s.frames.pattern,
           "image pattern or video file, relative to the trial folder");
  h5::Integers(g, "frames_first", {s.frames.first}, {}, "frame", "first frame number");
  h5::Integers(g, "frames_count", {s.frames.count}, {}, "frame", "number of frames");
  h5::Scalar(g, "camera_m_per_px", s.camera.m_per_px, "m/px", "scale stated in trial.json");
  h5::Vec2(g, "camera_gravity_image", s.camera.gravity_image, "1",
           "unit direction of gravity in the image (x right, y down)");
  if (s.camera.distortion)
    h5::Doubles(g, "camera_distortion",
                std::vector<double>(s.camera.distortion->begin(), s.camera.distortion->end()), {5},
                "1", "OpenCV k1 k2 p1 p2 k3");
  if (s.camera.camera_matrix)
    h5::Doubles(g, "camera_matrix",
                std::vector<double>(s.camera.camera_matrix->begin(), s.camera.camera_matrix->end()),
                {3, 3}, "px", "camera matrix fx 0 cx / 0 fy cy / 0 0 1");
  if (s.surface_line_px)
    h5::Doubles(g, "surface_line_px",
                {(*s.surface_line_px)[0].x(), (*s.surface_line_px)[0].y(),
                 (*s.surface_line_px)[1].x(), (*s.surface_line_px)[1].y()},
                {2, 2}, "px", "two image points on the surface, [point, (x, y)]");
  h5::Text(g, "notes", s.notes, "notes (trial.json)");
  h5::Texts(g, "input_warnings", s.warnings, {s.warnings.size()},
            "warnings from reading trial.json");
  h5::Scalar(g, "m_per_px_used", r.m_per_px_used, "m/px", "scale the analysis used");
  h5::Scalar(g, "m_per_px_from_markers", NaNIfZero(r.m_per_px_from_markers), "m/px",
             "scale measured from the marker spacing (NaN when not measured)");
  h5::Scalar(g, "surface_angle_measured_deg", r.surface_angle_measured_deg.value_or(kNaN), "deg",
             "surface angle measured in the first frame (NaN when not measured)");
  h5::Scalar(g, "analysis_seconds", r.seconds, "s", "wall time of the analysis");
}

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

void WriteFit(const H5::Group& g, const kinematics::FlightFit& fit) {
  h5::Integers(g, "first_frame", {fit.first_frame}, {}, "frame", "first frame of the fit window");
  h5::Integers(g, "last_frame", {fit.last_frame}, {}, "frame", "last frame of the fit window");
  h5::Integers(g, "n", {fit.n}, {}, "1", "frames used in the fit");
  h5::Vec2(g, "p_WC_m", fit.p_WC, "m", "position of C at the impact time, W");
  h5::Vec2(g, "v_WC_m_s", fit.v_WC, "m/s", "velocity of C at the impact time, W");
  h5::Doubles(g, "cov_v_WC_m2_s2",
              {fit.cov_v_WC(0, 0), fit.cov_v_WC(0, 1), fit.cov_v_WC(1, 0), fit.cov_v_WC(1, 1)},
              {2, 2}, "m^2/s^2", "covariance of v_WC");
  h5::Scalar(g, "theta_W_rad", fit.theta_W_rad, "rad", "angle at the impact time");
  h5::Scalar(g, "theta_se_rad", fit.theta_se_rad, "rad", "its standard error");
  h5::Scalar(g, "w_rad_s", fit.w_rad_s, "rad/s", "angular velocity");
  h5::Scalar(g, "w_se_rad_s", fit.w_se_rad_s, "rad/s", "its standard error");
  h5::Scalar(g, "rms_residual_m", fit.rms_residual_m, "m", "rms residual of the position fit");
  h5::Scalar(g, "rms_theta_residual_rad", fit.rms_theta_residual_rad, "rad",
             "rms residual of the angle fit");
}

void WriteImpact(const H5::Group& g, const kinematics::ImpactKinematics& k) {
  const std::string S = ", S = [along the surface (down-slope), normal]";
  h5::Scalar(g, "impact_time_s", k.impact_time_s, "s", "impact time since frame 0 (sub-frame)");
  h5::Integers(g, "impact_frame", {k.impact_frame}, {}, "frame", "last frame before the impact");
  h5::Vec2(g, "v_SC_before_m_s", k.v_SC_before, "m/s", "velocity of C before" + S);
  h5::Vec2(g, "v_SC_before_se_m_s", k.v_SC_before_se, "m/s", "its standard error");
  h5::Vec2(g, "v_SC_after_m_s", k.v_SC_after, "m/s", "velocity of C after" + S);
  h5::Vec2(g, "v_SC_after_se_m_s", k.v_SC_after_se, "m/s", "its standard error");
  h5::Vec2(g, "v_ST_before_m_s", k.v_ST_before, "m/s",
           "velocity of the body point at T before" + S);
  h5::Vec2(g, "v_ST_after_m_s", k.v_ST_after, "m/s", "velocity of the body point at T after" + S);
  h5::Scalar(g, "w_before_rad_s", k.w_before_rad_s, "rad/s", "angular velocity before");
  h5::Scalar(g, "w_before_se_rad_s", k.w_before_se_rad_s, "rad/s", "its standard error");
  h5::Scalar(g, "w_after_rad_s", k.w_after_rad_s, "rad/s", "angular velocity after");
  h5::Scalar(g, "w_after_se_rad_s", k.w_after_se_rad_s, "rad/s", "its standard error");
  h5::Scalar(g, "e", k.e, "1", "normal coefficient of restitution");
  h5::Scalar(g, "e_se", k.e_se, "1", "its standard error");
  h5::Doubles(g, "e_ci", {k.e_ci_low, k.e_ci_high}, {2}, "1",
              "confidence interval of e (level: /study/analysis_options/confidence)");
  h5::Scalar(g, "mu_eff", k.mu_eff, "1", "effective friction coefficient");
  h5::Scalar(g, "mu_eff_se", k.mu_eff_se, "1", "its standard error");
  h5::Doubles(g, "mu_eff_ci", {k.mu_eff_ci_low, k.mu_eff_ci_high}, {2}, "1",
              "confidence interval of mu_eff");
  h5::Scalar(g, "kinetic_energy_before_J", k.kinetic_energy_before_J, "J",
             "kinetic energy before (translation and rotation)");
  h5::Scalar(g, "kinetic_energy_after_J", k.kinetic_energy_after_J, "J", "kinetic energy after");
  h5::Texts(g, "warnings", k.warnings, {k.warnings.size()}, "warnings of the impact measurement");
}

void WriteTrial(const H5::Group& trials, const std::string& group_name,
                const pipeline::TrialAnalysis& r) {
  const H5::Group g = h5::MakeGroup(trials, group_name, "trial " + r.spec.id);
  h5::Bools(g, "success", {r.success ? std::uint8_t{1} : std::uint8_t{0}}, {},
            "1 when the impact was measured");
  h5::Text(g, "error", r.error, "why the trial failed (empty on success)");
  h5::Texts(g, "flags", r.flags, {r.flags.size()}, "short tags: out_of_plane, surface_angle, ...");
  h5::Texts(g, "warnings", r.warnings, {r.warnings.size()}, "warnings in words");
  WriteTrialMetadata(h5::MakeGroup(g, "metadata", "trial.json and the calibration checks"), r);
  WriteTracks(h5::MakeGroup(g, "tracks", "raw marker tracks"), r);
  WritePoses(h5::MakeGroup(g, "poses", "body pose per frame"), r);
  h5::Text(g, "impact_message", r.impact.message, "why the impact measurement failed, if it did");
  if (!r.impact.success) return;
  const H5::Group fits = h5::MakeGroup(g, "fits", "free-flight fits before and after the impact");
  WriteFit(h5::MakeGroup(fits, "before", "fit before the impact"), r.impact.before);
  WriteFit(h5::MakeGroup(fits, "after", "fit after the impact"), r.impact.after);
  WriteImpact(h5::MakeGroup(g, "results", "the impact in the surface frame S"), r.impact);
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

std::string ShapeText(const std::vector<hsize_t>& dims) {
  std::string out = "[";
  for (std::size_t i = 0; i < dims.size(); ++i) out += (i ? ", " : "") + std::to_string(dims[i]);
  return out + "]";
}

std::optional<double> UnlessNaN(double v) {
  if (std::isnan(v)) return std::nullopt;
  return v;
}

/// The datasets of one group, read with their shapes checked. `where` is the file and the
/// group ("study.h5:/trials/x"); every error names it and the item.
class GroupReader {
 public:
  GroupReader(const H5::Group& group, std::string where)
      : group_(group), where_(std::move(where)) {}

  const std::string& where() const { return where_; }
  bool Has(const std::string& name) const { return group_.nameExists(name); }

  GroupReader Group(const std::string& name) const {
    if (!Has(name)) throw std::runtime_error(Item(name) + " does not exist");
    if (group_.childObjType(name) != H5O_TYPE_GROUP)
      throw std::runtime_error(Item(name) + " is not a group");
    return GroupReader(group_.openGroup(name), Item(name));
  }
  /// Length of the 1-D dataset `name`.
  hsize_t Length(const std::string& name) const {
    const std::vector<hsize_t> shape = h5::Shape(Open(name));
    if (shape.size() != 1)
      throw std::runtime_error(Item(name) + " has shape " + ShapeText(shape) +
                               ", expected one dimension");
    return shape[0];
  }
  std::vector<double> Doubles(const std::string& name, const std::vector<hsize_t>& dims) const {
    return h5::ReadDoubles(Open(name, dims), Item(name));
  }
  double Scalar(const std::string& name) const { return Doubles(name, {})[0]; }
  Eigen::Vector2d Vec2(const std::string& name) const {
    const std::vector<double> v = Doubles(name, {2});
    return {v[0], v[1]};
  }
  std::vector<std::int64_t> Integers(const std::string& name,
                                     const std::vector<hsize_t>& dims) const {
    return h5::ReadIntegers(Open(name, dims), Item(name));
  }
  int Int(const std::string& name) const {
    const std::int64_t v = Integers(name, {})[0];
    if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
      throw std::runtime_error(Item(name) + " = " + std::to_string(v) + " is out of range");
    return static_cast<int>(v);
  }
  bool Bool(const std::string& name) const { return Integers(name, {})[0] != 0; }
  std::vector<std::string> Texts(const std::string& name, const std::vector<hsize_t>& dims) const {
    return h5::ReadTexts(Open(name, dims), Item(name));
  }
  std::string Text(const std::string& name) const { return Texts(name, {})[0]; }
  /// A 1-D text dataset of any length.
  std::vector<std::string> TextList(const std::string& name) const {
    return Texts(name, {Length(name)});
  }

 private:
  std::string Item(const std::string& name) const { return where_ + "/" + name; }
  H5::DataSet Open(const std::string& name) const {
    if (!Has(name)) throw std::runtime_error(Item(name) + " does not exist");
    if (group_.childObjType(name) != H5O_TYPE_DATASET)
      throw std::runtime_error(Item(name) + " is not a dataset");
    return group_.openDataSet(name);
  }
  H5::DataSet Open(const std::string& name, const std::vector<hsize_t>& dims) const {
    H5::DataSet d = Open(name);
    const std::vector<hsize_t> shape = h5::Shape(d);
    if (shape != dims)
      throw std::runtime_error(Item(name) + " has shape " + ShapeText(shape) + ", expected " +
                               ShapeText(dims));
    return d;
  }

  H5::Group group_;
  std::string where_;
};

pipeline::SpecimenSpec ReadSpecimen(const GroupReader& g) {
  pipeline::SpecimenSpec s;
  s.mass_kg = g.Scalar("mass_kg");
  s.inertia_kg_m2 = g.Scalar("inertia_kg_m2");
  s.end_radius_m = g.Scalar("end_radius_m");
  s.d_EC_m = g.Scalar("d_EC_m");
  s.length_m = g.Scalar("length_m");
  s.width_m = g.Scalar("width_m");
  s.thickness_m = g.Scalar("thickness_m");
  const std::vector<std::string> names = g.TextList("marker_names");
  const std::vector<double> p = g.Doubles("markers_B_m", {names.size(), 2});
  for (std::size_t i = 0; i < names.size(); ++i)
    s.markers_B_m.emplace_back(names[i], Eigen::Vector2d(p[2 * i], p[2 * i + 1]));
  return s;
}

void ReadTrialMetadata(const GroupReader& g, pipeline::TrialAnalysis& r) {
  pipeline::TrialSpec& s = r.spec;
  s.id = g.Text("id");
  s.dir = g.Text("dir");
  s.specimen_id = g.Text("specimen");
  s.surface = g.Text("surface");
  s.surface_angle_deg = g.Scalar("surface_angle_deg");
  s.fps = g.Scalar("fps");
  s.nominal_speed_m_s = UnlessNaN(g.Scalar("nominal_speed_m_s"));
  s.frames.first = g.Int("frames_first");
  s.frames.count = g.Int("frames_count");
  s.camera.m_per_px = g.Scalar("camera_m_per_px");
  s.camera.gravity_image = g.Vec2("camera_gravity_image");
  if (g.Has("camera_distortion")) {
    const std::vector<double> v = g.Doubles("camera_distortion", {5});
    s.camera.distortion.emplace();
    std::copy(v.begin(), v.end(), s.camera.distortion->begin());
  }
  if (g.Has("camera_matrix")) {
    const std::vector<double> v = g.Doubles("camera_matrix", {3, 3});
    s.camera.camera_matrix.emplace();
    std::copy(v.begin(), v.end(), s.camera.camera_matrix->begin());
  }
  if (g.Has("surface_line_px")) {
    const std::vector<double> v = g.Doubles("surface_line_px", {2, 2});
    s.surface_line_px =
        std::array<Eigen::Vector2d, 2>{Eigen::Vector2d(v[0], v[1]), Eigen::Vector2d(v[2], v[3])};
  }
  s.notes = g.Text("notes");
  s.warnings = g.TextList("input_warnings");
  r.m_per_px_used = g.Scalar("m_per_px_used");
  const double from_markers = g.Scalar("m_per_px_from_markers");
  r.m_per_px_from_markers = std::isnan(from_markers) ? 0.0 : from_markers;
  r.surface_angle_measured_deg = UnlessNaN(g.Scalar("surface_angle_measured_deg"));
  r.seconds = g.Scalar("analysis_seconds");
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

kinematics::FlightFit ReadFit(const GroupReader& g) {
  kinematics::FlightFit fit;
  fit.first_frame = g.Int("first_frame");
  fit.last_frame = g.Int("last_frame");
  fit.n = g.Int("n");
  fit.p_WC = g.Vec2("p_WC_m");
  fit.v_WC = g.Vec2("v_WC_m_s");
  const std::vector<double> cov = g.Doubles("cov_v_WC_m2_s2", {2, 2});
  fit.cov_v_WC << cov[0], cov[1], cov[2], cov[3];
  fit.theta_W_rad = g.Scalar("theta_W_rad");
  fit.theta_se_rad = g.Scalar("theta_se_rad");
  fit.w_rad_s = g.Scalar("w_rad_s");
  fit.w_se_rad_s = g.Scalar("w_se_rad_s");
  fit.rms_residual_m = g.Scalar("rms_residual_m");
  fit.rms_theta_residual_rad = g.Scalar("rms_theta_residual_rad");
  return fit;
}

void ReadImpact(const GroupReader& g, kinematics::ImpactKinematics& k) {
  k.impact_time_s = g.Scalar("impact_time_s");
  k.impact_frame = g.Int("impact_frame");
  k.v_SC_before = g.Vec2("v_SC_before_m_s");
  k.v_SC_before_se = g.Vec2("v_SC_before_se_m_s");
  k.v_SC_after = g.Vec2("v_SC_after_m_s");
  k.v_SC_after_se = g.Vec2("v_SC_after_se_m_s");
  k.v_ST_before = g.Vec2("v_ST_before_m_s");
  k.v_ST_after = g.Vec2("v_ST_after_m_s");
  k.w_before_rad_s = g.Scalar("w_before_rad_s");
  k.w_before_se_rad_s = g.Scalar("w_before_se_rad_s");
  k.w_after_rad_s = g.Scalar("w_after_rad_s");
  k.w_after_se_rad_s = g.Scalar("w_after_se_rad_s");
  k.e = g.Scalar("e");
  k.e_se = g.Scalar("e_se");
  const Eigen::Vector2d e_ci = g.Vec2("e_ci");
  k.e_ci_low = e_ci.x();
  k.e_ci_high = e_ci.y();
  k.mu_eff = g.Scalar("mu_eff");
  k.mu_eff_se = g.Scalar("mu_eff_se");
  const Eigen::Vector2d mu_ci = g.Vec2("mu_eff_ci");
  k.mu_eff_ci_low = mu_ci.x();
  k.mu_eff_ci_high = mu_ci.y();
  k.kinetic_energy_before_J = g.Scalar("kinetic_energy_before_J");
  k.kinetic_energy_after_J = g.Scalar("kinetic_energy_after_J");
  k.warnings = g.TextList("warnings");
}

/// One `/trials/<id>` group; the specimen is filled in by the caller.
pipeline::TrialAnalysis ReadTrialGroup(const GroupReader& g) {
  pipeline::TrialAnalysis r;
  r.success = g.Bool("success");
  r.error = g.Text("error");
  r.flags = g.TextList("flags");
  r.warnings = g.TextList("warnings");
  ReadTrialMetadata(g.Group("metadata"), r);
  r.tracks = ReadTracks(g.Group("tracks"));
  ReadPoses(g.Group("poses"), r);
  r.impact.message = g.Text("impact_message");
  if (g.Has("results")) {  // written only when the impact was measured, with the fits
    r.impact.success = true;
    const GroupReader fits = g.Group("fits");
    r.impact.before = ReadFit(fits.Group("before"));
    r.impact.after = ReadFit(fits.Group("after"));
    ReadImpact(g.Group("results"), r.impact);
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
    put("m_per_px_from_markers", NaNIfZero(r.m_per_px_from_markers), true);
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
    k.fit_frames = g.Int("fit_frames");
    k.min_fit_frames = g.Int("min_fit_frames");
    k.max_contact_s = g.Scalar("max_contact_s");
    k.exposure_s = g.Scalar("exposure_s");
    k.gravity_m_s2 = g.Scalar("gravity_m_s2");
    k.confidence = g.Scalar("confidence");
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
          it = specimens.emplace(r.spec.specimen_id, ReadSpecimen(g)).first;
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
