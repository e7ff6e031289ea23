#pragma once
/// @file
/// The study file: one HDF5 file per study that holds everything measured (docs/hdf5-schema.md).
///
/// Layout in short: root attributes (format, name, study_dir, hoofimpact_version, created_utc,
/// command_line); `/study` (specimens, analysis options, warnings); `/trials/<id>` per trial
/// (metadata, tracks, poses, fits, results, flags, warnings, success, error); `/results`, a flat
/// table with one row per trial; `/impacts`, one row per impact of every trial's clip; and groups
/// of named tables that later steps add (`/stats`,
/// `/discovery`) through WriteTables().
///
/// Every file is written atomically: to a temporary file beside the target, renamed over it only
/// when complete (io::TemporaryPathFor, io::CommitTemporary). Adding tables to an existing file
/// copies it to a temporary file, changes the copy and renames it, so a crash or an error leaves
/// the previous file as it was.
///
/// Every dataset carries a `units` attribute ("m/s", "px", "rad", "1" for dimensionless numbers,
/// "" for text, booleans and labels) and a `description` attribute. Values that were not
/// measured are NaN. Booleans are uint8 0/1; text is variable-length UTF-8.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <Eigen/Core>

#include "pipeline/study_format.h"
#include "pipeline/trial_analysis.h"

namespace hoof::studyfile {

/// Value of the root attribute `format`; the reader refuses other values.
inline constexpr const char* kStudyFileFormat = "hoofimpact-study-h5/1";

/// The study as a whole: what the root attributes and `/study` hold.
struct StudyInfo {
  std::string name;                 ///< study.json "name"
  std::filesystem::path study_dir;  ///< the study folder that was analysed
  /// Program version; empty = the version this library was built with.
  std::string hoofimpact_version;
  /// Creation time, ISO 8601 UTC ("2024-05-01T12:00:00Z"); empty = now.
  std::string created_utc;
  std::string command_line;  ///< how the file was made (free text; may be empty)
  std::map<std::string, pipeline::SpecimenSpec> specimens;
  pipeline::TrialAnalysisOptions options;  ///< the analysis options every trial used
  std::vector<std::string> warnings;       ///< study-level warnings (study.json and the like)

  /// The info of `study` measured with `options`: its name, absolute folder, specimens and
  /// warnings; version and time are filled when the file is written.
  static StudyInfo Of(const pipeline::StudySpec& study,
                      const pipeline::TrialAnalysisOptions& options, std::string command_line = {});
};

/// One column of a Table: numbers, integers or text, with its unit and meaning.
struct Column {
  std::string name;   ///< dataset name; no '/'
  std::string units;  ///< "m/s", "1" (dimensionless), "" (text, labels, booleans)
  std::string description;
  std::variant<std::vector<double>, std::vector<std::int64_t>, std::vector<std::string>> values;

  /// Number of rows.
  std::size_t size() const;
  /// Row `row` as CSV text: a round-trip number, an integer, or an escaped string.
  std::string CsvCell(std::size_t row) const;
  /// Column of doubles (IEEE 64-bit little-endian in the file).
  static Column Numbers(std::string name, std::string units, std::string description,
                        std::vector<double> values);
  /// Column of integers (64-bit signed in the file).
  static Column Integers(std::string name, std::string units, std::string description,
                         std::vector<std::int64_t> values);
  /// Column of text (variable-length UTF-8 strings; units "").
  static Column Texts(std::string name, std::string description, std::vector<std::string> values);
};

/// A table of named columns of equal length: written as one group holding one 1-D dataset per
/// column (what MATLAB's h5read and h5py read most directly), with the group attributes
/// `description` and `columns` (the column names in order) and `rows`.
struct Table {
  /// Path of the table's group below the group it is written into; may contain '/' to nest
  /// ("e/by_surface/anova"). Not empty, no leading '/'.
  std::string name;
  std::string description;
  std::vector<Column> columns;

