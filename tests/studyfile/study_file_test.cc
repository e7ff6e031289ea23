// Tests of the HDF5 study file: trials built here with known numbers are written, then read
// back twice: with ReadStudyResults/ReadTable, and independently with the raw HDF5 C API
// (shapes, values, `units` and `description` on every dataset). Atomicity: failed writes leave
// the previous file byte for byte and no temporary file.
#include "studyfile/study_file.h"

#include <hdf5.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/csv.h"
#include "support/paper_specimen.h"

namespace hoof::studyfile {
namespace {

namespace fs = std::filesystem;

fs::path Dir(const std::string& name) {
  const fs::path dir = fs::path(HOOF_BINARY_DIR) / "study_file_test" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string Bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// Files in `dir` other than `keep`.
std::vector<std::string> Others(const fs::path& dir, const fs::path& keep) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path() != keep) out.push_back(e.path().filename().string());
  return out;
}

/// A measured trial: 3 frames x 2 markers, marker 2 lost in frame 1, and known results.
pipeline::TrialAnalysis GoodTrial(const std::string& id, const std::string& surface, double angle,
                                  double e) {
  pipeline::TrialAnalysis r;
  r.spec.id = id;
  r.spec.dir = "/data/" + id;
  r.spec.specimen_id = "A";
  r.spec.specimen = hoof::testing::PaperSpecimenSpec();
  r.spec.surface = surface;
  r.spec.surface_angle_deg = angle;
  r.spec.fps = 8000.0;
  r.spec.nominal_speed_m_s = 3.0;
  r.spec.frames.pattern = "frames/%06d.png";
  r.spec.frames.count = 3;
  r.spec.camera.m_per_px = 2e-4;
  r.success = true;
  r.tracks.names = {"M1", "M2"};
  for (int f = 0; f < 3; ++f) {
    std::vector<tracking::MarkerObservation> row(2);
    for (int m = 0; m < 2; ++m) {
      row[m].found = !(f == 1 && m == 1);
      row[m].p_I = {100.0 + 10 * m + 0.25 * f, 50.0 + 2.0 * f};
      row[m].quality = 20.0 + f;
      row[m].radius_px = 4.0;
      row[m].status = row[m].found ? "ok" : "lost";
    }
    r.tracks.frames.push_back(row);
    tracking::BodyPose pose;
    pose.valid = f != 1;
    pose.p_WE = {0.02 + 0.001 * f, 0.05 - 0.0004 * f};
    pose.theta_W_rad = 1.5 + 0.01 * f;
    pose.rms_residual_m = 1e-6;
    pose.markers_used = pose.valid ? 2 : 1;
    pose.marker_distance_m = 0.018;
    r.poses.push_back(pose);
  }
  r.marker_distance_ratio = {1.0, std::numeric_limits<double>::quiet_NaN(), 0.999};
  auto& k = r.impact;
  k.success = true;
  k.impact_time_s = 0.0031;
  k.impact_frame = 24;
  k.before.first_frame = 5;
  k.before.last_frame = 24;
  k.before.n = 20;
  k.before.v_WC = {1.0, -3.0};
  k.before.cov_v_WC << 1e-6, 2e-7, 2e-7, 4e-6;
  k.after.first_frame = 27;
  k.after.last_frame = 46;
  k.after.n = 20;
  k.v_SC_before = {1.026, -2.819};
  k.v_SC_after = {-0.033, 2.216};
  k.v_SC_before_se = {0.001, 0.002};
  k.w_after_rad_s = 1.5;
  k.e = e;
  k.e_se = 1e-4;
  k.e_ci_low = e - 2e-4;
  k.e_ci_high = e + 2e-4;
  k.mu_eff = 0.21;
  k.mu_eff_se = 5e-5;
  r.m_per_px_used = 2e-4;
  r.m_per_px_from_markers = 2.0001e-4;
  r.surface_angle_measured_deg = angle + 0.1;
  r.flags = {"out_of_plane", "lost_marker"};
  r.warnings = {"marker M2 lost in frame 1"};
  return r;
}

/// A trial whose trial.json could not be read: nothing measured.
pipeline::TrialAnalysis FailedTrial() {
  pipeline::TrialAnalysis r;
  r.spec.id = "broken";
  r.spec.dir = "/data/broken";
  r.error = "/data/broken/trial.json: missing field \"fps\"";
  return r;
}

std::vector<pipeline::TrialAnalysis> Trials() {
  return {GoodTrial("steel_20deg_r1", "steel", 20.0, 0.7886),
          GoodTrial("concrete_0deg_r1", "concrete", 0.0, 0.61), FailedTrial()};
}

StudyInfo Info() {
  StudyInfo info;
  info.name = "unit-study";
  info.study_dir = "/data";
  info.created_utc = "2024-05-01T12:00:00Z";
  info.specimens["A"] = hoof::testing::PaperSpecimenSpec();
  info.options.kinematics.fit_frames = 17;
  return info;
}

// ------------------------------------------------------------------------------------------
// Independent reading with the HDF5 C API.
// ------------------------------------------------------------------------------------------

class RawFile {
 public:
  explicit RawFile(const fs::path& p) : id_(H5Fopen(p.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT)) {}
  ~RawFile() {
    if (id_ >= 0) H5Fclose(id_);
  }
  RawFile(const RawFile&) = delete;
  RawFile& operator=(const RawFile&) = delete;
  hid_t id() const { return id_; }

