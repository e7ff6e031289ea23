// A small study: docs/format.md compliance of study.json, trial.json and truth.json, and identical
// bytes for the same seed whatever the number of threads.
#include "synth/study.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "synth/test_support.h"

namespace hoof::synth {
namespace {

namespace fs = std::filesystem;
using testing::FreshDir;
using testing::ReadJson;

StudyDesign SmallDesign() {
  StudyDesign d;
  d.name = "small";
  d.seed = 99;
  d.surfaces = {dynamics::Surface::kSteel, dynamics::Surface::kAsphalt};
  d.angles_deg = {20.0};
  d.speeds_m_s = {2.5};
  d.trials_per_cell = 2;
  return d;
}

RenderOptions Short() {
  RenderOptions o;
  o.frames_before = 6;
  o.frames_after = 6;
  return o;
}

std::string Bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Every regular file below `dir`, relative, with its bytes.
std::map<std::string, std::string> Tree(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) out[fs::relative(e.path(), dir).string()] = Bytes(e.path());
  return out;
}

TEST(StudyTest, SameSeedGivesIdenticalBytesWithOneOrTwoThreads) {
  const fs::path a = FreshDir("study-threads-1"), b = FreshDir("study-threads-2");
  const StudyResult ra = RenderStudy(SmallDesign(), {}, Short(), a, 1);
  const StudyResult rb = RenderStudy(SmallDesign(), {}, Short(), b, 2);
  ASSERT_EQ(ra.failed, 0);
  ASSERT_EQ(rb.failed, 0);
  const auto ta = Tree(a), tb = Tree(b);
  ASSERT_EQ(ta.size(), 1 + 4 * (2 + 12u));  // study.json; per trial two JSON files, 12 frames
  for (const auto& [name, bytes] : ta) {
    ASSERT_TRUE(tb.count(name)) << name;
    EXPECT_TRUE(tb.at(name) == bytes) << name << " differs";
  }
  // A different seed changes the frames.
  StudyDesign other = SmallDesign();
  other.seed = 100;
  const fs::path c = FreshDir("study-seed-100");
  RenderStudy(other, {}, Short(), c, 2);
  EXPECT_NE(Bytes(c / "steel_20deg_v2.50_r1" / "frames" / "000003.png"),
            Bytes(a / "steel_20deg_v2.50_r1" / "frames" / "000003.png"));
}

TEST(StudyTest, FoldersFollowFormatMd) {
  const fs::path dir = FreshDir("study-format");
  RenderOptions o = Short();
  o.bit_depth = 16;
  const StudyResult r = RenderStudy(SmallDesign(), {}, o, dir, 2);
  ASSERT_EQ(r.failed, 0);
  const nlohmann::json study = ReadJson(dir / "study.json");
  EXPECT_EQ(study["format"], "hoofimpact-study/1");
  EXPECT_EQ(study["name"], "small");
  const nlohmann::json& a = study["specimens"]["A"];
  EXPECT_EQ(a["mass_kg"].get<double>(), 0.008);
  EXPECT_EQ(a["inertia_kg_m2"].get<double>(), 1.5207e-6);
  EXPECT_EQ(a["end_radius_m"].get<double>(), 0.009);
  EXPECT_EQ(a["d_EC_m"].get<double>(), 0.0135);
  EXPECT_EQ(a["length_m"].get<double>(), 0.045);
  EXPECT_EQ(a["width_m"].get<double>(), 0.016);
  EXPECT_EQ(a["thickness_m"].get<double>(), 0.008);
  EXPECT_EQ(a["markers_B_m"]["M1"], nlohmann::json({0.006, 0.0}));
  EXPECT_EQ(a["markers_B_m"]["M2"], nlohmann::json({0.024, 0.0}));
  ASSERT_EQ(study["trials"].size(), 4u);
  for (const auto& id : study["trials"]) {
    const fs::path t = dir / id.get<std::string>();
    const nlohmann::json trial = ReadJson(t / "trial.json");
    EXPECT_EQ(trial["format"], "hoofimpact-trial/1");
    EXPECT_EQ(trial["id"], id);
    EXPECT_EQ(trial["specimen"], "A");
    EXPECT_TRUE(std::set<std::string>({"steel", "concrete", "asphalt"}).count(trial["surface"]));
    EXPECT_EQ(trial["surface_angle_deg"].get<double>(), 20.0);
    EXPECT_EQ(trial["fps"].get<double>(), 8000.0);
    EXPECT_EQ(trial["frames"]["pattern"], "frames/%06d.png");
    EXPECT_EQ(trial["frames"]["first"], 0);
    ASSERT_EQ(trial["frames"]["count"], 12);
    EXPECT_EQ(trial["camera"]["m_per_px"].get<double>(), 2e-4);
    EXPECT_EQ(trial["camera"]["gravity_image"], nlohmann::json({0.0, 1.0}));
    EXPECT_EQ(trial["camera"]["distortion"].size(), 5u);
    EXPECT_EQ(trial["camera"]["camera_matrix"].size(), 3u);
    EXPECT_EQ(trial["nominal_speed_m_s"].get<double>(), 2.5);
    // surface_line_px: two image points; the line through them is at the surface angle
    // (distortion bends it by well under a degree at these points).
    const auto& line = trial["surface_line_px"];
    ASSERT_EQ(line.size(), 2u);
    const double angle = std::atan2(line[1][1].get<double>() - line[0][1].get<double>(),
                                    line[1][0].get<double>() - line[0][0].get<double>());
    EXPECT_NEAR(angle * 180 / 3.14159265358979, 20.0, 0.5);
    for (int i = 0; i < 12; ++i) {
      char file[32];
      std::snprintf(file, sizeof(file), "frames/%06d.png", i);
      const cv::Mat img = cv::imread((t / file).string(), cv::IMREAD_UNCHANGED);
      ASSERT_FALSE(img.empty()) << file;
      EXPECT_EQ(img.type(), CV_16U);
      EXPECT_EQ(img.cols, 512);
      EXPECT_EQ(img.rows, 384);
    }
    const nlohmann::json truth = ReadJson(t / "truth.json");
    EXPECT_EQ(truth["format"], "hoofimpact-truth/1");
    for (const char* key : {"impact_time_s", "w_before_rad_s", "w_after_rad_s", "e", "mu_eff"})
      EXPECT_TRUE(truth[key].is_number()) << key;
    for (const char* key : {"v_SC_before_m_s", "v_SC_after_m_s"})
      EXPECT_EQ(truth[key].size(), 2u) << key;
    for (const char* key : {"k_N_m", "b_N_s_m", "mu", "zeta"})
      EXPECT_TRUE(truth["model"][key].is_number()) << key;
    EXPECT_TRUE(truth["model"]["hidden_effects"].is_object());
    ASSERT_EQ(truth["frames"].size(), 12u);
    for (const auto& f : truth["frames"]) {
      EXPECT_TRUE(f["t_s"].is_number());
      EXPECT_EQ(f["p_WE_m"].size(), 2u);
      EXPECT_TRUE(f["theta_W_rad"].is_number());
      EXPECT_EQ(f["markers_px"]["M1"].size(), 2u);
      EXPECT_EQ(f["markers_px"]["M2"].size(), 2u);
      EXPECT_EQ(f["markers_px_undistorted"]["M2"].size(), 2u);
    }
  }
  // Nothing half-written is left behind.
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_NE(e.path().filename().string().front(), '.') << e.path();
}

TEST(StudyTest, PaperDesignHas144TrialsWithDistinctSeedsAndIds) {
  const std::vector<TrialSpec> trials = StudyDesign{}.Trials();
  ASSERT_EQ(trials.size(), 144u);
  std::set<std::string> ids;
  std::set<std::uint64_t> seeds;
  for (const TrialSpec& t : trials) {
    ids.insert(t.id);
    seeds.insert(t.seed);
    EXPECT_GE(t.speed_m_s, 1.5);
    EXPECT_LE(t.speed_m_s, 4.0);
  }
  EXPECT_EQ(ids.size(), 144u);
  EXPECT_EQ(seeds.size(), 144u);
  EXPECT_EQ(trials.front().id, "steel_0deg_v1.50_r1");
}

TEST(StudyTest, ScatterScaleReachesEveryTrialAndABadOneNamesTheField) {
  StudyDesign d = SmallDesign();
  d.scatter_scale = 0.5;
  for (const TrialSpec& t : d.Trials()) EXPECT_EQ(t.scatter_scale, 0.5) << t.id;
  for (double bad : {-1.0, 4.5}) {
    d.scatter_scale = bad;
    try {
      d.Validate();
      ADD_FAILURE() << "scatter_scale " << bad << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("study.scatter_scale"), std::string::npos) << e.what();
    }
  }
}

