// End-to-end tests of `hoofimpact analyze` (and `stats` on what it writes): a small study is
// rendered with `hoofimpact synth --study`, analysed, and the e and v_SC stored in the HDF5 file
// are held against each trial's truth.json (the renderer's ground truth, which the pipeline
// never reads). Bad trials must be recorded with their reason without sinking the study.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include "io/csv.h"
#include "stats/grouping.h"
#include "stats/one_way_analysis.h"
#include "stats/two_way_anova.h"
#include "studyfile/study_file.h"
#include "support/run_command.h"
#include "support/test_studies.h"

namespace hoof::cli {
namespace {

namespace fs = std::filesystem;
using hoof::testing::RunHoofimpact;

/// One folder per test process: CTest runs the tests of this file as separate processes,
/// possibly at the same time.
fs::path Root() {
  return fs::path(HOOF_BINARY_DIR) / "analyze_command_test" / std::to_string(::getpid());
}

/// 2 surfaces x 2 angles x 1 speed x 2 repetitions = 8 trials of 52 frames, rendered once.
class AnalyzeCommandTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    fs::remove_all(Root());
    fs::create_directories(Root());
  }
  static void TearDownTestSuite() { fs::remove_all(Root()); }
  /// Rendered once per renderer by the fixture test_studies, and never written to.
  static fs::path Study() { return hoof::testing::TestStudyDir("analyze_8"); }

  /// A copy of the study to break.
  static fs::path CopyStudy(const std::string& name) {
    const fs::path dir = Root() / name;
    fs::remove_all(dir);
    fs::copy(Study(), dir, fs::copy_options::recursive);
    return dir;
  }

  static nlohmann::json Truth(const fs::path& trial_dir) {
    std::ifstream in(trial_dir / "truth.json");
    return nlohmann::json::parse(in);
  }

  /// e within 0.005 and v_SC before and after within 0.3 % of the truth (docs/tracking.md,
  /// "Accuracy on rendered trials"; 0.05 px centroid noise gives about 0.3 % over 20 frames).
  static void ExpectMatchesTruth(const studyfile::TrialResult& t, const fs::path& trial_dir) {
    const nlohmann::json truth = Truth(trial_dir);
    EXPECT_NEAR(t.e, truth["e"].get<double>(), 0.005) << t.id;
    for (const auto& [key, measured] : {std::pair{"v_SC_before_m_s", t.v_SC_before_m_s},
                                        std::pair{"v_SC_after_m_s", t.v_SC_after_m_s}}) {
      const Eigen::Vector2d v(truth[key][0].get<double>(), truth[key][1].get<double>());
      EXPECT_LE((measured - v).norm(), 0.003 * v.norm())
          << t.id << " " << key << ": measured [" << measured.transpose() << "], truth ["
          << v.transpose() << "]";
    }
  }
};

