// Simulation against measurement on rendered studies without hidden effects: the model that
// made the frames, fitted back from the measurements, must reproduce every trial.
#include "compare/trial_comparison.h"

#include "compare/comparison_tables.h"
#include "compare/study_comparison.h"

#include <cmath>
#include <filesystem>
#include <map>
#include <string>

#include <vector>

#include <gtest/gtest.h>

#include <unistd.h>
#include "support/test_util.h"

#include <fstream>
#include <nlohmann/json.hpp>
#include "pipeline/study_analysis.h"
#include "pipeline/truth_score.h"
#include "support/run_command.h"
#include "support/test_studies.h"

namespace hoof::compare {
namespace {

namespace fs = std::filesystem;

/// A study rendered without per-trial scatter (every trial of a surface shares its contact
/// law), so the surface model fitted to the measurements is the truth.
const std::vector<pipeline::TrialAnalysis>& Trials() {
  static const std::vector<pipeline::TrialAnalysis> trials =
      pipeline::AnalyzeStudy(pipeline::ReadStudy(hoof::testing::TestStudyDir("compare_12")), {}, 2);
  return trials;
}

TEST(TrialComparisonTest, SurfaceModelsRecoverTheRenderedContactLaw) {
  for (const std::string surface : {"steel", "asphalt"}) {
    const SurfaceModel m = FitSurfaceModel(surface, Trials());
    ASSERT_TRUE(m.success) << m.message;
    EXPECT_EQ(m.normal_trials, 3);
    EXPECT_EQ(m.oblique_trials, 3);
    // Truth: the paper's zeta and mu for the surface (no scatter), in every truth.json.
    const auto& any = *std::find_if(Trials().begin(), Trials().end(),
                                    [&](const auto& t) { return t.spec.surface == surface; });
    const auto truth = nlohmann::json::parse(std::ifstream(any.spec.dir / "truth.json"));
    const double zeta = truth["model"]["zeta"].get<double>();
    const double mu = truth["model"]["mu"].get<double>();
    EXPECT_NEAR(m.zeta_fit.zeta, zeta, 3 * m.zeta_fit.zeta_se + 1e-4) << surface;
    if (m.mu_only_lower_bound) {
      EXPECT_LE(m.mu, mu + 0.02) << surface;  // sticking contacts bound mu from below only
    } else {
      EXPECT_NEAR(m.mu, mu, 3 * m.mu_se + 1e-3) << surface;
    }
  }
}

TEST(TrialComparisonTest, SurfaceModelIsTheSameWhateverTheThreads) {
  // The grid in mu runs in parallel; each point's sum is formed on one thread in trial order,
  // so the fit must agree to the last bit.
  for (const std::string surface : {"steel", "asphalt"}) {
    const SurfaceModel one = FitSurfaceModel(surface, Trials(), 1);
    for (int jobs : {2, 3}) {
      const SurfaceModel many = FitSurfaceModel(surface, Trials(), jobs);
      ASSERT_TRUE(many.success) << many.message;
      EXPECT_EQ(many.zeta_fit.zeta, one.zeta_fit.zeta) << surface << " jobs " << jobs;
      EXPECT_EQ(many.mu, one.mu) << surface << " jobs " << jobs;
      if (std::isfinite(one.mu_se)) {
        EXPECT_EQ(many.mu_se, one.mu_se) << surface;
      }
      EXPECT_EQ(many.mu_only_lower_bound, one.mu_only_lower_bound) << surface;
    }
  }
}

TEST(TrialComparisonTest, SimulatedVelocitiesAgreeWithinTheMeasurementUncertainty) {
  std::map<std::string, SurfaceModel> models;
  for (const std::string surface : {"steel", "asphalt"})
    models[surface] = FitSurfaceModel(surface, Trials());
  for (const auto& t : Trials()) {
    ASSERT_TRUE(t.success) << t.error;
    dynamics::ContactParameters c = models[t.spec.surface].Contact();
    if (std::isnan(c.mu)) c.mu = 0.0;
    const TrialComparison cmp = CompareTrial(t, c, Uncertainty(models[t.spec.surface]));
    ASSERT_TRUE(cmp.success) << cmp.message;
    EXPECT_LT(std::abs(cmp.v_SC_after_z.x()), 3.0) << t.spec.id;
    EXPECT_LT(std::abs(cmp.v_SC_after_z.y()), 3.0) << t.spec.id;
    EXPECT_LT(std::abs(cmp.w_after_z), 3.0) << t.spec.id;
    std::cout << t.spec.id << ": z = " << cmp.v_SC_after_z.transpose() << " " << cmp.w_after_z
              << "\n";
  }
}

TEST(TrialComparisonTest, MarkersAfterImpactStayWithinHalfAPixelOnSteel) {
  const SurfaceModel steel = FitSurfaceModel("steel", Trials());
  for (const auto& t : Trials()) {
    if (t.spec.surface != "steel") continue;
    const TrialComparison cmp = CompareTrial(t, steel.Contact());
    ASSERT_TRUE(cmp.success) << cmp.message;
    const int first_after = static_cast<int>(std::ceil(cmp.t_touch_s * t.spec.fps));
    double worst = 0;
    for (int f = first_after; f < first_after + 20 && f < static_cast<int>(cmp.frames.size()); ++f)
      for (double r : cmp.frames[static_cast<std::size_t>(f)].marker_residual_px)
        if (std::isfinite(r)) worst = std::max(worst, r);
    EXPECT_LT(worst, 0.5) << t.spec.id;
    std::cout << t.spec.id << ": worst marker residual over 20 frames after impact " << worst
              << " px\n";
  }
}

}  // namespace
}  // namespace hoof::compare