// The unreplicated design (the discovery scorecard's): the same seed draws the same cells, every
// surface and angle gets its trials at distinct speeds inside the range, and arguments under
// which the redraws could never end are refused by name.
TEST(StudyTest, UnreplicatedCellsAreDistinctReproducibleAndBadArgumentsAreNamed) {
  StudyDesign a, b;
  a.seed = b.seed = 4374853049126759078ULL;
  DrawUnreplicatedCells(a);
  DrawUnreplicatedCells(b);
  ASSERT_EQ(a.cells.size(), 36u);
  EXPECT_EQ(a.trials_per_cell, 1);
  std::set<std::string> ids;
  for (std::size_t i = 0; i < a.cells.size(); ++i) {
    EXPECT_EQ(a.cells[i].speed_m_s, b.cells[i].speed_m_s);
    EXPECT_GE(a.cells[i].speed_m_s, 1.5);
    EXPECT_LT(a.cells[i].speed_m_s, 4.0);
    char id[64];
    std::snprintf(id, sizeof id, "%d_%g_%.2f", static_cast<int>(a.cells[i].surface),
                  a.cells[i].angle_deg, a.cells[i].speed_m_s);
    ids.insert(id);
  }
  EXPECT_EQ(ids.size(), 36u);
  EXPECT_EQ(a.Trials().size(), 36u);
  b.seed = a.seed + 1;
  DrawUnreplicatedCells(b);
  EXPECT_NE(a.cells.front().speed_m_s, b.cells.front().speed_m_s);
  auto message = [](int per_angle, double lo, double hi) {
    StudyDesign d;
    try {
      DrawUnreplicatedCells(d, per_angle, lo, hi);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message(0, 1.5, 4.0).find("per_angle"), std::string::npos);
  EXPECT_NE(message(3, 4.0, 1.5).find("speed range"), std::string::npos);
  EXPECT_NE(message(3, 0.0, 4.0).find("speed range"), std::string::npos);
  EXPECT_NE(message(3, 2.0, 2.02).find("too few speeds"), std::string::npos);
  EXPECT_EQ(message(3, 2.0, 2.05), "");
}

}  // namespace
}  // namespace hoof::synth
