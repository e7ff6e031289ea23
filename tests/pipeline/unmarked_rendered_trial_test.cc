// An unmarked specimen rendered with known truth by the synth library (front-lit hoof-wall
// texture without markers, the renderer's default noise, blur and scatter, 8000 fps) and
// measured by its outline alone (AnalyzeTrial with the body trial.json names): e within 0.01 of
// the truth (issue 16: "marker-free e within 0.01 of the truth at 8000 fps"). The ball has its
// own rendered test (tests/cli/track_silhouette_test.cc); the rate over seeds and conditions is
// bench/silhouette_scorecard's (docs/performance.md, "Marker-free e over seeds").
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "pipeline/study_format.h"
#include "pipeline/trial_analysis.h"
#include "synth/options.h"
#include "synth/renderer.h"
#include "synth/trial_files.h"

namespace hoof::pipeline {
namespace {

namespace fs = std::filesystem;

TEST(UnmarkedRenderedTrialTest, TheOutlineGivesTheTruthsRestitution) {
  synth::SpecimenGeometry geometry;
  geometry.body = synth::Body::kUnmarked;
  synth::RenderOptions render;  // 8000 fps, default camera effects
  synth::TrialSpec spec;
  spec.surface = dynamics::Surface::kSteel;
  spec.angle_deg = 20;
  spec.seed = 3;
  spec.id = "unmarked";
  const fs::path dir =
      fs::path(HOOF_BINARY_DIR) / "test-output" / "unmarked_rendered_trial" / spec.id;
  fs::remove_all(dir);
  fs::create_directories(dir.parent_path());
  // The specimen's study.json beside the trial, as a rendered study has it.
  std::ofstream(dir.parent_path() / "study.json")
      << synth::StudyJson("unmarked", geometry, {spec.id}).dump(2);
  synth::RenderTrial(spec, geometry, render,
                     synth::BuildSceneAssets(geometry, render, {spec.surface}, spec.seed), dir,
                     true);
  const TrialAnalysis a = AnalyzeTrial(ReadTrial(dir));
  ASSERT_TRUE(a.success) << a.error;
  EXPECT_EQ(a.spec.body.model, "silhouette");
  EXPECT_EQ(a.spec.body.shape, "outline");
  // truth.json's e (pipeline::ReadTruth wants the markers' positions, which an unmarked
  // specimen has none of).
  const double e_truth = nlohmann::json::parse(std::ifstream(dir / "truth.json")).at("e");
  EXPECT_NEAR(a.impact.e, e_truth, 0.01) << "e " << a.impact.e << " +- " << a.impact.e_se;
}

}  // namespace
}  // namespace hoof::pipeline