namespace hoof::compare {
namespace {

TEST(StudyComparisonTest, TablesGoIntoTheStudyFileAndReadBack) {
  const auto& trials = Trials();
  const StudyComparison cmp = CompareStudy(trials, 2);
  ASSERT_EQ(cmp.surfaces.size(), 2u);
  const fs::path file =
      fs::path(HOOF_BINARY_DIR) / "test-output" / ("compare_" + std::to_string(::getpid()) + ".h5");
  studyfile::StudyInfo info;
  info.name = "compare-test";
  studyfile::WriteStudyFile(file, info, trials);
  studyfile::WriteTables(file, "/comparison", "simulation against measurement",
                         ComparisonTables(trials, cmp), {}, ComparisonLinks(trials, cmp));
  // Each trial's tables are also found under its own group (soft links).
  const auto linked = studyfile::ReadTable(
      file, "/trials/" + studyfile::TrialGroupNames(trials)[0] + "/comparison_frames");
  EXPECT_EQ(linked.Get("M1_residual_px").size(), cmp.trials[0].frames.size());
  // Simulated marker positions in W and in the image agree through the camera model.
  EXPECT_EQ(linked.Get("M1_sim_x_m").size(), cmp.trials[0].frames.size());
  const auto surfaces = studyfile::ReadTable(file, "/comparison/surfaces");
  EXPECT_EQ(surfaces.Get("surface").size(), 2u);
  const auto rows = studyfile::ReadTable(file, "/comparison/trials");
  const auto& z = std::get<std::vector<double>>(rows.Get("z_v_y").values);
  ASSERT_EQ(z.size(), trials.size());
  for (std::size_t i = 0; i < z.size(); ++i) {
    EXPECT_TRUE(cmp.trials[i].success);
    EXPECT_DOUBLE_EQ(z[i], cmp.trials[i].v_SC_after_z.y());
  }
  const auto frames = studyfile::ReadTable(file, "/comparison/frames/" + trials[0].spec.id);
  const auto& res = std::get<std::vector<double>>(frames.Get("M1_residual_px").values);
  ASSERT_EQ(res.size(), cmp.trials[0].frames.size());
  for (std::size_t f = 0; f < res.size(); ++f) {
    const double expected = cmp.trials[0].frames[f].marker_residual_px[0];
    if (std::isnan(expected)) {
      EXPECT_TRUE(std::isnan(res[f]));
    } else {
      EXPECT_DOUBLE_EQ(res[f], expected);
    }
  }
  // The typed readers give back what was written: the models, each trial's values and frames
  // (the markers named from the columns), and the contact's energy.
  ASSERT_TRUE(HasComparison(file));
  const std::vector<SurfaceModel> models = ReadSurfaceModels(file);
  ASSERT_EQ(models.size(), cmp.surfaces.size());
  for (const SurfaceModel& m : models) {
    const SurfaceModel& w = cmp.surfaces.at(m.surface);
    EXPECT_EQ(m.success, w.success);
    EXPECT_EQ(m.zeta_fit.zeta, w.zeta_fit.zeta);
    EXPECT_EQ(m.mu, w.mu);
    EXPECT_EQ(m.mu_only_lower_bound, w.mu_only_lower_bound);
    EXPECT_EQ(m.oblique_trials, w.oblique_trials);
  }
  const std::vector<ComparedTrial> compared = ReadComparedTrials(file);
  ASSERT_EQ(compared.size(), trials.size());
  for (std::size_t i = 0; i < trials.size(); ++i) {
    EXPECT_EQ(compared[i].id, trials[i].spec.id);
    EXPECT_EQ(compared[i].comparison.v_SC_after_sim, cmp.trials[i].v_SC_after_sim);
    EXPECT_EQ(compared[i].comparison.w_after_z, cmp.trials[i].w_after_z);
    EXPECT_EQ(compared[i].comparison.t_touch_s, cmp.trials[i].t_touch_s);
  }
  const ComparedFrames read = ReadComparedFrames(file, trials[0].spec.id);
  ASSERT_EQ(read.markers.size(), trials[0].spec.specimen.markers_B_m.size());
  for (std::size_t m = 0; m < read.markers.size(); ++m)
    EXPECT_EQ(read.markers[m], trials[0].spec.specimen.markers_B_m[m].first);
  ASSERT_EQ(read.frames.size(), cmp.trials[0].frames.size());
  for (std::size_t f = 0; f < read.frames.size(); ++f) {
    const FrameComparison &a = read.frames[f], &b = cmp.trials[0].frames[f];
    EXPECT_EQ(a.p_WC_sim, b.p_WC_sim);
    EXPECT_EQ(a.measured, b.measured);
    EXPECT_EQ(a.markers_px_sim, b.markers_px_sim);
    if (b.measured) {
      EXPECT_EQ(a.theta_W_meas_rad, b.theta_W_meas_rad);
    } else {
      EXPECT_TRUE(std::isnan(a.theta_W_meas_rad));  // NaN in the file, whatever was in memory
    }
  }
  TrialComparison energy;
  ReadContactEnergy(file, trials[0].spec.id, energy);
  EXPECT_EQ(energy.contact_kinetic_energy_J, cmp.trials[0].contact_kinetic_energy_J);
  hoof::testing::ExpectErrorContaining([&] { ReadContactEnergy(file, "no_such_trial", energy); },
                                       file.string());
  fs::remove(file);
}

}  // namespace
}  // namespace hoof::compare
