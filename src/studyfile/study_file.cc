#include "studyfile/study_file.h"

#include <H5Cpp.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <set>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "core/frames.h"
#include "io/atomic_file.h"
#include "io/csv.h"
#include "studyfile/file_util.h"
#include "studyfile/frame_archive.h"
#include "studyfile/hdf5_util.h"
#include "studyfile/schema.h"
#include "studyfile/table_archive.h"

#ifndef HOOF_VERSION
#define HOOF_VERSION "unknown"
#endif

namespace hoof::studyfile {
namespace {

using core::kNaN;
using internal::AtomicHdf5;
using internal::WriteTable;

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

void WriteTrial(const H5::Group& trials, const std::string& group_name,
                const pipeline::TrialAnalysis& r) {
  const H5::Group g = h5::MakeGroup(trials, group_name, "trial " + r.spec.id);
  internal::H5Writer outcome(g);
  internal::SerializeOutcome(outcome, r);
  internal::H5Writer metadata(
      h5::MakeGroup(g, "metadata", "trial.json and the calibration checks"));
  internal::SerializeMetadata(metadata, r);
  // The trial's own specimen, as it was measured with: a ball without a specimen, or one given
  // in trial.json, is in no study.json.
  internal::H5Writer specimen(
      h5::MakeGroup(g, "specimen", "the trial's specimen (" + r.spec.specimen_origin + ")"));
  internal::Serialize(specimen, r.spec.specimen);
  internal::FramesWriter tracks(h5::MakeGroup(g, "tracks", "raw marker tracks"));
  internal::SerializeTracks(tracks, r);
  internal::FramesWriter poses(h5::MakeGroup(g, "poses", "body pose per frame"));
  internal::SerializePoses(poses, r);
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

/// The measured quantities of impact `k` into a `/results` or `/impacts` row (the same
/// columns, SerializeImpactMeasures); NaN where `measured` is false.
template <typename Row>
void CopyMeasures(const kinematics::ImpactKinematics& k, bool measured, Row& r) {
  const auto value = [measured](double v) { return measured ? v : kNaN; };
  r.e = value(k.e);
  r.e_se = value(k.e_se);
  r.e_ci_low = value(k.e_ci_low);
  r.e_ci_high = value(k.e_ci_high);
  r.mu_eff = value(k.mu_eff);
  r.mu_eff_se = value(k.mu_eff_se);
  r.mu_eff_ci_low = value(k.mu_eff_ci_low);
  r.mu_eff_ci_high = value(k.mu_eff_ci_high);
  r.v_SC_before_m_s = k.v_SC_before.unaryExpr(value);
  r.v_SC_after_m_s = k.v_SC_after.unaryExpr(value);
  r.v_SC_before_se_m_s = k.v_SC_before_se.unaryExpr(value);
  r.v_SC_after_se_m_s = k.v_SC_after_se.unaryExpr(value);
  r.w_before_rad_s = value(k.w_before_rad_s);
  r.w_after_rad_s = value(k.w_after_rad_s);
  r.w_before_se_rad_s = value(k.w_before_se_rad_s);
  r.w_after_se_rad_s = value(k.w_after_se_rad_s);
  r.kinetic_energy_before_J = value(k.kinetic_energy_before_J);
  r.kinetic_energy_after_J = value(k.kinetic_energy_after_J);
}

/// The `/results` row of `trial`, written into its group `group`: NaN for what was not
/// measured.
TrialResult ResultOf(const pipeline::TrialAnalysis& trial, const std::string& group) {
  const auto& k = trial.impact;
  const bool m = trial.success && k.success;
  const auto measured = [&](double v) { return m ? v : kNaN; };
  TrialResult r;
  r.id = trial.spec.id;
  r.group = group;
  r.dir = trial.spec.dir.string();
  r.specimen = trial.spec.specimen_id;
  r.surface = trial.spec.surface;
  r.surface_angle_deg = trial.spec.surface_angle_deg;
  r.fps = trial.spec.fps;
  r.nominal_speed_m_s = trial.spec.nominal_speed_m_s.value_or(kNaN);
  r.success = trial.success;
  r.error = trial.error;
  r.impact_time_s = measured(k.impact_time_s);
  CopyMeasures(k, m, r);
  r.m_per_px_used = trial.m_per_px_used;
  r.m_per_px_from_markers = trial.m_per_px_from_markers != 0.0 ? trial.m_per_px_from_markers : kNaN;
  r.surface_angle_measured_deg = trial.surface_angle_measured_deg.value_or(kNaN);
  r.out_of_plane_change = trial.poses.empty() ? kNaN : trial.out_of_plane_change;
  r.flags = trial.flags;
  return r;
}

/// The `/impacts` rows of `trial` (group `group`): every impact of its clip, or, for a trial
/// whose measurement found none, nothing.
std::vector<ImpactResult> ImpactsOf(const pipeline::TrialAnalysis& trial,
                                    const std::string& group) {
  std::vector<ImpactResult> rows;
  for (const auto& k : trial.impacts) {
    ImpactResult r;
    r.trial = trial.spec.id;
    r.group = group;
    r.impact_index = k.index;
    r.lowest_frame = k.lowest_frame;
    r.is_main = trial.impact.success && k.index == trial.impact.index;
    r.success = k.success;
    r.error = k.success ? std::string() : k.message;
    r.impact_time_s = k.impact_time_s;
    r.impact_frame = k.impact_frame;
    CopyMeasures(k, k.success, r);
    if (k.success) {
      r.fit_before_first_frame = k.before.first_frame;
      r.fit_before_last_frame = k.before.last_frame;
      r.fit_after_first_frame = k.after.first_frame;
      r.fit_after_last_frame = k.after.last_frame;
    }
    r.method = kinematics::KinematicsMethodName(k.method);
    r.impact_time_se_s = k.success ? k.impact_time_se_s : kNaN;
    r.surface_angle_W_deg = k.success ? k.surface_angle_W_deg : kNaN;
    r.p_WT_m = k.success ? k.p_WT : Eigen::Vector2d(kNaN, kNaN);
    const kinematics::ImpactLimits& L = k.limits;
    r.samples_before = L.samples_before;
    r.samples_after = L.samples_after;
    r.contact_frames = static_cast<int>(L.contact_frames.size());
    r.outlier_frames = static_cast<int>(L.outlier_frames.size());
    r.not_in_flight_frames = static_cast<int>(L.not_in_flight_frames.size());
    r.missing_frames = static_cast<int>(L.missing_frames.size());
    r.repeated_frames = static_cast<int>(L.repeated_frames.size());
    r.short_arc = L.short_arc;
    r.depth_rate_before_per_s = L.depth_rate_before_per_s;
    r.depth_rate_after_per_s = L.depth_rate_after_per_s;
    r.depth_corrected = L.depth_corrected;
    r.e_depth_shift = L.e_depth_shift;
    r.e_perspective_shift = L.e_perspective_shift;
    r.meeting_gap_m = L.meeting_gap_m;
    r.meeting_gap_se_m = L.meeting_gap_se_m;
    rows.push_back(std::move(r));
  }
  return rows;
}

/// Every row of `t` as CSV, with a header of its column names.
void WriteTableCsv(const std::filesystem::path& path, const Table& t) {
  io::WriteFileAtomically(path, [&](std::ostream& out) {
    for (std::size_t c = 0; c < t.columns.size(); ++c)
      out << (c ? "," : "") << io::CsvEscape(t.columns[c].name);
    out << "\n";
    const std::size_t rows = t.columns.empty() ? 0 : t.columns[0].size();
    for (std::size_t r = 0; r < rows; ++r) {
      for (std::size_t c = 0; c < t.columns.size(); ++c) {
        if (c) out << ",";
        out << t.columns[c].CsvCell(r);
      }
      out << "\n";
    }
  });
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
  std::vector<TrialResult> rows;
  for (std::size_t i = 0; i < trials.size(); ++i)
    rows.push_back(ResultOf(trials[i], "/trials/" + groups[i]));
  return TableWriter::Of("results", "one row per trial, in study order; NaN where not measured",
                         rows,
                         [](auto& a, const TrialResult& r) { internal::SerializeResult(a, r); });
}

Table ImpactsTable(const std::vector<pipeline::TrialAnalysis>& trials) {
  const std::vector<std::string> groups = TrialGroupNames(trials);
  std::vector<ImpactResult> rows;
  for (std::size_t i = 0; i < trials.size(); ++i)
    for (auto& r : ImpactsOf(trials[i], "/trials/" + groups[i])) rows.push_back(std::move(r));
  return TableWriter::Of(
      "impacts",
      "one row per impact found in each trial's clip, trials in study order, impacts in time "
      "order; NaN where not measured",
      rows, [](auto& a, const ImpactResult& r) { internal::SerializeImpact(a, r); });
}

std::vector<ImpactResult> ReadStudyImpacts(const std::filesystem::path& path) {
  if (!HasGroup(path, "/impacts")) return {};
  return TableReader::Read<ImpactResult>(
      ReadTable(path, "/impacts"), path.string() + ":/impacts",
      [](auto& a, ImpactResult& r) { internal::SerializeImpact(a, r); });
}

void WriteImpactsCsv(const std::filesystem::path& path,
                     const std::vector<pipeline::TrialAnalysis>& trials) {
  WriteTableCsv(path, ImpactsTable(trials));
}

void WriteStudyFile(const std::filesystem::path& path, const StudyInfo& info,
                    const std::vector<pipeline::TrialAnalysis>& trials,
                    const std::function<void(std::size_t)>& after_trial) {
  const Table results = ResultsTable(trials);
  results.Validate();
  const Table impacts = ImpactsTable(trials);
  impacts.Validate();
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
        WriteTable(root, impacts);
        file.flush(H5F_SCOPE_GLOBAL);
      });
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