TEST_F(AnalyzeCommandTest, EveryTrialMatchesItsTruthInTheStudyFile) {
  const fs::path out = Root() / "good";
  const auto r =
      RunHoofimpact("analyze " + Study().string() + " -o " + (out / "study.h5").string() +
                    " --json --jobs 2 --csv " + (out / "results.csv").string() + " --tracks-csv " +
                    (out / "tracks.csv").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const studyfile::StudyResults s = studyfile::ReadStudyResults(out / "study.h5");
  ASSERT_EQ(s.trials.size(), 8u);
  const auto json = nlohmann::json::parse(r.out).at("results").at("trials");
  ASSERT_EQ(json.size(), 8u);
  double worst_e = 0, worst_v = 0;
  for (std::size_t i = 0; i < s.trials.size(); ++i) {
    const auto& t = s.trials[i];
    ASSERT_TRUE(t.success) << t.id << ": " << t.error;
    ExpectMatchesTruth(t, Study() / t.id);
    const auto truth = Truth(Study() / t.id);
    worst_e = std::max(worst_e, std::abs(t.e - truth["e"].get<double>()));
    const Eigen::Vector2d vb(truth["v_SC_before_m_s"][0].get<double>(),
                             truth["v_SC_before_m_s"][1].get<double>());
    worst_v = std::max(worst_v, (t.v_SC_before_m_s - vb).norm() / vb.norm());
    // The JSON on stdout and the file agree, in the study's order.
    EXPECT_EQ(json[i]["id"], t.id);
    EXPECT_EQ(json[i]["e"].get<double>(), t.e);
    EXPECT_EQ(t.nominal_speed_m_s, 3.0);
    // mu_eff is not defined for a normal impact: NaN in the file, null in the JSON (and "nan"
    // in results.csv, below); measured on the oblique ones.
    if (t.surface_angle_deg == 0.0) {
      EXPECT_TRUE(std::isnan(t.mu_eff)) << t.id << ": " << t.mu_eff;
      EXPECT_TRUE(json[i]["mu_eff"].is_null()) << json[i]["mu_eff"];
    } else {
      EXPECT_TRUE(std::isfinite(t.mu_eff)) << t.id;
    }
  }
  std::cout << "worst |e - e_true| = " << worst_e
            << ", worst |v_SC_before| error = " << 100 * worst_v << " %\n";
  EXPECT_EQ(s.trials[0].id, "steel_0deg_v3.00_r1");
  const io::CsvTable csv = io::CsvTable::Read(out / "results.csv");
  EXPECT_EQ(csv.rows(), 8u);
  for (std::size_t row = 0; row < csv.rows(); ++row) {
    if (csv.Text(row, csv.Column("surface_angle_deg")) == "0") {
      EXPECT_EQ(csv.Text(row, csv.Column("mu_eff")), "nan") << csv.Text(row, csv.Column("id"));
    }
  }
  EXPECT_EQ(io::CsvTable::Read(out / "tracks.csv").rows(), 8u * 52u * 2u);
  EXPECT_NE(r.err.find("8 ok, 0 failed"), std::string::npos) << r.err;
}

TEST_F(AnalyzeCommandTest, BadTrialsAreRecordedAndTheOthersMeasured) {
  const fs::path study = CopyStudy("bad_study");
  fs::remove(study / "steel_0deg_v3.00_r2" / "frames" / "000010.png");
  std::ofstream(study / "concrete_20deg_v3.00_r1" / "trial.json") << "{ not json";
  const fs::path file = Root() / "bad" / "study.h5";
  const auto r = RunHoofimpact("analyze " + study.string() + " -o " + file.string());
  EXPECT_EQ(r.exit_code, 3) << r.out << r.err;
  EXPECT_NE(r.out.find("6 ok, 2 failed"), std::string::npos) << r.out;
  const studyfile::StudyResults s = studyfile::ReadStudyResults(file);
  ASSERT_EQ(s.trials.size(), 8u);
  std::map<std::string, const studyfile::TrialResult*> by_id;
  for (const auto& t : s.trials) by_id[t.id] = &t;
  const auto* missing = by_id.at("steel_0deg_v3.00_r2");
  EXPECT_FALSE(missing->success);
  EXPECT_NE(missing->error.find("000010.png"), std::string::npos) << missing->error;
  EXPECT_TRUE(std::isnan(missing->e));
  const auto* corrupt = by_id.at("concrete_20deg_v3.00_r1");
  EXPECT_FALSE(corrupt->success);
  EXPECT_NE(corrupt->error.find("concrete_20deg_v3.00_r1/trial.json"), std::string::npos)
      << corrupt->error;
  for (const auto& t : s.trials) {
    if (&t == missing || &t == corrupt) continue;
    EXPECT_TRUE(t.success) << t.id << ": " << t.error;
    ExpectMatchesTruth(t, study / t.id);
  }

  // stats leaves the failed trials out, with a note naming them.
  const auto st = RunHoofimpact("stats " + file.string() + " --json");
  ASSERT_EQ(st.exit_code, 0) << st.err;
  const auto j = nlohmann::json::parse(st.out).at("results");
  ASSERT_EQ(j["excluded"].size(), 2u);
  EXPECT_EQ(j["excluded"][0]["id"], "steel_0deg_v3.00_r2");
  EXPECT_EQ(j["responses"]["e"]["observations"].get<int>(), 6);
}

// A surface angle in trial.json that the image contradicts is measured as stated, and said.
TEST_F(AnalyzeCommandTest, ASurfaceAngleTheImageContradictsIsAWarning) {
  const fs::path study = CopyStudy("angle_study");
  const fs::path trial = study / "steel_20deg_v3.00_r1" / "trial.json";
  nlohmann::json j = nlohmann::json::parse(std::ifstream(trial));
  j["surface_angle_deg"] = 0.0;
  std::ofstream(trial) << j.dump(1);
  const auto r =
      RunHoofimpact("analyze " + study.string() + " -o " + (Root() / "angle.h5").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("WARNING steel_20deg_v3.00_r1: the surface in the image is at 20"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("trial.json says 0 deg"), std::string::npos) << r.out;
}

TEST_F(AnalyzeCommandTest, UnreadableStudyExitsWithOneAndNamesTheFile) {
  const fs::path empty = Root() / "empty";
  fs::create_directories(empty);
  const auto r = RunHoofimpact("analyze " + empty.string() + " -o " + (Root() / "x.h5").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("study.json"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(Root() / "x.h5"));

  // Every trial failing is a failure of the study, but the file still records why.
  const fs::path study = CopyStudy("all_bad");
  for (const auto& e : fs::directory_iterator(study))
    if (e.is_directory()) fs::remove_all(e.path() / "frames");
  const auto all =
      RunHoofimpact("analyze " + study.string() + " -o " + (Root() / "all_bad.h5").string());
  EXPECT_EQ(all.exit_code, 1);
  const auto s = studyfile::ReadStudyResults(Root() / "all_bad.h5");
  ASSERT_EQ(s.trials.size(), 8u);
  for (const auto& t : s.trials) EXPECT_FALSE(t.error.empty()) << t.id;
}

// The stats plumbing: the F of e by surface, and the two-way table, as stored in /stats and
// printed as JSON, equal what hoof::stats computes from the e values read back from the file.
TEST_F(AnalyzeCommandTest, StatsOnTheStudyFileAgreesWithTheLibrary) {
  const fs::path file = Root() / "stats" / "study.h5";
  ASSERT_EQ(RunHoofimpact("analyze " + Study().string() + " -o " + file.string()).exit_code, 0);
  const fs::path csv = Root() / "stats" / "tables.csv";
  const auto r = RunHoofimpact("stats " + file.string() + " --json --out-csv " + csv.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;

  const studyfile::StudyResults s = studyfile::ReadStudyResults(file);
  std::vector<double> e;
  std::vector<std::string> surface, angle;
  for (const auto& t : s.trials) {
    e.push_back(t.e);
    surface.push_back(t.surface);
    angle.push_back(t.surface_angle_deg == 0 ? "0" : "20");
  }
  const auto expected = stats::AnalyzeOneWay(stats::GroupByLabel(e, surface));
  const auto j = nlohmann::json::parse(r.out).at("results");
  const auto& by_surface = j["responses"]["e"]["by_surface"];
  EXPECT_DOUBLE_EQ(by_surface["anova"]["between"]["f"].get<double>(), expected.original.anova.f);
  EXPECT_DOUBLE_EQ(by_surface["anova"]["between"]["p"].get<double>(), expected.original.anova.p);
  const studyfile::Table anova = studyfile::ReadTable(file, "/stats/e/by_surface/anova");
  EXPECT_DOUBLE_EQ(std::get<std::vector<double>>(anova.Get("f").values)[0],
                   expected.original.anova.f);
  EXPECT_EQ(std::get<std::vector<double>>(anova.Get("df").values), (std::vector<double>{1, 6, 7}));

  stats::TwoWayOptions o;
  o.name_a = "surface";
  o.name_b = "angle";
  const auto two_way = stats::TwoWayAnova(e, surface, angle, o);
  const studyfile::Table tw = studyfile::ReadTable(file, "/stats/e/two_way");
  EXPECT_DOUBLE_EQ(std::get<std::vector<double>>(tw.Get("f").values)[0], two_way.a.f);
  EXPECT_DOUBLE_EQ(std::get<std::vector<double>>(tw.Get("f").values)[1], two_way.b.f);

  // mu_eff uses the oblique trials only (4 of 8), as in the paper.
  EXPECT_EQ(j["responses"]["mu_eff"]["observations"].get<int>(), 4);
  // The speed factor has one level here: not computed, with the reason, and no failure.
  EXPECT_NE(j["responses"]["e"]["by_speed"]["note"].get<std::string>().find("at least 2 groups"),
            std::string::npos);

  const io::CsvTable t = io::CsvTable::Read(csv);
  bool found = false;
  for (std::size_t i = 0; i < t.rows(); ++i)
    if (t.Text(i, 0) == "e/by_surface/anova" && t.Text(i, 1) == "between" && t.Text(i, 2) == "f") {
      EXPECT_DOUBLE_EQ(t.Number(i, 3), expected.original.anova.f);
      found = true;
    }
  EXPECT_TRUE(found);
}

}  // namespace
}  // namespace hoof::cli
