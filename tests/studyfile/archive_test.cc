// The archives of the study file: one list of fields drives writing and reading, of a group
// (studyfile/archive.h, schema.h), of a table of struct rows (studyfile/table_archive.h) and of
// a trial's per-frame tracks and poses (studyfile/frame_archive.h).
#include <H5Cpp.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <gtest/gtest.h>

#include "studyfile/archive.h"
#include "studyfile/schema.h"
#include "studyfile/study_file.h"
#include "studyfile/table_archive.h"
#include "support/test_util.h"

namespace {

namespace fs = std::filesystem;
using hoof::studyfile::EnumText;
using hoof::studyfile::Presence;
using hoof::studyfile::Table;
using hoof::studyfile::TableReader;
using hoof::studyfile::TableWriter;
namespace internal = hoof::studyfile::internal;

enum class Shade { kLight, kDark };
const char* ShadeText(Shade s) { return s == Shade::kLight ? "light" : "dark"; }
Shade ShadeFromText(const std::string& s) {
  if (s == "light") return Shade::kLight;
  if (s == "dark") return Shade::kDark;
  throw std::invalid_argument("\"" + s + "\" is neither light nor dark");
}
constexpr EnumText<Shade> kShade{&ShadeText, &ShadeFromText};

struct Row {
  std::string name;
  double value = 0.0;
  int count = 0;
  long long big = 0;
  bool flag = false;
  Shade shade = Shade::kLight;
  double added_later = -1.0;  // the default a file without the column leaves
};

template <class Archive, class R>
requires std::is_same_v<std::remove_const_t<R>, Row>
void Serialize(Archive& a, R& r) {
  a.Text("name", r.name, "a name");
  a.Number("value", r.value, "m/s", "a number");
  a.Integer("count", r.count, "1", "an int");
  a.Integer("big", r.big, "1", "a long long");
  a.Flag("flag", r.flag, "a flag");
  a.Choice("shade", r.shade, kShade, "light or dark");
  a.Number("added_later", r.added_later, "1", "a column newer files have", Presence::kAddedLater);
}

const auto kSerialize = [](auto& a, auto& r) { Serialize(a, r); };

std::vector<Row> Rows() {
  return {{"a", 1.5, 3, 1LL << 40, true, Shade::kDark, 7.0},
          {"b", -2.25, -4, -5, false, Shade::kLight, std::nan("")}};
}

TEST(TableArchiveTest, RowsReadBackAsWrittenWithTheDeclaredColumns) {
  const Table t = TableWriter::Of("rows", "test rows", Rows(), kSerialize);
  ASSERT_EQ(t.columns.size(), 7u);
  EXPECT_EQ(t.columns[1].name, "value");
  EXPECT_EQ(t.columns[1].units, "m/s");
  EXPECT_EQ(t.columns[4].units, "");  // flags are unitless integers
  const std::vector<Row> back = TableReader::Read<Row>(t, "f.h5: table /rows", kSerialize);
  ASSERT_EQ(back.size(), 2u);
  const std::vector<Row> rows = Rows();
  for (std::size_t i = 0; i < 2; ++i) {
    const Row& w = rows[i];
    EXPECT_EQ(back[i].name, w.name);
    EXPECT_EQ(back[i].value, w.value);
    EXPECT_EQ(back[i].count, w.count);
    EXPECT_EQ(back[i].big, w.big);
    EXPECT_EQ(back[i].flag, w.flag);
    EXPECT_EQ(back[i].shade, w.shade);
  }
  EXPECT_EQ(back[0].added_later, 7.0);
  EXPECT_TRUE(std::isnan(back[1].added_later));
}

TEST(TableArchiveTest, ATableOfNoRowsStillHasItsColumns) {
  const Table t = TableWriter::Of("rows", "", std::vector<Row>{}, kSerialize);
  ASSERT_EQ(t.columns.size(), 7u);
  EXPECT_EQ(t.columns[0].size(), 0u);
  EXPECT_TRUE(TableReader::Read<Row>(t, "x", kSerialize).empty());
}

TEST(TableArchiveTest, AColumnAddedLaterMayBeMissingARequiredOneMayNot) {
  Table t = TableWriter::Of("rows", "", Rows(), kSerialize);
  t.columns.pop_back();  // a file written before added_later existed
  const std::vector<Row> back = TableReader::Read<Row>(t, "old.h5: table /rows", kSerialize);
  EXPECT_EQ(back[0].added_later, -1.0);
  EXPECT_EQ(back[1].value, -2.25);
  t.columns.erase(t.columns.begin() + 1);  // and without "value"
  hoof::testing::ExpectErrorContaining(
      [&] { TableReader::Read<Row>(t, "old.h5: table /rows", kSerialize); },
      "old.h5: table /rows: column \"value\" is missing");
}

TEST(TableArchiveTest, BadValuesAreNamedWithTheColumnAndTheRow) {
  Table t = TableWriter::Of("rows", "", Rows(), kSerialize);
  std::get<std::vector<std::string>>(t.columns[5].values)[1] = "grey";
  hoof::testing::ExpectErrorContaining(
      [&] { TableReader::Read<Row>(t, "f.h5: table /rows", kSerialize); },
      "column \"shade\" row 1: \"grey\" is neither light nor dark");
  t = TableWriter::Of("rows", "", Rows(), kSerialize);
  t.columns[2] = hoof::studyfile::Column::Numbers("count", "1", "", {3.0, 2.5});
  hoof::testing::ExpectErrorContaining(
      [&] { TableReader::Read<Row>(t, "f.h5: table /rows", kSerialize); },
      "column \"count\" row 1");
  t = TableWriter::Of("rows", "", Rows(), kSerialize);
  t.columns[2] = hoof::studyfile::Column::Integers("count", "1", "", {3, 1LL << 40});
  hoof::testing::ExpectErrorContaining(
      [&] { TableReader::Read<Row>(t, "f.h5: table /rows", kSerialize); }, "out of range");
}

TEST(TableArchiveTest, AOneRowTableHoldsExactlyOne) {
  const Row one = Rows().front();
  const Table t = TableWriter::OfOne("one", "", one, kSerialize);
  Row back;
  TableReader::ReadOne(t, "f.h5: table /one", back, kSerialize);
  EXPECT_EQ(back.name, "a");
  EXPECT_EQ(back.big, 1LL << 40);
  const Table two = TableWriter::Of("two", "", Rows(), kSerialize);
  hoof::testing::ExpectErrorContaining(
      [&] { TableReader::ReadOne(two, "f.h5: table /two", back, kSerialize); },
      "f.h5: table /two has 2 rows, not 1");
}

TEST(TableArchiveTest, ARowThatVisitsOtherColumnsThanDeclaredIsABug) {
  struct Odd {
    bool extra = false;
  };
  const auto serialize = [](auto& a, const Odd& o) {
    a.Number("x", 1.0, "1", "");
    if (o.extra) a.Number("y", 2.0, "1", "");
  };
  EXPECT_THROW(TableWriter::Of("odd", "", std::vector<Odd>{{true}}, serialize), std::logic_error);
}

TEST(GroupArchiveTest, AFitAndATrialsMetadataReadBackAsWritten) {
  const fs::path dir = hoof::testing::FreshDir("archive_test");
  const fs::path path = dir / "a.h5";
  hoof::kinematics::FlightFit fit;
  fit.first_frame = 3;
  fit.last_frame = 22;
  fit.n = 20;
  fit.p_WC = {0.1, -0.2};
  fit.v_WC = {1.25, -3.5};
  fit.cov_v_WC << 1e-6, 2e-7, 3e-7, 4e-6;  // not symmetric: row-major order is checked
  fit.theta_W_rad = 0.3;
  fit.w_rad_s = -12.0;
  hoof::pipeline::TrialAnalysis r;
  r.spec.id = "t1";
  r.spec.nominal_speed_m_s.reset();
  r.spec.camera.distortion = std::array<double, 5>{0.1, -0.2, 0.0, 0.0, 0.01};
  r.m_per_px_from_markers = 0.0;  // not measured: NaN in the file, 0 again when read
  r.surface_angle_measured_deg = 19.5;
  {
    H5::H5File file(path.string(), H5F_ACC_TRUNC);
    internal::H5Writer fits(file.createGroup("/fit"));
    internal::Serialize(fits, fit);
    internal::H5Writer metadata(file.createGroup("/metadata"));
    internal::SerializeMetadata(metadata, r);
  }
  H5::H5File file(path.string(), H5F_ACC_RDONLY);
  const internal::GroupReader root(file.openGroup("/"), path.string() + ":");
  hoof::kinematics::FlightFit fit_back;
  internal::Serialize(internal::H5Reader(root.Group("fit")), fit_back);
  EXPECT_EQ(fit_back.first_frame, 3);
  EXPECT_EQ(fit_back.n, 20);
  EXPECT_EQ(fit_back.v_WC, fit.v_WC);
  EXPECT_EQ(fit_back.cov_v_WC, fit.cov_v_WC);
  EXPECT_EQ(fit_back.w_rad_s, -12.0);
  EXPECT_TRUE(std::isnan(root.Group("metadata").Scalar("m_per_px_from_markers")));
  hoof::pipeline::TrialAnalysis back;
  back.m_per_px_from_markers = 5.0;
  internal::SerializeMetadata(internal::H5Reader(root.Group("metadata")), back);
  EXPECT_EQ(back.spec.id, "t1");
  EXPECT_FALSE(back.spec.nominal_speed_m_s.has_value());
  ASSERT_TRUE(back.spec.camera.distortion.has_value());
  EXPECT_EQ(*back.spec.camera.distortion, *r.spec.camera.distortion);
  EXPECT_FALSE(back.spec.camera.camera_matrix.has_value());  // absent: not written, not read
  EXPECT_EQ(back.m_per_px_from_markers, 0.0);
  EXPECT_EQ(back.surface_angle_measured_deg, 19.5);
  // A field missing from the group is named with the file and the group.
  hoof::testing::ExpectErrorContaining(
      [&] {
        hoof::pipeline::SpecimenSpec s;
        internal::Serialize(internal::H5Reader(root.Group("fit")), s);
      },
      path.string() + ":/fit/mass_kg does not exist");
}

// ------------------------------------------------------------------------------------------
// Per-frame arrays: /trials/<id>/tracks and /trials/<id>/poses
// ------------------------------------------------------------------------------------------

/// A trial of three frames and two markers, by hand: M2 lost in frame 1 (with a centre and a
/// radius in memory that the file must not keep), frame 2 holding M1 only; pose 1 invalid (with
/// numbers that must not be kept), pose 2 valid with a marker distance of 0 (not measured); the
/// distance ratio NaN in frame 1 and one frame short.
hoof::pipeline::TrialAnalysis TrackedTrial() {
  hoof::pipeline::TrialAnalysis r;
  r.spec.id = "tracked";
  r.spec.fps = 2000.0;
  auto& t = r.tracks;
  t.names = {"M1", "M2"};
  t.warnings = {"frame 1: M2 lost"};
  t.frames = {{{true, {10.25, 20.5}, 3.5, 4.25, "ok"}, {true, {30.75, 21.0}, 4.0, 4.5, "ok"}},
              {{true, {11.0, 22.5}, 3.25, 4.0, "ok"}, {false, {99.0, 98.0}, 0.0, 7.0, "lost"}},
              {{true, {12.5, 24.0}, 3.0, 4.125, "ok"}}};
  r.poses = {{true, {0.1, -0.2}, 0.3, 1e-5, 2, 0.024},
             {false, {5.0, 6.0}, 1.0, 2.0, 1, 0.02},
             {true, {0.11, -0.25}, 0.31, 2e-5, 2, 0.0}};
  r.marker_distance_ratio = {1.0, std::nan("")};
  r.out_of_plane_change = 0.01;
  r.out_of_plane_noise = 0.002;
  return r;
}

/// A trial whose tracking never started: marker names, no frames.
hoof::pipeline::TrialAnalysis UntrackedTrial() {
  hoof::pipeline::TrialAnalysis r;
  r.spec.id = "untracked";
  r.spec.fps = 2000.0;
  r.tracks.names = {"M1", "M2"};
  return r;
}

/// Exactly equal, or both NaN.
void ExpectSame(double read, double want, const std::string& what) {
  if (std::isnan(want))
    EXPECT_TRUE(std::isnan(read)) << what << ": " << read;
  else
    EXPECT_EQ(read, want) << what;
}

/// `read` against `want`, field by field: the tracks, the poses and their per-frame numbers.
void ExpectSameFrames(const hoof::pipeline::TrialAnalysis& read,
                      const hoof::pipeline::TrialAnalysis& want) {
  EXPECT_EQ(read.tracks.names, want.tracks.names);
  EXPECT_EQ(read.tracks.warnings, want.tracks.warnings);
  ASSERT_EQ(read.tracks.frames.size(), want.tracks.frames.size());
  for (std::size_t f = 0; f < want.tracks.frames.size(); ++f) {
    ASSERT_EQ(read.tracks.frames[f].size(), want.tracks.frames[f].size()) << "frame " << f;
    for (std::size_t m = 0; m < want.tracks.frames[f].size(); ++m) {
      const auto& x = read.tracks.frames[f][m];
      const auto& y = want.tracks.frames[f][m];
      const std::string what = "frame " + std::to_string(f) + " marker " + std::to_string(m);
      EXPECT_EQ(x.found, y.found) << what;
      EXPECT_EQ(x.p_I, y.p_I) << what;
      EXPECT_EQ(x.quality, y.quality) << what;
      EXPECT_EQ(x.radius_px, y.radius_px) << what;
      EXPECT_EQ(x.status, y.status) << what;
    }
  }
  ASSERT_EQ(read.poses.size(), want.poses.size());
  for (std::size_t f = 0; f < want.poses.size(); ++f) {
    const auto& x = read.poses[f];
    const auto& y = want.poses[f];
    const std::string what = "pose " + std::to_string(f);
    EXPECT_EQ(x.valid, y.valid) << what;
    EXPECT_EQ(x.p_WE, y.p_WE) << what;
    EXPECT_EQ(x.theta_W_rad, y.theta_W_rad) << what;
    EXPECT_EQ(x.rms_residual_m, y.rms_residual_m) << what;
    EXPECT_EQ(x.markers_used, y.markers_used) << what;
    EXPECT_EQ(x.marker_distance_m, y.marker_distance_m) << what;
  }
  ASSERT_EQ(read.marker_distance_ratio.size(), want.marker_distance_ratio.size());
  for (std::size_t f = 0; f < want.marker_distance_ratio.size(); ++f)
    ExpectSame(read.marker_distance_ratio[f], want.marker_distance_ratio[f],
               "marker_distance_ratio " + std::to_string(f));
  EXPECT_EQ(read.out_of_plane_change, want.out_of_plane_change);
  EXPECT_EQ(read.out_of_plane_noise, want.out_of_plane_noise);
}

TEST(FrameArchiveTest, TracksAndPosesReadBackAsWrittenFieldByField) {
  const fs::path path = hoof::testing::FreshDir("archive_test_frames") / "study.h5";
  const std::vector<hoof::pipeline::TrialAnalysis> written = {TrackedTrial(), UntrackedTrial()};
  hoof::studyfile::WriteStudyFile(path, hoof::studyfile::StudyInfo{}, written);
  const std::vector<hoof::pipeline::TrialAnalysis> read = hoof::studyfile::ReadTrialAnalyses(path);
  ASSERT_EQ(read.size(), 2u);
  // What the file keeps: no centre or radius of a marker not found, a missing marker of a
  // frame as not found, no numbers of an invalid pose, the ratio as long as the poses.
  hoof::pipeline::TrialAnalysis want = TrackedTrial();
  want.tracks.frames[1][1].p_I = {0.0, 0.0};
  want.tracks.frames[1][1].radius_px = 0.0;
  want.tracks.frames[2].emplace_back();
  want.poses[1] = {false, {0.0, 0.0}, 0.0, 0.0, 1, 0.0};
  want.marker_distance_ratio.push_back(std::nan(""));
  {
    SCOPED_TRACE("tracked");
    ExpectSameFrames(read[0], want);
  }
  {
    SCOPED_TRACE("untracked");
    ExpectSameFrames(read[1], UntrackedTrial());
  }
  // The file itself: NaN for what was not measured, shapes [frame, marker(, 2)].
  H5::H5File file(path.string(), H5F_ACC_RDONLY);
  const internal::GroupReader trial =
      internal::GroupReader(file.openGroup("/"), path.string() + ":")
          .Group("trials")
          .Group("tracked");
  const internal::GroupReader tracks = trial.Group("tracks");
  const std::vector<double> p = tracks.Doubles("p_I_px", {3, 2, 2});
  EXPECT_EQ(p[0], 10.25);
  for (std::size_t i : {6, 7, 10, 11}) EXPECT_TRUE(std::isnan(p[i])) << "p_I_px " << i;
  const std::vector<double> radius = tracks.Doubles("radius_px", {3, 2});
  EXPECT_TRUE(std::isnan(radius[3]));
  EXPECT_TRUE(std::isnan(radius[5]));
  EXPECT_EQ(tracks.Doubles("t_s", {3}), (std::vector<double>{0.0, 0.0005, 0.001}));
  EXPECT_EQ(tracks.Texts("status", {3, 2})[5], "");
  const internal::GroupReader poses = trial.Group("poses");
  const std::vector<double> distance = poses.Doubles("marker_distance_m", {3});
  EXPECT_EQ(distance[0], 0.024);
  EXPECT_TRUE(std::isnan(distance[1]));  // invalid
  EXPECT_TRUE(std::isnan(distance[2]));  // 0: not measured
  EXPECT_TRUE(std::isnan(poses.Doubles("p_WE_m", {3, 2})[2]));
  EXPECT_TRUE(std::isnan(poses.Doubles("theta_W_rad", {3})[1]));
  EXPECT_EQ(poses.Integers("markers_used", {3}), (std::vector<std::int64_t>{2, 1, 2}));
  const internal::GroupReader untracked =
      internal::GroupReader(file.openGroup("/"), path.string() + ":")
          .Group("trials")
          .Group("untracked");
  EXPECT_TRUE(untracked.Group("tracks").Doubles("p_I_px", {0, 2, 2}).empty());
  EXPECT_TRUE(untracked.Group("tracks").Texts("status", {0, 2}).empty());
  EXPECT_TRUE(untracked.Group("poses").Integers("valid", {0}).empty());
}

}  // namespace