  std::vector<hsize_t> Dims(const std::string& path) const {
    const hid_t d = H5Dopen2(id_, path.c_str(), H5P_DEFAULT);
    EXPECT_GE(d, 0) << path;
    const hid_t s = H5Dget_space(d);
    std::vector<hsize_t> dims(static_cast<std::size_t>(H5Sget_simple_extent_ndims(s)));
    if (!dims.empty()) H5Sget_simple_extent_dims(s, dims.data(), nullptr);
    H5Sclose(s);
    H5Dclose(d);
    return dims;
  }
  std::vector<double> Doubles(const std::string& path) const {
    const hid_t d = H5Dopen2(id_, path.c_str(), H5P_DEFAULT);
    const hid_t s = H5Dget_space(d);
    std::vector<double> v(static_cast<std::size_t>(H5Sget_simple_extent_npoints(s)));
    EXPECT_GE(H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), 0) << path;
    H5Sclose(s);
    H5Dclose(d);
    return v;
  }
  std::vector<std::string> Strings(const std::string& path) const {
    const hid_t d = H5Dopen2(id_, path.c_str(), H5P_DEFAULT);
    const hid_t s = H5Dget_space(d);
    const hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_size(t, H5T_VARIABLE);
    H5Tset_cset(t, H5T_CSET_UTF8);  // the file's text is UTF-8; HDF5 will not convert ASCII
    std::vector<char*> p(static_cast<std::size_t>(H5Sget_simple_extent_npoints(s)));
    std::vector<std::string> out;
    if (!p.empty() && H5Dread(d, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, p.data()) >= 0) {
      for (char* c : p) out.emplace_back(c ? c : "");
      H5Dvlen_reclaim(t, s, H5P_DEFAULT, p.data());
    }
    H5Tclose(t);
    H5Sclose(s);
    H5Dclose(d);
    return out;
  }
  /// A text attribute of the object at `path`.
  std::string Attr(const std::string& path, const std::string& name) const {
    const hid_t a = H5Aopen_by_name(id_, path.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT);
    if (a < 0) return "<missing>";
    const hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_size(t, H5T_VARIABLE);
    H5Tset_cset(t, H5T_CSET_UTF8);  // the file's text is UTF-8; HDF5 will not convert ASCII
    char* c = nullptr;
    std::string out = "<unreadable>";
    if (H5Aread(a, t, &c) >= 0 && c) {
      out = c;
      H5free_memory(c);
    }
    H5Tclose(t);
    H5Aclose(a);
    return out;
  }

