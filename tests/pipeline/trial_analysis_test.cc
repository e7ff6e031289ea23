// A trial end to end, on studies rendered by `hoofimpact synth` at default realism and scored
// against their truth.json; and every kind of bad input.
#include "pipeline/trial_analysis.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "pipeline/out_of_plane.h"
#include "pipeline/study_analysis.h"
#include "pipeline/truth_score.h"
#include "support/run_command.h"
#include "support/test_studies.h"

namespace hoof::pipeline {
namespace {

namespace fs = std::filesystem;

fs::path OutDir(const std::string& name) {
  return fs::path(HOOF_BINARY_DIR) / "test-output" / name;
}

using hoof::testing::TestStudyDir;

/// Every trial of `study`, measured on two threads.
std::vector<TrialAnalysis> AnalyzeAll(const StudySpec& study) { return AnalyzeStudy(study, {}, 2); }

// The accuracy targets (docs/tracking.md, "Accuracy on rendered trials"), on every trial of the
// paper-sized study (3 surfaces x 4 angles x 4 speeds x 3 repetitions) at the renderer's default
// realism.
TEST(TrialAnalysisTest, EveryTrialOfAFullStudyMeetsTheAccuracyTargets) {
  const fs::path dir = TestStudyDir("full_study");
  const StudySpec study = ReadStudy(dir);
  ASSERT_EQ(study.trial_dirs.size(), 144u);
  const auto results = AnalyzeAll(study);
  double ss = 0, worst_v = 0, worst_w = 0, worst_e = 0, worst_mu = 0;
  long markers = 0;
  for (const auto& r : results) {
    ASSERT_TRUE(r.success) << r.spec.id << ": " << r.error;
    const TrialScore s = ScoreTrial(r, ReadTruth(r.spec.dir));
    ss += s.marker_rms_px * s.marker_rms_px * s.marker_count;
    markers += s.marker_count;
    EXPECT_LT(s.v_before_rel, 0.003) << r.spec.id;
    EXPECT_LT(s.v_after_rel, 0.003) << r.spec.id;
    EXPECT_LT(s.w_before_abs, 2.0) << r.spec.id;
    EXPECT_LT(s.w_after_abs, 2.0) << r.spec.id;
    EXPECT_LT(s.e_abs, 0.005) << r.spec.id;
    if (r.spec.surface_angle_deg > 0) {
      EXPECT_LT(s.mu_eff_abs, 0.01) << r.spec.id;
    }
    // No out-of-plane rotation was rendered, so none may be flagged.
    EXPECT_EQ(std::count(r.flags.begin(), r.flags.end(), "out_of_plane"), 0) << r.spec.id;
    worst_v = std::max({worst_v, s.v_before_rel, s.v_after_rel});
    worst_w = std::max({worst_w, s.w_before_abs, s.w_after_abs});
    worst_e = std::max(worst_e, s.e_abs);
    if (std::isfinite(s.mu_eff_abs)) worst_mu = std::max(worst_mu, s.mu_eff_abs);
  }
  const double rms = std::sqrt(ss / static_cast<double>(markers));
  EXPECT_LT(rms, 0.05);
  std::cout << "full study: marker rms " << rms << " px over " << markers << " centres; worst v "
            << 100 * worst_v << " %, w " << worst_w << " rad/s, e " << worst_e << ", mu_eff "
            << worst_mu << "\n";
}

TEST(TrialAnalysisTest, OutOfPlaneRotationIsFlagged) {
  const fs::path dir = TestStudyDir("out_of_plane");
  const StudySpec study = ReadStudy(dir);
  ASSERT_EQ(study.trial_dirs.size(), 4u);
  for (const auto& r : AnalyzeAll(study)) {
    ASSERT_TRUE(ReadTruth(r.spec.dir).out_of_plane) << "the renderer did not tilt " << r.spec.id;
    EXPECT_EQ(std::count(r.flags.begin(), r.flags.end(), "out_of_plane"), 1)
        << r.spec.id << ": change " << r.out_of_plane_change << " noise " << r.out_of_plane_noise;
  }
}

// A tilt that grows through the clip at 1000 deg/s slides the markers on the face toward the
// camera (4 mm in front of the axis) at about 7 cm/s: the flight fits take that for the body's
// velocity. Re-measured with the rendered motion, the velocities are the body's again.
TEST(TrialAnalysisTest, ATrialReMeasuredWithItsOutOfPlaneMotionHasTheTrueVelocities) {
  constexpr double kRateDegS = 1000.0;
  const fs::path dir = TestStudyDir("out_of_plane_rate");
  const StudySpec study = ReadStudy(dir);
  ASSERT_EQ(study.trial_dirs.size(), 4u);
  OutOfPlaneMotion motion;
  motion.tilt_rate_rad_s = kRateDegS * M_PI / 180;
  for (const auto& r : AnalyzeAll(study)) {
    ASSERT_TRUE(r.success) << r.error;
    const TrialTruth truth = ReadTruth(r.spec.dir);
    const TrialAnalysis again = RemeasureOutOfPlane(r, motion, {});
    ASSERT_TRUE(again.success) << again.error;
    auto error = [&](const kinematics::ImpactKinematics& k) {
      return std::max((k.v_SC_before - truth.v_SC_before).norm(),
                      (k.v_SC_after - truth.v_SC_after).norm()) /
             truth.v_SC_before.norm();
    };
    const double before = error(r.impact), after = error(again.impact);
    std::cout << r.spec.id << ": velocity error " << 100 * before << " % as measured, "
              << 100 * after << " % re-measured; e " << r.impact.e << " -> " << again.impact.e
              << " (true " << truth.e << ")\n";
    // Re-measured, the velocities meet the tracker's accuracy on trials without the rotation.
    EXPECT_GT(before, 5e-3) << r.spec.id << ": the rotation should bias the velocities";
    EXPECT_LT(after, 5e-4) << r.spec.id;
    EXPECT_NEAR(again.impact.e, truth.e, 1e-3) << r.spec.id;
    // And the marker distance, divided by the one the motion predicts, is flat at 1.
    for (int f = again.impact.after.first_frame; f <= again.impact.after.last_frame; ++f) {
      const double ratio = again.marker_distance_ratio[static_cast<std::size_t>(f)];
      if (std::isfinite(ratio)) {
        EXPECT_NEAR(ratio, 1.0, 1e-3) << r.spec.id << " frame " << f;
      }
    }
  }
}

// A motion of zero leaves the trial as measured.
TEST(TrialAnalysisTest, ReMeasuringWithoutAnOutOfPlaneMotionChangesNothing) {
  const fs::path dir = TestStudyDir("out_of_plane_rate");
  const StudySpec study = ReadStudy(dir);
  const TrialAnalysis r = AnalyzeTrial(ReadTrial(study.trial_dirs.at(0), study));
  ASSERT_TRUE(r.success) << r.error;
  OutOfPlaneMotion tiny;
  tiny.tilt_rate_rad_s = 1e-12;  // not zero: the poses are fitted again
  const TrialAnalysis again = RemeasureOutOfPlane(r, tiny, {});
  EXPECT_NEAR((again.impact.v_SC_after - r.impact.v_SC_after).norm(), 0.0, 1e-9);
  EXPECT_NEAR(again.impact.e, r.impact.e, 1e-9);
}

// Results are keyed by id: of two trials with one id, the second fails and names the first's
// folder; the study goes on.
TEST(StudyAnalysisTest, ASecondTrialWithTheSameIdFailsNamingTheFirst) {
  const fs::path dir = OutDir("duplicate_ids");
  fs::remove_all(dir);
  fs::copy(fs::path(HOOF_SOURCE_DIR) / "sample_frames", dir, fs::copy_options::recursive);
  const fs::path second = dir / "steel_20deg_v3.28_r1" / "trial.json";
  nlohmann::json j = nlohmann::json::parse(std::ifstream(second));
  j["id"] = "steel_0deg_v3.00_r1";
  std::ofstream(second) << j.dump(1);
  const auto results = AnalyzeStudy(ReadStudy(dir), {}, 2);
  ASSERT_EQ(results.size(), 4u);
  EXPECT_TRUE(results[0].success) << results[0].error;
  EXPECT_FALSE(results[1].success);
  EXPECT_NE(results[1].error.find("field \"id\" is \"steel_0deg_v3.00_r1\", already the id of"),
            std::string::npos)
      << results[1].error;
  EXPECT_NE(results[1].error.find("steel_0deg_v3.00_r1"), std::string::npos);
  EXPECT_TRUE(results[2].success && results[3].success);
}

// --- Bad input: each gives a clear error naming the file, frame or field -----------------

class BadInputTest : public ::testing::Test {
 protected:
  /// A fresh copy of a one-trial study.
  fs::path Copy(const std::string& name) {
    const fs::path base = TestStudyDir("bad_input_base");
    const fs::path dir = OutDir("bad_input_" + name);
    fs::remove_all(dir);
    fs::copy(base, dir, fs::copy_options::recursive);
    return dir;
  }
  static fs::path Trial(const fs::path& study) { return ReadStudy(study).trial_dirs.at(0); }
  static TrialAnalysis Analyze(const fs::path& study) {
    return AnalyzeTrial(ReadTrial(Trial(study)));
  }
  static void EditJson(const fs::path& file, const std::function<void(nlohmann::json&)>& edit) {
    nlohmann::json j = nlohmann::json::parse(std::ifstream(file));
    edit(j);
    std::ofstream(file) << j.dump(2);
  }
  static void PaintOver(const fs::path& frame, const Eigen::Vector2d& centre) {
    cv::Mat img = cv::imread(frame.string(), cv::IMREAD_UNCHANGED);
    cv::circle(img, cv::Point(static_cast<int>(centre.x()), static_cast<int>(centre.y())), 20,
               cv::Scalar(90), cv::FILLED);
    cv::imwrite(frame.string(), img);
  }
};

TEST_F(BadInputTest, TheUntouchedTrialWorks) {
  const TrialAnalysis r = Analyze(Copy("none"));
  EXPECT_TRUE(r.success) << r.error;
}

TEST_F(BadInputTest, MissingFrame) {
  const fs::path study = Copy("missing_frame");
  fs::remove(Trial(study) / "frames/000012.png");
  const TrialAnalysis r = Analyze(study);
  EXPECT_FALSE(r.success);
  EXPECT_NE(r.error.find("000012.png: frame 12 is missing"), std::string::npos) << r.error;
}

TEST_F(BadInputTest, CorruptImage) {
  const fs::path study = Copy("corrupt_frame");
  std::ofstream(Trial(study) / "frames/000007.png", std::ios::trunc) << "garbage";
  const TrialAnalysis r = Analyze(study);
  EXPECT_FALSE(r.success);
  EXPECT_NE(r.error.find("000007.png: frame 7 cannot be decoded"), std::string::npos) << r.error;
}

TEST_F(BadInputTest, NoMarkers) {
  const fs::path study = Copy("no_markers");
  const cv::Mat blank(384, 512, CV_8U, cv::Scalar(30));
  for (const auto& e : fs::directory_iterator(Trial(study) / "frames"))
    cv::imwrite(e.path().string(), blank);
  const TrialAnalysis r = Analyze(study);
  EXPECT_FALSE(r.success);
  EXPECT_NE(r.error.find("000000.png: found 0 marker(s)"), std::string::npos) << r.error;
}

TEST_F(BadInputTest, MarkerLostForGood) {
  const fs::path study = Copy("lost_marker");
  const TrialTruth truth = ReadTruth(Trial(study));
  for (int f = 10; f < static_cast<int>(truth.markers_px.size()); ++f) {
    char name[32];
    std::snprintf(name, sizeof name, "frames/%06d.png", f);
    PaintOver(Trial(study) / name, truth.markers_px[static_cast<std::size_t>(f)].at("M2"));
  }
  const TrialAnalysis r = Analyze(study);
  EXPECT_FALSE(r.success);
  EXPECT_EQ(std::count(r.flags.begin(), r.flags.end(), "lost_marker"), 1);
  const bool named = std::any_of(r.warnings.begin(), r.warnings.end(), [](const std::string& w) {
    return w.find("000010.png: marker M2 not found") != std::string::npos;
  });
  EXPECT_TRUE(named);
  EXPECT_NE(r.error.find("too few"), std::string::npos) << r.error;
}

TEST_F(BadInputTest, NoImpactInTheSequence) {
  const fs::path study = Copy("no_impact");
  EditJson(Trial(study) / "trial.json", [](nlohmann::json& j) { j["frames"]["count"] = 26; });
  const TrialAnalysis r = Analyze(study);
  EXPECT_FALSE(r.success);
  EXPECT_NE(r.error.find("no impact found"), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("trial.json"), std::string::npos) << r.error;
}

TEST_F(BadInputTest, LayoutThatDoesNotMatch) {
  const fs::path study = Copy("layout");
  EditJson(study / "study.json", [](nlohmann::json& j) {
    for (auto& [id, s] : j["specimens"].items()) s["markers_B_m"]["M2"] = {0.036, 0.0};
  });
  const TrialAnalysis r = Analyze(study);
  EXPECT_FALSE(r.success);
  EXPECT_NE(r.error.find("layout does not match"), std::string::npos) << r.error;
}

TEST_F(BadInputTest, BadJsonField) {
  const fs::path study = Copy("bad_field");
  EditJson(Trial(study) / "trial.json", [](nlohmann::json& j) { j["fps"] = "fast"; });
  try {
    ReadTrial(Trial(study));
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("trial.json: field \"fps\" must be a number"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace hoof::pipeline
