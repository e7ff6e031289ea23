// `hoofimpact run` end to end on a small rendered study without per-trial scatter, where the
// fitted model is the truth and every trial must agree with its simulation.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include "studyfile/study_file.h"
#include "support/run_command.h"
#include "support/test_studies.h"

namespace hoof::cli {
namespace {

namespace fs = std::filesystem;
using hoof::testing::RunHoofimpact;

TEST(RunCommandTest, TheWholeStudyEndToEnd) {
  const fs::path base =
      fs::path(HOOF_BINARY_DIR) / "test-output" / ("run_" + std::to_string(::getpid()));
  fs::remove_all(base);
  const fs::path study = hoof::testing::TestStudyDir("run_16");
  auto r = RunHoofimpact("run " + study.string() + " -o " + (base / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("16 measured, 0 failed"), std::string::npos) << r.out;
  const fs::path h5 = base / "out" / "study.h5";
  // The comparison: every trial agrees with the simulation of the fitted (true) model within
  // three combined standard errors.
  const auto trials = studyfile::ReadTable(h5, "/comparison/trials");
  for (const char* z : {"z_v_x", "z_v_y", "z_w"})
    for (double v : std::get<std::vector<double>>(trials.Get(z).values))
      EXPECT_LT(std::abs(v), 3.0) << z;
  // Each trial on the scale of its prediction interval (/prediction): 16 trials, none beyond 3
  // where the model is the truth, and the report's Trials table says how many are.
  const auto predicted = studyfile::ReadTable(h5, "/prediction/trials");
  EXPECT_EQ(predicted.Get("id").size(), 16u);
  int prediction_components = 0;
  for (const char* z : {"z_v_x", "z_v_y", "z_w"})
    for (double v : std::get<std::vector<double>>(predicted.Get(z).values))
      if (std::isfinite(v)) {
        ++prediction_components;
        EXPECT_LT(std::abs(v), 3.0) << z;
      }
  EXPECT_EQ(prediction_components, 8 * 1 + 8 * 3);  // v_y of the normal trials; all of the oblique
  {
    std::ifstream in(base / "out" / "report.html");
    const std::string page((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(page.find("<p id=\"prediction-z-count\">0 of " +
                        std::to_string(prediction_components) + " trial components"),
              std::string::npos);
    EXPECT_NE(page.find("precision-only z"), std::string::npos);
  }
  // Statistics stored, CSVs and figures written.
  EXPECT_NO_THROW(studyfile::ReadTable(h5, "/stats/e/by_surface/anova"));
  EXPECT_TRUE(fs::exists(base / "out" / "results.csv"));
  EXPECT_TRUE(fs::exists(base / "out" / "stats.csv"));
  EXPECT_TRUE(fs::exists(base / "out" / "figures" / "e_by_angle.png"));
  EXPECT_TRUE(fs::exists(base / "out" / "figures" / "mu_eff_by_angle.svg"));
  EXPECT_GT(fs::file_size(base / "out" / "report.html"), 10000u);
  // The paper's Figures 6-8: velocities after normal and oblique impacts, and energy.
  EXPECT_TRUE(fs::exists(base / "out" / "figures" / "velocity_normal.png"));
  EXPECT_TRUE(fs::exists(base / "out" / "figures" / "velocity_oblique.svg"));
  int energy = 0;
  for (const auto& e : fs::directory_iterator(base / "out" / "figures"))
    energy +=
        e.path().filename().string().rfind("energy_", 0) == 0 && e.path().extension() == ".png";
  EXPECT_EQ(energy, 2);  // one oblique trial per surface
  // Units written properly: the energy figures' time axis is in µs (the SVG holds the UTF-8 text).
  for (const auto& e : fs::directory_iterator(base / "out" / "figures"))
    if (e.path().filename().string().rfind("energy_", 0) == 0 && e.path().extension() == ".svg") {
      std::ifstream in(e.path());
      const std::string svg((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      EXPECT_NE(svg.find("time since first touch (µs)"), std::string::npos) << e.path();
    }
  EXPECT_NE(r.out.find("report.html"), std::string::npos);
  fs::remove_all(base);
}

TEST(RunCommandTest, AMissingStudyIsAClearError) {
  const auto r = RunHoofimpact("run /nonexistent-study-folder");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("nonexistent-study-folder"), std::string::npos) << r.err;
}

/// A copy of the study `name` under `base` (its JSON files copied, its frames linked), with
/// `edit` applied to each trial.json (by the trial folder's name).
fs::path CopyStudy(const std::string& name, const fs::path& base,
                   const std::function<void(const std::string&, nlohmann::json&)>& edit) {
  const fs::path from = hoof::testing::TestStudyDir(name), to = base / name;
  fs::create_directories(to);
  fs::copy_file(from / "study.json", to / "study.json");
  for (const auto& e : fs::directory_iterator(from)) {
    if (!e.is_directory()) continue;
    const fs::path trial = to / e.path().filename();
    fs::create_directories(trial);
    fs::create_directory_symlink(e.path() / "frames", trial / "frames");
    fs::copy_file(e.path() / "truth.json", trial / "truth.json");
    nlohmann::json j = nlohmann::json::parse(std::ifstream(e.path() / "trial.json"));
    edit(e.path().filename().string(), j);
    std::ofstream(trial / "trial.json") << j.dump(2);
  }
  return to;
}

std::string ReadText(const fs::path& file) {
  std::ifstream in(file);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

TEST(RunCommandTest, BallAndOutlineStudiesRunEndToEndAndAreDiscovered) {
  // The whole job on bodies without markers: every trial measured and compared, the centre of
  // mass within 0.25 px of its simulation over the 20 frames after impact (the fitted model is
  // the truth's: no scatter), the report's replay drawing the centre (and a ball's circle,
  // 10 mm at 0.2 mm/px: 50 px), and `discover` on the study file saying why the out-of-plane
  // candidates are not tested.
  const fs::path base =
      fs::path(HOOF_BINARY_DIR) / "test-output" / ("run_bodies_" + std::to_string(::getpid()));
  fs::remove_all(base);
  for (const std::string name : {"ball_8", "unmarked_8"}) {
    const bool ball = name == "ball_8";
    const fs::path out = base / name;
    auto r = RunHoofimpact("run " + hoof::testing::TestStudyDir(name).string() + " -o " +
                           out.string() + " --json");
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    const nlohmann::json& res = j["results"];
    EXPECT_EQ(res["measured"], 8) << name;
    EXPECT_EQ(res["compared"], 8) << name;
    EXPECT_LT(res["worst_centre_px"].get<double>(), 0.25) << name;
    EXPECT_EQ(res["trials_without_mass"], 0) << name;
    for (const auto& s : res["surfaces"]) {
      EXPECT_TRUE(s["success"].get<bool>()) << name << s.dump();
      EXPECT_TRUE(s["mass_known"].get<bool>()) << name;
      EXPECT_TRUE(s["k_N_m"].is_number()) << name;
    }
    const std::string page = ReadText(out / "report.html");
    EXPECT_NE(page.find("\"centre_of_mass\":true"), std::string::npos) << name;
    EXPECT_EQ(page.find("\"centre_of_mass\":false"), std::string::npos) << name;
    EXPECT_NE(page.find(ball ? "\"ball_radius_px\":50," : "\"ball_radius_px\":null"),
              std::string::npos)
        << name;
    r = RunHoofimpact("discover " + (out / "study.h5").string() + " -o " +
                      (out / "discovered.h5").string());
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    EXPECT_NE(r.out.find(ball ? "out-of-plane rotation (a measurement effect); out-of-plane tilt "
                                "growing through the impact (a measurement effect); out-of-plane "
                                "roll growing through the impact (a measurement effect): does not "
                                "apply to a ball"
                              : "not measured on bodies without markers (8 unmarked outline(s))"),
              std::string::npos)
        << name << "\n"
        << r.out;
    EXPECT_EQ(r.out.find("Mass:"), std::string::npos) << name;  // every mass is known
  }
  fs::remove_all(base);
}

TEST(RunCommandTest, ABallOfUnknownMassRunsAndSaysWhatNeedsTheMass) {
  // The ball study's trials without their specimen (as `init` writes for a clip from a phone):
  // the ball is its own specimen, of unknown mass. The job measures and compares every trial and
  // says plainly what it cannot give; the study file holds no energy and no k or b.
  const fs::path base =
      fs::path(HOOF_BINARY_DIR) / "test-output" / ("run_no_mass_" + std::to_string(::getpid()));
  fs::remove_all(base);
  const fs::path study =
      CopyStudy("ball_8", base, [](const std::string&, nlohmann::json& j) { j.erase("specimen"); });
  const auto r = RunHoofimpact("run " + study.string() + " -o " + (base / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("8 measured, 0 failed"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("k and b need the mass (not given)"), std::string::npos) << r.out;
  EXPECT_NE(
      r.out.find(
          "8 trial(s) of a ball of unknown mass (no ball specimen with a mass_kg in study.json): "
          "their velocities, e and mu_eff are compared, as none depends on the mass; "
          "their kinetic energies and the contact law's k and b need the mass and "
          "are not given"),
      std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("8 trial(s) compared"), std::string::npos) << r.out;
  const fs::path h5 = base / "out" / "study.h5";
  const auto trials = studyfile::ReadTable(h5, "/comparison/trials");
  for (double e : std::get<std::vector<double>>(trials.Get("kinetic_energy_before_J").values))
    EXPECT_TRUE(std::isnan(e));
  for (double v : std::get<std::vector<double>>(trials.Get("v_SC_after_sim_y_m_s").values))
    EXPECT_TRUE(std::isfinite(v));
  const auto surfaces = studyfile::ReadTable(h5, "/comparison/surfaces");
  for (double b : std::get<std::vector<double>>(surfaces.Get("b_N_s_m").values))
    EXPECT_TRUE(std::isnan(b));
  EXPECT_NE(ReadText(base / "out" / "report.html").find("k and b need the mass"),
            std::string::npos);
  fs::remove_all(base);
}

TEST(RunCommandTest, ATrialThatContradictsItsSpecimenIsNamedAndTheStudyGoesOn) {
  // One trial.json gives its ball a diameter that its study.json's ball specimen does not have:
  // that trial fails with the file and the field named, and the other seven are measured and
  // compared (exit 3: some trials failed).
  const fs::path base =
      fs::path(HOOF_BINARY_DIR) / "test-output" / ("run_bad_ball_" + std::to_string(::getpid()));
  fs::remove_all(base);
  const std::string bad = "steel_20deg_v2.50_r1";
  const fs::path study =
      CopyStudy("ball_8", base, [&](const std::string& trial, nlohmann::json& j) {
        if (trial == bad) j["body"]["diameter_m"] = 0.025;
      });
  const auto r = RunHoofimpact("run " + study.string() + " -o " + (base / "out").string());
  EXPECT_EQ(r.exit_code, 3) << r.err << r.out;
  EXPECT_NE(r.out.find("FAILED " + bad + ": " + (study / bad / "trial.json").string() +
                       ": field \"body.diameter_m\" is 0.025 m, but the trial names the ball "
                       "specimen \"ball\" (" +
                       (study / "study.json").string() + ", specimens.ball)"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("7 measured, 1 failed"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("7 trial(s) compared"), std::string::npos) << r.out;
  fs::remove_all(base);
}

}  // namespace
}  // namespace hoof::cli