 private:
  hid_t id_;
};

/// Every dataset of the file, with whether it has `units` and `description` attributes.
struct DatasetCheck {
  int datasets = 0;
  std::vector<std::string> missing;
};

herr_t VisitDataset(hid_t obj, const char* name, const H5O_info_t* info, void* data) {
  auto* check = static_cast<DatasetCheck*>(data);
  if (info->type != H5O_TYPE_DATASET) return 0;
  ++check->datasets;
  for (const char* attr : {"units", "description"})
    if (H5Aexists_by_name(obj, name, attr, H5P_DEFAULT) <= 0)
      check->missing.push_back(std::string(name) + " lacks " + attr);
  return 0;
}

TEST(StudyFileTest, WrittenTrialsReadBackWithTheRawCApi) {
  const fs::path file = Dir("raw") / "study.h5";
  WriteStudyFile(file, Info(), Trials());
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  RawFile raw(file);
  ASSERT_GE(raw.id(), 0);
  EXPECT_EQ(raw.Attr("/", "format"), "hoofimpact-study-h5/1");
  EXPECT_EQ(raw.Attr("/", "name"), "unit-study");
  EXPECT_EQ(raw.Attr("/", "created_utc"), "2024-05-01T12:00:00Z");

  // /results: one row per trial, in the order given.
  EXPECT_EQ(raw.Dims("/results/e"), (std::vector<hsize_t>{3}));
  const auto e = raw.Doubles("/results/e");
  EXPECT_EQ(e[0], 0.7886);
  EXPECT_EQ(e[1], 0.61);
  EXPECT_TRUE(std::isnan(e[2]));
  EXPECT_EQ(raw.Strings("/results/id"),
            (std::vector<std::string>{"steel_20deg_r1", "concrete_0deg_r1", "broken"}));
  EXPECT_EQ(raw.Doubles("/results/success"), (std::vector<double>{1, 1, 0}));
  EXPECT_EQ(raw.Strings("/results/flags")[0], "out_of_plane;lost_marker");
  EXPECT_EQ(raw.Doubles("/results/v_SC_after_y_m_s")[0], 2.216);
  EXPECT_EQ(raw.Attr("/results/v_SC_after_y_m_s", "units"), "m/s");
  EXPECT_EQ(raw.Attr("/results/e", "units"), "1");
  EXPECT_EQ(raw.Attr("/results/surface_angle_deg", "units"), "deg");

  // One trial's group: tracks [frame, marker, 2], NaN where the marker was lost.
  const std::string t = "/trials/steel_20deg_r1";
  EXPECT_EQ(raw.Dims(t + "/tracks/p_I_px"), (std::vector<hsize_t>{3, 2, 2}));
  EXPECT_EQ(raw.Attr(t + "/tracks/p_I_px", "units"), "px");
  const auto p = raw.Doubles(t + "/tracks/p_I_px");
  EXPECT_EQ(p[(2 * 2 + 1) * 2 + 0], 100.0 + 10 + 0.5);  // frame 2, marker M2, x
  EXPECT_EQ(p[(2 * 2 + 1) * 2 + 1], 54.0);              // frame 2, marker M2, y
  EXPECT_TRUE(std::isnan(p[(1 * 2 + 1) * 2]));          // frame 1, M2 lost
  EXPECT_EQ(raw.Doubles(t + "/tracks/found"), (std::vector<double>{1, 1, 1, 0, 1, 1}));
  EXPECT_EQ(raw.Strings(t + "/tracks/status")[3], "lost");
  EXPECT_EQ(raw.Dims(t + "/poses/p_WE_m"), (std::vector<hsize_t>{3, 2}));
  EXPECT_EQ(raw.Doubles(t + "/poses/p_WE_m")[5], 0.05 - 0.0008);
  EXPECT_EQ(raw.Attr(t + "/poses/theta_W_rad", "units"), "rad");
  EXPECT_EQ(raw.Doubles(t + "/poses/marker_distance_ratio")[2], 0.999);
  EXPECT_EQ(raw.Dims(t + "/fits/before/cov_v_WC_m2_s2"), (std::vector<hsize_t>{2, 2}));
  EXPECT_EQ(raw.Doubles(t + "/fits/before/cov_v_WC_m2_s2"),
            (std::vector<double>{1e-6, 2e-7, 2e-7, 4e-6}));
  EXPECT_EQ(raw.Doubles(t + "/fits/before/n"), (std::vector<double>{20}));
  EXPECT_EQ(raw.Dims(t + "/results/e"), (std::vector<hsize_t>{}));  // scalar
  EXPECT_EQ(raw.Doubles(t + "/results/v_SC_before_m_s"), (std::vector<double>{1.026, -2.819}));
  EXPECT_EQ(raw.Doubles(t + "/metadata/nominal_speed_m_s"), (std::vector<double>{3.0}));
  EXPECT_EQ(raw.Strings(t + "/flags"), (std::vector<std::string>{"out_of_plane", "lost_marker"}));
  EXPECT_EQ(raw.Doubles("/study/specimens/A/markers_B_m"),
            (std::vector<double>{0.006, 0.0, 0.024, 0.0}));
  EXPECT_EQ(raw.Doubles("/study/analysis_options/fit_frames"), (std::vector<double>{17}));

  // The failed trial is stored with its reason, and without fits or results.
  EXPECT_EQ(raw.Strings("/trials/broken/error")[0],
            "/data/broken/trial.json: missing field \"fps\"");
  EXPECT_EQ(raw.Doubles("/trials/broken/success"), (std::vector<double>{0}));
  EXPECT_LE(H5Lexists(raw.id(), "/trials/broken/results", H5P_DEFAULT), 0);

  DatasetCheck check;
  H5Ovisit2(raw.id(), H5_INDEX_NAME, H5_ITER_NATIVE, VisitDataset, &check, H5O_INFO_BASIC);
  EXPECT_GT(check.datasets, 150);
  EXPECT_TRUE(check.missing.empty()) << check.missing.front();
}

