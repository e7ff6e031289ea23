// `hoofimpact init` on a rendered unmarked specimen (an outline, no markers): the trial.json it
// writes is measured by `hoofimpact track` without edits, e and mu_eff within 0.01 of the
// renderer's truth.json (issue 16: "init on rendered clips of each kind writes a trial.json that
// track measures without edits"; "marker-free e within 0.01 of the truth at 8000 fps").
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/run_command.h"

namespace {

namespace fs = std::filesystem;
using hoof::testing::RunHoofimpact;
using json = nlohmann::json;

const fs::path kOut = fs::path(HOOF_BINARY_DIR) / "test-output" / "init_outline";

json Results(const hoof::testing::CommandResult& r) { return json::parse(r.out)["results"]; }

// Renders an unmarked specimen (lit as `synth_extra` says) onto steel at `angle_deg` (PNG frames,
// 8000 fps, every camera effect on), writes the paper specimen into a study.json beside the trial
// folder, runs init (with `init_extra`: the scale) and then track on what init wrote.
void InitThenTrack(const std::string& name, double angle_deg, int seed,
                   const std::string& synth_extra, const std::string& init_extra) {
  const fs::path dir = kOut / name;
  fs::remove_all(dir);
  const fs::path render = dir / "render";
  const auto s = RunHoofimpact(
      "synth -o " + render.string() + " --body unmarked --surface steel --angle-deg " +
      std::to_string(angle_deg) + " --seed " + std::to_string(seed) + synth_extra);
  ASSERT_EQ(s.exit_code, 0) << s.err;
  const json truth = json::parse(std::ifstream(render / "truth.json"));
  // The paper's specimen as the renderer drew it (core/specimen.h's defaults).
  const json study = {{"format", "hoofimpact-study/1"},
                      {"name", name},
                      {"specimens",
                       {{"A",
                         {{"mass_kg", 0.008},
                          {"inertia_kg_m2", 1.5207e-6},
                          {"end_radius_m", 0.009},
                          {"d_EC_m", 0.0135},
                          // study.json requires a layout; the unmarked body shows none of it.
                          {"markers_B_m", {{"M1", {0.006, 0.0}}, {"M2", {0.024, 0.0}}}}}}}}};
  std::ofstream(dir / "study.json") << study.dump(2);
  const fs::path trial = dir / "trial";
  const auto r = RunHoofimpact("init " + (render / "frames").string() + " -o " + trial.string() +
                               " --fps 8000 --specimen A --json" + init_extra);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = Results(r);
  EXPECT_EQ(j["body_shape"], "outline");
  EXPECT_NEAR(j["surface_angle_deg"].get<double>(), angle_deg, 0.5);
  ASSERT_EQ(j["impact_frames"].size(), 1u) << j["impact_frames"].dump();
  EXPECT_NEAR(j["impact_frames"][0].get<double>(), truth["impact_time_s"].get<double>() * 8000,
              2.0);

  const auto t = RunHoofimpact("track " + trial.string() + " --json");
  ASSERT_EQ(t.exit_code, 0) << t.out << t.err;
  const json k = Results(t);
  EXPECT_NEAR(k["e"].get<double>(), truth["e"].get<double>(), 0.01);
  if (angle_deg > 0) {
    EXPECT_NEAR(k["mu_eff"].get<double>(), truth["mu_eff"].get<double>(), 0.01);
  }
  // The scale track used (stated, or from gravity), within 1 % of the rendered 2e-4 m/px.
  EXPECT_NEAR(k["m_per_px_used"].get<double>(), 2e-4, 0.01 * 2e-4);
  ASSERT_TRUE(k["round_end"]["measured"].get<bool>()) << k["round_end"].dump();
}

TEST(InitOutlineTest, AFrontLitUnmarkedClipAt40DegIsMeasuredWithoutEdits) {
  InitThenTrack("front_40deg", 40, 2, " --lighting front", " --m-per-px 2e-4");
}

TEST(InitOutlineTest, AFrontLitUnmarkedClipAt20DegIsMeasuredWithoutEdits) {
  InitThenTrack("front_20deg", 20, 3, " --lighting front", " --m-per-px 2e-4");
}

// Back-lit: the dark outline joins the dark surface block at the contact; the frames where the
// tracker loses it or its centroid jumps are left out as the contact's.
TEST(InitOutlineTest, ABackLitUnmarkedClipAt40DegIsMeasuredWithoutEdits) {
  InitThenTrack("backlit_40deg", 40, 2, " --lighting backlit", " --m-per-px 2e-4");
}

}  // namespace