  /// Throws std::invalid_argument naming the table and the column when a name is empty or
  /// repeated, contains '/', or the columns differ in length.
  void Validate() const;
  /// The column called `name`; throws std::out_of_range naming the table otherwise.
  const Column& Get(const std::string& name) const;
};

/// Writes the study file `path` atomically: the study info, every trial of `trials` (failed ones
/// too, with their reason) under `/trials/<id>`, the `/results` table in the order of `trials`
/// and the `/impacts` table. `after_trial(i)`, when set, is called after trial i is written (for
/// progress); an exception from it, like any other failure, aborts the write, removes the temporary
/// file and leaves `path` as it was. Throws std::runtime_error naming the file on HDF5 or
/// filesystem errors. Creates missing parent directories.
void WriteStudyFile(const std::filesystem::path& path, const StudyInfo& info,
                    const std::vector<pipeline::TrialAnalysis>& trials,
                    const std::function<void(std::size_t)>& after_trial = {});

/// Replaces the group `group` (absolute, e.g. "/stats" or "/discovery/run1"; created with its
/// parents when missing) of the existing study file `path` with `tables`, atomically (copy,
/// change, rename). The group gets the attribute `description`. Tables are validated before the
/// file is touched. `after_table(i)` as in WriteStudyFile. Throws std::runtime_error naming the
/// file when it is missing or not a study file, and std::invalid_argument for a bad table.
/// Space of a replaced group is not reclaimed (h5repack does that).
/// `soft_links`: (link, target) pairs of absolute paths; after the tables are written each
/// `link` becomes an HDF5 soft link to `target` (an existing link or object there is replaced),
/// in the same atomic update, so data kept in one place can be found under each trial too.
void WriteTables(const std::filesystem::path& path, const std::string& group,
                 const std::string& description, const std::vector<Table>& tables,
                 const std::function<void(std::size_t)>& after_table = {},
                 const std::vector<std::pair<std::string, std::string>>& soft_links = {});

/// Whether the study file `path` has the group (or table) `group_path` (absolute, e.g.
/// "/stats" or "/discovery/options"). Throws std::runtime_error naming the file when it is
/// missing or not an HDF5 file.
bool HasGroup(const std::filesystem::path& path, const std::string& group_path);

/// Reads the table whose group is `table_path` (absolute, e.g. "/results" or
/// "/stats/e/by_surface/anova") back, columns in their written order; its name is the path
/// without the leading '/'. Throws
/// std::runtime_error naming the file and the path.
Table ReadTable(const std::filesystem::path& path, const std::string& table_path);

/// One trial as the `/results` table and its `/trials/<id>` group give it. Vectors in S are
/// [along the surface (down-slope), normal]. NaN where not measured (every measured value of
/// a failed trial).
struct TrialResult {
  std::string id;
  std::string group;  ///< its group in the file, "/trials/<id>"
  std::string dir;    ///< trial folder
  std::string specimen;
  std::string surface;
  double surface_angle_deg = 0.0;
  double fps = 0.0;                ///< 1/s
  double nominal_speed_m_s = 0.0;  ///< NaN when trial.json does not give it
  bool success = false;
  std::string error;  ///< why it failed; empty on success
  double impact_time_s = 0.0;
  double e = 0.0, e_se = 0.0, e_ci_low = 0.0, e_ci_high = 0.0;
  double mu_eff = 0.0, mu_eff_se = 0.0, mu_eff_ci_low = 0.0, mu_eff_ci_high = 0.0;
  Eigen::Vector2d v_SC_before_m_s{0, 0}, v_SC_after_m_s{0, 0};
  Eigen::Vector2d v_SC_before_se_m_s{0, 0}, v_SC_after_se_m_s{0, 0};
  double w_before_rad_s = 0.0, w_after_rad_s = 0.0;
  double w_before_se_rad_s = 0.0, w_after_se_rad_s = 0.0;
  double kinetic_energy_before_J = 0.0, kinetic_energy_after_J = 0.0;
  double m_per_px_used = 0.0;
  double m_per_px_from_markers = 0.0;       ///< NaN when it could not be measured
  double surface_angle_measured_deg = 0.0;  ///< NaN when not measured
  double out_of_plane_change = 0.0;         ///< range of the marker distance ratio (1)
  std::vector<std::string> flags;
  std::vector<std::string> warnings;
};

/// One impact of a trial as the `/impacts` table gives it: one row per impact found, trials in
/// study order and each trial's impacts in time order (docs/hdf5-schema.md). The measured
/// fields are those of TrialResult, NaN where the impact was not measured.
struct ImpactResult {
  std::string trial;      ///< trial id
  std::string group;      ///< the trial's group in the file, "/trials/<id>"
  int impact_index = 0;   ///< 0 = the clip's first impact
  int lowest_frame = -1;  ///< the frame where it was found
  bool is_main = false;   ///< this impact is the trial's result in /results
  bool success = false;   ///< measured
  std::string error;      ///< why it was not measured; empty when it was
  double impact_time_s = 0.0;
  int impact_frame = -1;
  double e = 0.0, e_se = 0.0, e_ci_low = 0.0, e_ci_high = 0.0;
  double mu_eff = 0.0, mu_eff_se = 0.0, mu_eff_ci_low = 0.0, mu_eff_ci_high = 0.0;
  Eigen::Vector2d v_SC_before_m_s{0, 0}, v_SC_after_m_s{0, 0};
  Eigen::Vector2d v_SC_before_se_m_s{0, 0}, v_SC_after_se_m_s{0, 0};
  double w_before_rad_s = 0.0, w_after_rad_s = 0.0;
  double w_before_se_rad_s = 0.0, w_after_se_rad_s = 0.0;
  double kinetic_energy_before_J = 0.0, kinetic_energy_after_J = 0.0;
  int fit_before_first_frame = -1, fit_before_last_frame = -1;  ///< -1 when not measured
  int fit_after_first_frame = -1, fit_after_last_frame = -1;
  /// How it was measured and what limited it (kinematics::ImpactKinematics's method,
  /// impact_time_se_s, surface_angle_W_deg, p_WT and limits; the frame lists as counts).
  std::string method;  ///< "windows" or "arcs"
  double impact_time_se_s = 0.0, surface_angle_W_deg = 0.0;
  Eigen::Vector2d p_WT_m{0, 0};
  int samples_before = 0, samples_after = 0;
  int contact_frames = 0, outlier_frames = 0, not_in_flight_frames = 0, missing_frames = 0,
      repeated_frames = 0;
  bool short_arc = false, depth_corrected = false;
  double depth_rate_before_per_s = 0.0, depth_rate_after_per_s = 0.0, e_depth_shift = 0.0,
         e_perspective_shift = 0.0;
  double meeting_gap_m = 0.0, meeting_gap_se_m = 0.0;
};

/// The `/impacts` table for `trials` (also what WriteImpactsCsv writes).
Table ImpactsTable(const std::vector<pipeline::TrialAnalysis>& trials);

/// Reads `/impacts` back; empty for a file written before it existed. Throws std::runtime_error
/// naming the file and the malformed item.
std::vector<ImpactResult> ReadStudyImpacts(const std::filesystem::path& path);

/// Writes the per-impact results as CSV (one row per impact; the columns of `/impacts`),
/// atomically.
void WriteImpactsCsv(const std::filesystem::path& path,
                     const std::vector<pipeline::TrialAnalysis>& trials);

/// What ReadStudyResults returns.
struct StudyResults {
  std::string name;
  std::string study_dir;
  std::string hoofimpact_version;
  std::string created_utc;
  std::string command_line;         ///< how the file was made; "" when not recorded
  std::vector<TrialResult> trials;  ///< in the order of `/results`
};

/// Reads the root attributes, `/results` and each trial's flags and warnings. Throws
/// std::runtime_error naming the file and the missing or malformed item.
StudyResults ReadStudyResults(const std::filesystem::path& path);

/// Reads every trial of the study file back as the analysis that wrote it: spec (metadata,
/// specimen, camera), success and error, tracks, poses, the before and after fits, the impact
/// results, the calibration checks, flags and warnings, in the order of `/results`. Enough to
/// simulate a trial against its measurement (compare::CompareTrial) without the frames. Fields
/// the file does not hold (the frame file pattern or video) are left at their defaults. Throws
/// std::runtime_error naming the file and the missing or malformed item.
std::vector<pipeline::TrialAnalysis> ReadTrialAnalyses(const std::filesystem::path& path);

/// The kinematics options the study's trials were measured with (`/study/analysis_options`).
/// Throws std::runtime_error naming the file and the missing or invalid item.
kinematics::KinematicsOptions ReadKinematicsOptions(const std::filesystem::path& path);

/// Writes the per-trial results as CSV (one row per trial; the columns of `/results`),
/// atomically.
void WriteResultsCsv(const std::filesystem::path& path,
                     const std::vector<pipeline::TrialAnalysis>& trials);

/// Writes the tracks of all trials as one long CSV (one row per trial, frame and marker:
/// trial, frame, t_s, marker, found, x_px, y_px, status, quality, then the frame's pose),
/// atomically.
void WriteTracksCsv(const std::filesystem::path& path,
                    const std::vector<pipeline::TrialAnalysis>& trials);

/// The `/results` table for `trials` (also what WriteResultsCsv writes).
Table ResultsTable(const std::vector<pipeline::TrialAnalysis>& trials);

/// Group names of `trials` below `/trials`: the id with '/' replaced by '_', made unique with
/// a suffix "_2", "_3", ... when ids repeat; an empty id becomes "trial_<index>".
std::vector<std::string> TrialGroupNames(const std::vector<pipeline::TrialAnalysis>& trials);

/// The current time in UTC as ISO 8601 ("2026-11-22T21:04:51Z"), as study files record it.
std::string NowUtc();

}  // namespace hoof::studyfile