TEST(StudyFileTest, ReadStudyResultsReturnsWhatWasWritten) {
  const fs::path file = Dir("reader") / "study.h5";
  const auto trials = Trials();
  WriteStudyFile(file, Info(), trials);
  const StudyResults s = ReadStudyResults(file);
  EXPECT_EQ(s.name, "unit-study");
  EXPECT_EQ(s.study_dir, "/data");
  EXPECT_FALSE(s.hoofimpact_version.empty());
  ASSERT_EQ(s.trials.size(), 3u);
  const TrialResult& a = s.trials[0];
  EXPECT_EQ(a.id, "steel_20deg_r1");
  EXPECT_EQ(a.group, "/trials/steel_20deg_r1");
  EXPECT_EQ(a.surface, "steel");
  EXPECT_EQ(a.specimen, "A");
  EXPECT_EQ(a.surface_angle_deg, 20.0);
  EXPECT_EQ(a.fps, 8000.0);
  EXPECT_EQ(a.nominal_speed_m_s, 3.0);
  EXPECT_TRUE(a.success);
  EXPECT_EQ(a.e, 0.7886);
  EXPECT_EQ(a.e_ci_high, 0.7886 + 2e-4);
  EXPECT_EQ(a.mu_eff_se, 5e-5);
  EXPECT_EQ(a.v_SC_before_m_s, Eigen::Vector2d(1.026, -2.819));
  EXPECT_EQ(a.v_SC_before_se_m_s, Eigen::Vector2d(0.001, 0.002));
  EXPECT_EQ(a.w_after_rad_s, 1.5);
  EXPECT_EQ(a.impact_time_s, 0.0031);
  EXPECT_EQ(a.m_per_px_from_markers, 2.0001e-4);
  EXPECT_EQ(a.surface_angle_measured_deg, 20.1);
  EXPECT_EQ(a.flags, (std::vector<std::string>{"out_of_plane", "lost_marker"}));
  EXPECT_EQ(a.warnings, (std::vector<std::string>{"marker M2 lost in frame 1"}));
  const TrialResult& b = s.trials[2];
  EXPECT_EQ(b.id, "broken");
  EXPECT_FALSE(b.success);
  EXPECT_EQ(b.error, "/data/broken/trial.json: missing field \"fps\"");
  EXPECT_TRUE(std::isnan(b.e));
  EXPECT_TRUE(std::isnan(b.nominal_speed_m_s));
  EXPECT_TRUE(std::isnan(b.m_per_px_from_markers));
}

TEST(StudyFileTest, TheKinematicsOptionsReadBackAsWritten) {
  const fs::path file = Dir("kinematics_options") / "study.h5";
  StudyInfo info = Info();
  info.options.kinematics.min_fit_frames = 5;
  info.options.kinematics.max_contact_s = 80e-6;
  info.options.kinematics.exposure_s = 1e-4;
  info.options.kinematics.gravity_m_s2 = 9.80665;
  info.options.kinematics.confidence = 0.9;
  WriteStudyFile(file, info, Trials());
  const hoof::kinematics::KinematicsOptions k = ReadKinematicsOptions(file);
  EXPECT_EQ(k.fit_frames, 17);
  EXPECT_EQ(k.min_fit_frames, 5);
  EXPECT_EQ(k.max_contact_s, 80e-6);
  EXPECT_EQ(k.exposure_s, 1e-4);
  EXPECT_EQ(k.gravity_m_s2, 9.80665);
  EXPECT_EQ(k.confidence, 0.9);
  EXPECT_THROW(ReadKinematicsOptions(Dir("kinematics_options") / "missing.h5"), std::runtime_error);
}

TEST(StudyFileTest, RepeatedAndSlashedIdsGetDistinctGroups) {
  auto trials = Trials();
  trials[1].spec.id = "steel_20deg_r1";
  trials[2].spec.id = "a/b";
  EXPECT_EQ(TrialGroupNames(trials),
            (std::vector<std::string>{"steel_20deg_r1", "steel_20deg_r1_2", "a_b"}));
  const fs::path file = Dir("names") / "study.h5";
  WriteStudyFile(file, Info(), trials);
  const StudyResults s = ReadStudyResults(file);
  EXPECT_EQ(s.trials[1].group, "/trials/steel_20deg_r1_2");
  EXPECT_EQ(s.trials[1].id, "steel_20deg_r1");
  EXPECT_EQ(s.trials[2].id, "a/b");
}

TEST(StudyFileTest, TablesAreAddedAndReplacedAndReadBack) {
  const fs::path file = Dir("tables") / "study.h5";
  WriteStudyFile(file, Info(), Trials());
  Table anova{"e/by_surface/anova", "one-way ANOVA", {}};
  anova.columns = {Column::Texts("source", "row", {"between", "within"}),
                   Column::Integers("df", "1", "degrees of freedom", {1, 4}),
                   Column::Numbers("f", "1", "F statistic", {12.5, std::nan("")})};
  WriteTables(file, "/stats", "statistics", {anova});
  Table back = ReadTable(file, "/stats/e/by_surface/anova");
  ASSERT_EQ(back.columns.size(), 3u);
  EXPECT_EQ(back.columns[0].name, "source");
  EXPECT_EQ(std::get<std::vector<std::string>>(back.Get("source").values),
            (std::vector<std::string>{"between", "within"}));
  EXPECT_EQ(std::get<std::vector<std::int64_t>>(back.Get("df").values),
            (std::vector<std::int64_t>{1, 4}));
  EXPECT_EQ(std::get<std::vector<double>>(back.Get("f").values)[0], 12.5);
  EXPECT_EQ(back.Get("f").units, "1");
  {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    RawFile raw(file);
    EXPECT_EQ(raw.Attr("/stats/e/by_surface/anova/f", "description"), "F statistic");
    EXPECT_EQ(raw.Attr("/stats", "description"), "statistics");
  }

  // Replacing /stats drops the old tables; the trials stay.
  Table other{"summary", "", {Column::Numbers("x", "m", "a length", {1.0})}};
  WriteTables(file, "/stats", "statistics again", {other});
  EXPECT_THROW(ReadTable(file, "/stats/e/by_surface/anova"), std::runtime_error);
  EXPECT_EQ(std::get<std::vector<double>>(ReadTable(file, "/stats/summary").Get("x").values)[0],
            1.0);
  EXPECT_EQ(ReadStudyResults(file).trials.size(), 3u);
  // A nested group whose parents do not exist yet.
  WriteTables(file, "/discovery/run1", "later", {other});
  EXPECT_EQ(ReadTable(file, "/discovery/run1/summary").columns.size(), 1u);
  EXPECT_EQ(Others(file.parent_path(), file), std::vector<std::string>{});
}

TEST(StudyFileTest, BadTablesAreRejectedBeforeTheFileIsTouched) {
  const fs::path file = Dir("bad_tables") / "study.h5";
  WriteStudyFile(file, Info(), Trials());
  const std::string before = Bytes(file);
  Table t{
      "t", "", {Column::Numbers("a", "1", "", {1.0, 2.0}), Column::Numbers("b", "1", "", {1.0})}};
  try {
    WriteTables(file, "/stats", "", {t});
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("column \"b\" has 1 rows"), std::string::npos) << e.what();
  }
  EXPECT_EQ(Bytes(file), before);
}

TEST(StudyFileTest, AFailedWriteLeavesThePreviousFileAndNoTemporary) {
  const fs::path dir = Dir("atomic");
  const fs::path file = dir / "study.h5";
  WriteStudyFile(file, Info(), Trials());
  const std::string before = Bytes(file);

  // A failure after one trial was written (a callback that throws).
  auto trials = Trials();
  trials[0].spec.id = "renamed";
  EXPECT_THROW(WriteStudyFile(file, Info(), trials,
                              [](std::size_t i) {
                                if (i == 1) throw std::runtime_error("disk full (simulated)");
                              }),
               std::runtime_error);
  EXPECT_EQ(Bytes(file), before);
  EXPECT_EQ(Others(dir, file), std::vector<std::string>{});

  // The same while adding tables to the existing file.
  Table t{"t", "", {Column::Numbers("a", "1", "", {1.0})}};
  EXPECT_THROW(WriteTables(file, "/stats", "", {t, t},
                           [](std::size_t) { throw std::runtime_error("simulated"); }),
               std::runtime_error);
  EXPECT_EQ(Bytes(file), before);
  EXPECT_EQ(Others(dir, file), std::vector<std::string>{});

  // Two tables of the same name: HDF5 refuses the second; the error names the file.
  try {
    WriteTables(file, "/stats", "", {t, t});
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
  EXPECT_EQ(Bytes(file), before);
  EXPECT_EQ(Others(dir, file), std::vector<std::string>{});

  // An unwritable target (its parent is a regular file).
  const fs::path blocker = dir / "not_a_dir";
  std::ofstream(blocker) << "x";
  EXPECT_THROW(WriteStudyFile(blocker / "study.h5", Info(), Trials()), std::runtime_error);
  EXPECT_EQ(Bytes(file), before);
}

TEST(StudyFileTest, ReaderNamesTheFileForWhatIsNotAStudyFile) {
  const fs::path dir = Dir("not_study");
  const fs::path text = dir / "notes.h5";
  std::ofstream(text) << "not hdf5";
  try {
    ReadStudyResults(text);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(text.string()), std::string::npos) << e.what();
  }
  try {
    ReadStudyResults(dir / "missing.h5");
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("missing.h5"), std::string::npos) << e.what();
  }
}

TEST(StudyFileTest, CsvExportsHoldEveryTrialAndEveryMarker) {
  const fs::path dir = Dir("csv");
  const auto trials = Trials();
  WriteResultsCsv(dir / "results.csv", trials);
  WriteTracksCsv(dir / "tracks.csv", trials);
  const io::CsvTable results = io::CsvTable::Read(dir / "results.csv");
  ASSERT_EQ(results.rows(), 3u);
  EXPECT_EQ(results.Text(2, results.Column("id")), "broken");
  EXPECT_EQ(results.Number(0, results.Column("e")), 0.7886);
  EXPECT_EQ(results.Number(1, results.Column("v_SC_before_y_m_s")), -2.819);
  EXPECT_EQ(results.Text(2, results.Column("e")), "nan");
  EXPECT_EQ(results.Text(2, results.Column("error")),
            "/data/broken/trial.json: missing field \"fps\"");
  const io::CsvTable tracks = io::CsvTable::Read(dir / "tracks.csv");
  ASSERT_EQ(tracks.rows(), 2u * 3u * 2u);  // two tracked trials x 3 frames x 2 markers
  EXPECT_EQ(tracks.Text(3, tracks.Column("marker")), "M2");
  EXPECT_EQ(tracks.Text(3, tracks.Column("status")), "lost");
  EXPECT_EQ(tracks.Text(3, tracks.Column("x_px")), "");
  EXPECT_EQ(tracks.Number(5, tracks.Column("x_px")), 110.5);
  EXPECT_EQ(Others(dir, dir / "results.csv"), std::vector<std::string>{"tracks.csv"});
}

/// A trial whose clip holds three impacts: the first measured (the trial's result), the second
/// measured with other numbers, the third found but not measured.
pipeline::TrialAnalysis BouncingTrial() {
  pipeline::TrialAnalysis r = GoodTrial("ball_3_bounces", "steel", 0.0, 0.83);
  r.impact.index = 0;
  r.impact.lowest_frame = 24;
  kinematics::ImpactKinematics second = r.impact;
  second.index = 1;
  second.lowest_frame = 170;
  second.impact_time_s = 0.1705;
  second.impact_frame = 170;
  second.before.first_frame = 150;
  second.before.last_frame = 169;
  second.after.first_frame = 172;
  second.after.last_frame = 191;
  second.e = 0.81;
  second.e_se = 3e-4;
  second.v_SC_before = {0.002, -0.834};
  second.mu_eff = std::numeric_limits<double>::quiet_NaN();
  // Measured by the joint arcs, with what limited it.
  second.method = kinematics::KinematicsMethod::kArcs;
  second.impact_time_se_s = 2.5e-4;
  second.surface_angle_W_deg = 1.5;
  second.p_WT = {0.12, -0.04};
  second.limits.samples_before = 9;
  second.limits.samples_after = 7;
  second.limits.contact_frames = {170};
  second.limits.repeated_frames = {160, 181};
  second.limits.meeting_gap_m = 1e-4;
  second.limits.e_depth_shift = -0.003;
  kinematics::ImpactKinematics third;
  third.index = 2;
  third.lowest_frame = 300;
  third.impact_frame = 300;
  third.impact_time_s = 0.3;
  third.message =
      "too few free-flight frames around the impact near frame 300: 4 before and 3 "
      "after (need 6)";
  third.limits.short_arc = true;
  r.impacts = {r.impact, second, third};
  return r;
}

// /impacts: one row per impact, trials in order, read back as written; NaN for what the
// unmeasured impact lacks; the same rows in the CSV.
TEST(StudyFileTest, ThePerImpactTableReadsBackAsWritten) {
  const fs::path dir = Dir("impacts");
  auto trials = Trials();
  trials.insert(trials.begin() + 1, BouncingTrial());
  WriteStudyFile(dir / "study.h5", Info(), trials);
  const std::vector<ImpactResult> rows = ReadStudyImpacts(dir / "study.h5");
  ASSERT_EQ(rows.size(), 3u);  // the other trials were given no impacts list
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(rows[i].trial, "ball_3_bounces");
    EXPECT_EQ(rows[i].group, "/trials/ball_3_bounces");
    EXPECT_EQ(rows[i].impact_index, static_cast<int>(i));
  }
  EXPECT_TRUE(rows[0].is_main);
  EXPECT_FALSE(rows[1].is_main);
  EXPECT_FALSE(rows[2].is_main);
  EXPECT_TRUE(rows[0].success);
  EXPECT_EQ(rows[0].e, 0.83);
  EXPECT_EQ(rows[0].mu_eff, 0.21);
  EXPECT_EQ(rows[0].impact_time_s, 0.0031);
  EXPECT_EQ(rows[0].fit_after_last_frame, 46);
  EXPECT_EQ(rows[1].lowest_frame, 170);
  EXPECT_EQ(rows[1].impact_frame, 170);
  EXPECT_EQ(rows[1].impact_time_s, 0.1705);
  EXPECT_EQ(rows[1].e, 0.81);
  EXPECT_EQ(rows[1].e_se, 3e-4);
  EXPECT_EQ(rows[1].v_SC_before_m_s, Eigen::Vector2d(0.002, -0.834));
  EXPECT_TRUE(std::isnan(rows[1].mu_eff));
  EXPECT_EQ(rows[1].fit_before_first_frame, 150);
  EXPECT_EQ(rows[1].fit_after_first_frame, 172);
  EXPECT_TRUE(rows[1].error.empty());
  EXPECT_EQ(rows[0].method, "windows");
  EXPECT_EQ(rows[1].method, "arcs");
  EXPECT_EQ(rows[1].impact_time_se_s, 2.5e-4);
  EXPECT_EQ(rows[1].surface_angle_W_deg, 1.5);
  EXPECT_EQ(rows[1].p_WT_m, Eigen::Vector2d(0.12, -0.04));
  EXPECT_EQ(rows[1].samples_before, 9);
  EXPECT_EQ(rows[1].samples_after, 7);
  EXPECT_EQ(rows[1].contact_frames, 1);
  EXPECT_EQ(rows[1].repeated_frames, 2);
  EXPECT_EQ(rows[1].missing_frames, 0);
  EXPECT_EQ(rows[1].meeting_gap_m, 1e-4);
  EXPECT_EQ(rows[1].e_depth_shift, -0.003);
  EXPECT_TRUE(std::isnan(rows[1].depth_rate_before_per_s));
  EXPECT_FALSE(rows[1].short_arc);
  EXPECT_TRUE(rows[2].short_arc);
  EXPECT_TRUE(std::isnan(rows[2].impact_time_se_s));
  EXPECT_FALSE(rows[2].success);
  EXPECT_EQ(rows[2].error, trials[1].impacts[2].message);
  EXPECT_EQ(rows[2].impact_time_s, 0.3);
  EXPECT_EQ(rows[2].lowest_frame, 300);
  EXPECT_TRUE(std::isnan(rows[2].e));
  EXPECT_TRUE(std::isnan(rows[2].v_SC_after_m_s.y()));
  EXPECT_EQ(rows[2].fit_before_first_frame, -1);
  // Units and descriptions on the columns, as every table has.
  const Table t = ReadTable(dir / "study.h5", "/impacts");
  EXPECT_EQ(t.Get("e").units, "1");
  EXPECT_EQ(t.Get("impact_time_s").units, "s");
  EXPECT_FALSE(t.Get("main").description.empty());
  // The CSV holds the same rows.
  WriteImpactsCsv(dir / "impacts.csv", trials);
  const io::CsvTable csv = io::CsvTable::Read(dir / "impacts.csv");
  ASSERT_EQ(csv.rows(), 3u);
  EXPECT_EQ(csv.Number(1, csv.Column("e")), 0.81);
  EXPECT_EQ(csv.Text(2, csv.Column("e")), "nan");
  EXPECT_EQ(csv.Number(2, csv.Column("impact_index")), 2);
  EXPECT_EQ(csv.Text(2, csv.Column("error")), trials[1].impacts[2].message);
}

}  // namespace
}  // namespace hoof::studyfile
