// Tests of ReadTrialAnalyses: the four sample trials (sample_frames/) are analysed here, with a
// trial whose impact is not in its frames, a trial folder that does not exist and a copy of a
// sample trial with a marker painted over in two frames, written to a study file and read back.
// Every field the file holds must come back exactly (doubles bit for bit, NaN as NaN), the rest at
// its default, and compare::CompareTrial must simulate the read trials exactly as the analysed
// ones. Broken files must fail with the file and the item named.
#include "studyfile/study_file.h"

#include <H5Cpp.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "compare/trial_comparison.h"
#include "core/parallel.h"
#include "dynamics/parameters.h"
#include "pipeline/study_analysis.h"
#include "support/test_util.h"

namespace hoof::studyfile {
namespace {

namespace fs = std::filesystem;

/// This process's folder (ctest runs each test in its own process, possibly in parallel).
const fs::path& Dir() {
  static const fs::path dir =
      hoof::testing::FreshDir("read_trial_analyses_" + std::to_string(::getpid()));
  return dir;
}

/// Removes Dir() when the tests of this process are done.
class RemoveDir : public ::testing::Environment {
 public:
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(Dir(), ec);
  }
};
[[maybe_unused]] ::testing::Environment* const kRemoveDir =
    ::testing::AddGlobalTestEnvironment(new RemoveDir);

struct Written {
  pipeline::StudySpec study;
  std::vector<pipeline::TrialAnalysis> trials;  ///< as analysed
  fs::path file;                                ///< the study file they were written to
  std::vector<std::string> groups;              ///< their groups below /trials
};

/// Frames of the occluded trial in which marker M2 is painted over.
constexpr int kOccludedFrames[] = {30, 31};

/// A copy of sample trial `id` with marker M2 painted black in kOccludedFrames, where `tracks`
/// (the sample trial's) found it.
pipeline::TrialSpec OccludedCopy(const pipeline::StudySpec& study, const std::string& id,
                                 const tracking::MarkerTracks& tracks) {
  const fs::path dir = Dir() / "occluded";
  fs::copy(fs::path(HOOF_SOURCE_DIR) / "sample_frames" / id, dir, fs::copy_options::recursive);
  pipeline::TrialSpec spec = pipeline::ReadTrial(dir, study);
  for (int f : kOccludedFrames) {
    char name[32];
    std::snprintf(name, sizeof name, spec.frames.pattern.c_str(), spec.frames.first + f);
    const std::string frame = (dir / name).string();
    cv::Mat image = cv::imread(frame, cv::IMREAD_UNCHANGED);
    EXPECT_FALSE(image.empty()) << frame;
    const auto& m2 = tracks.frames.at(static_cast<std::size_t>(f)).at(1);
    EXPECT_TRUE(m2.found) << frame;
    cv::circle(image, cv::Point(static_cast<int>(m2.p_I.x()), static_cast<int>(m2.p_I.y())),
               static_cast<int>(2 * m2.radius_px) + 3, cv::Scalar::all(0), cv::FILLED);
    EXPECT_TRUE(cv::imwrite(frame, image)) << frame;
  }
  spec.id = "steel_20deg_occluded";
  return spec;
}

/// The sample study analysed (two threads) plus three more trials, written once per process:
/// [0..3] the sample trials, [3] (asphalt) with the scale taken from the markers; [4]
/// steel_20deg_v3.28_r1 again (same id, so group "..._2") cut to its first 14 frames, before
/// the impact: tracked, but the impact is not measured; [5] a trial folder that does not
/// exist: nothing measured; [6] steel_20deg_v3.28_r1 with marker M2 painted over in two
/// frames: measured, with lost markers and invalid poses.
const Written& Study() {
  static const Written w = [] {
    Written out;
    out.study = pipeline::ReadStudy(fs::path(HOOF_SOURCE_DIR) / "sample_frames");
    const pipeline::TrialAnalysisOptions options;
    pipeline::TrialAnalysisOptions from_markers;
    from_markers.scale_from_markers = true;
    out.trials.resize(out.study.trial_dirs.size() + 3);
    core::ParallelFor(out.study.trial_dirs.size(), 2, [&](std::size_t i) {
      out.trials[i] = pipeline::AnalyzeTrialFolder(out.study.trial_dirs[i], out.study,
                                                   i == 3 ? from_markers : options);
    });
    pipeline::TrialSpec cut = pipeline::ReadTrial(
        fs::path(HOOF_SOURCE_DIR) / "sample_frames" / "steel_20deg_v3.28_r1", out.study);
    cut.frames.count = 14;
    out.trials[4] = pipeline::AnalyzeTrial(cut, options);
    out.trials[5] = pipeline::AnalyzeTrialFolder(Dir() / "no_such_trial", out.study, options);
    EXPECT_EQ(out.trials[1].spec.id, "steel_20deg_v3.28_r1");
    out.trials[6] = pipeline::AnalyzeTrial(
        OccludedCopy(out.study, "steel_20deg_v3.28_r1", out.trials[1].tracks), options);
    StudyInfo info;
    info.name = out.study.name;
    info.study_dir = out.study.dir;
    info.specimens = out.study.specimens;
    out.file = Dir() / "study.h5";
    WriteStudyFile(out.file, info, out.trials);
    out.groups = TrialGroupNames(out.trials);
    return out;
  }();
  return w;
}

/// What ReadTrialAnalyses gives for Study().file, read once per process.
const std::vector<pipeline::TrialAnalysis>& Read() {
  static const std::vector<pipeline::TrialAnalysis> read = ReadTrialAnalyses(Study().file);
  return read;
}

/// Exactly equal, or both NaN.
void ExpectSame(double read, double written, const std::string& what) {
  if (std::isnan(written))
    EXPECT_TRUE(std::isnan(read)) << what << ": " << read << ", expected NaN";
  else
    EXPECT_EQ(read, written) << what;
}

void ExpectSame(const Eigen::Vector2d& read, const Eigen::Vector2d& written,
                const std::string& what) {
  ExpectSame(read.x(), written.x(), what + ".x");
  ExpectSame(read.y(), written.y(), what + ".y");
}

void ExpectSameSpecimen(const pipeline::SpecimenSpec& a, const pipeline::SpecimenSpec& b) {
  ExpectSame(a.mass_kg, b.mass_kg, "mass_kg");  // NaN for a ball of unknown mass
  ExpectSame(a.inertia_kg_m2, b.inertia_kg_m2, "inertia_kg_m2");
  EXPECT_EQ(a.end_radius_m, b.end_radius_m);
  EXPECT_EQ(a.d_EC_m, b.d_EC_m);
  EXPECT_EQ(a.shape, b.shape);
  EXPECT_EQ(a.inertia, b.inertia);
  EXPECT_EQ(a.length_m, b.length_m);
  EXPECT_EQ(a.width_m, b.width_m);
  EXPECT_EQ(a.thickness_m, b.thickness_m);
  ASSERT_EQ(a.markers_B_m.size(), b.markers_B_m.size());
  for (std::size_t m = 0; m < a.markers_B_m.size(); ++m) {
    EXPECT_EQ(a.markers_B_m[m].first, b.markers_B_m[m].first);
    ExpectSame(a.markers_B_m[m].second, b.markers_B_m[m].second, "marker " + std::to_string(m));
  }
}

void ExpectSameSpec(const pipeline::TrialSpec& a, const pipeline::TrialSpec& b) {
  EXPECT_EQ(a.id, b.id);
  EXPECT_EQ(a.dir.string(), b.dir.string());
  EXPECT_EQ(a.specimen_id, b.specimen_id);
  EXPECT_EQ(a.specimen_origin, b.specimen_origin);
  ExpectSameSpecimen(a.specimen, b.specimen);
  EXPECT_EQ(a.body.model, b.body.model);
  EXPECT_EQ(a.body.shape, b.body.shape);
  EXPECT_EQ(a.body.diameter_m, b.body.diameter_m);
  EXPECT_EQ(a.surface, b.surface);
  EXPECT_EQ(a.surface_angle_deg, b.surface_angle_deg);
  EXPECT_EQ(a.fps, b.fps);
  EXPECT_EQ(a.frames.first, b.frames.first);
  EXPECT_EQ(a.frames.count, b.frames.count);
  // Not in the file: the image pattern or video (frames_source does not say which it is).
  EXPECT_TRUE(a.frames.pattern.empty());
  EXPECT_TRUE(a.frames.video.empty());
  EXPECT_EQ(a.camera.m_per_px, b.camera.m_per_px);
  ExpectSame(a.camera.gravity_image, b.camera.gravity_image, "gravity_image");
  EXPECT_EQ(a.camera.distortion, b.camera.distortion);
  EXPECT_EQ(a.camera.camera_matrix, b.camera.camera_matrix);
  ASSERT_EQ(a.surface_line_px.has_value(), b.surface_line_px.has_value());
  if (a.surface_line_px) {
    ExpectSame((*a.surface_line_px)[0], (*b.surface_line_px)[0], "surface_line_px[0]");
    ExpectSame((*a.surface_line_px)[1], (*b.surface_line_px)[1], "surface_line_px[1]");
  }
  EXPECT_EQ(a.nominal_speed_m_s, b.nominal_speed_m_s);
  EXPECT_EQ(a.notes, b.notes);
  EXPECT_EQ(a.warnings, b.warnings);
}

void ExpectSameTracks(const tracking::MarkerTracks& a, const tracking::MarkerTracks& b) {
  EXPECT_EQ(a.names, b.names);
  EXPECT_EQ(a.warnings, b.warnings);
  ASSERT_EQ(a.frames.size(), b.frames.size());
  for (std::size_t f = 0; f < a.frames.size(); ++f) {
    ASSERT_EQ(a.frames[f].size(), b.names.size()) << "frame " << f;
    for (std::size_t m = 0; m < b.frames[f].size(); ++m) {
      const auto& x = a.frames[f][m];
      const auto& y = b.frames[f][m];
      const std::string what = "frame " + std::to_string(f) + " marker " + std::to_string(m);
      EXPECT_EQ(x.found, y.found) << what;
      EXPECT_EQ(x.status, y.status) << what;
      ExpectSame(x.quality, y.quality, what + " quality");
      if (y.found) {
        ExpectSame(x.p_I, y.p_I, what + " p_I");
        ExpectSame(x.radius_px, y.radius_px, what + " radius");
      } else {  // the file holds no centre or radius for a marker not found
        EXPECT_TRUE(x.p_I.isZero(0.0)) << what;
        EXPECT_EQ(x.radius_px, 0.0) << what;
      }
    }
  }
}

void ExpectSamePoses(const std::vector<tracking::BodyPose>& a,
                     const std::vector<tracking::BodyPose>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t f = 0; f < a.size(); ++f) {
    const std::string what = "pose " + std::to_string(f);
    EXPECT_EQ(a[f].valid, b[f].valid) << what;
    EXPECT_EQ(a[f].markers_used, b[f].markers_used) << what;
    if (!b[f].valid) continue;
    ExpectSame(a[f].p_WE, b[f].p_WE, what + " p_WE");
    ExpectSame(a[f].theta_W_rad, b[f].theta_W_rad, what + " theta");
    ExpectSame(a[f].rms_residual_m, b[f].rms_residual_m, what + " rms");
    ExpectSame(a[f].marker_distance_m, b[f].marker_distance_m, what + " marker distance");
  }
}

void ExpectSameFit(const kinematics::FlightFit& a, const kinematics::FlightFit& b,
                   const std::string& what) {
  EXPECT_EQ(a.first_frame, b.first_frame) << what;
  EXPECT_EQ(a.last_frame, b.last_frame) << what;
  EXPECT_EQ(a.n, b.n) << what;
  ExpectSame(a.p_WC, b.p_WC, what + " p_WC");
  ExpectSame(a.v_WC, b.v_WC, what + " v_WC");
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) ExpectSame(a.cov_v_WC(i, j), b.cov_v_WC(i, j), what + " cov_v_WC");
  ExpectSame(a.theta_W_rad, b.theta_W_rad, what + " theta");
  ExpectSame(a.theta_se_rad, b.theta_se_rad, what + " theta_se");
  ExpectSame(a.w_rad_s, b.w_rad_s, what + " w");
  ExpectSame(a.w_se_rad_s, b.w_se_rad_s, what + " w_se");
  ExpectSame(a.rms_residual_m, b.rms_residual_m, what + " rms");
  ExpectSame(a.rms_theta_residual_rad, b.rms_theta_residual_rad, what + " rms theta");
}

void ExpectSameImpact(const kinematics::ImpactKinematics& a,
                      const kinematics::ImpactKinematics& b) {
  EXPECT_EQ(a.success, b.success);
  EXPECT_EQ(a.message, b.message);
  EXPECT_TRUE(a.flags.empty());  // not in the file (the trial's flags hold them)
  if (!b.success) {              // nothing else of a failed measurement is in the file
    EXPECT_TRUE(a.warnings.empty());
    EXPECT_EQ(a.impact_frame, -1);
    EXPECT_EQ(a.before.n, 0);
    return;
  }
  EXPECT_EQ(a.warnings, b.warnings);
  ExpectSame(a.impact_time_s, b.impact_time_s, "impact_time_s");
  EXPECT_EQ(a.impact_frame, b.impact_frame);
  ExpectSameFit(a.before, b.before, "before");
  ExpectSameFit(a.after, b.after, "after");
  ExpectSame(a.v_SC_before, b.v_SC_before, "v_SC_before");
  ExpectSame(a.v_SC_after, b.v_SC_after, "v_SC_after");
  ExpectSame(a.v_SC_before_se, b.v_SC_before_se, "v_SC_before_se");
  ExpectSame(a.v_SC_after_se, b.v_SC_after_se, "v_SC_after_se");
  ExpectSame(a.v_ST_before, b.v_ST_before, "v_ST_before");
  ExpectSame(a.v_ST_after, b.v_ST_after, "v_ST_after");
  ExpectSame(a.w_before_rad_s, b.w_before_rad_s, "w_before");
  ExpectSame(a.w_after_rad_s, b.w_after_rad_s, "w_after");
  ExpectSame(a.w_before_se_rad_s, b.w_before_se_rad_s, "w_before_se");
  ExpectSame(a.w_after_se_rad_s, b.w_after_se_rad_s, "w_after_se");
  ExpectSame(a.e, b.e, "e");
  ExpectSame(a.e_se, b.e_se, "e_se");
  ExpectSame(a.e_ci_low, b.e_ci_low, "e_ci_low");
  ExpectSame(a.e_ci_high, b.e_ci_high, "e_ci_high");
  ExpectSame(a.mu_eff, b.mu_eff, "mu_eff");
  ExpectSame(a.mu_eff_se, b.mu_eff_se, "mu_eff_se");
  ExpectSame(a.mu_eff_ci_low, b.mu_eff_ci_low, "mu_eff_ci_low");
  ExpectSame(a.mu_eff_ci_high, b.mu_eff_ci_high, "mu_eff_ci_high");
  ExpectSame(a.kinetic_energy_before_J, b.kinetic_energy_before_J, "kinetic_energy_before_J");
  ExpectSame(a.kinetic_energy_after_J, b.kinetic_energy_after_J, "kinetic_energy_after_J");
}

/// `a` (read) against `b` (analysed): everything the file holds.
void ExpectSameTrial(const pipeline::TrialAnalysis& a, const pipeline::TrialAnalysis& b) {
  SCOPED_TRACE("trial " + b.spec.id);
  ExpectSameSpec(a.spec, b.spec);
  EXPECT_EQ(a.success, b.success);
  EXPECT_EQ(a.error, b.error);
  ExpectSameTracks(a.tracks, b.tracks);
  ExpectSamePoses(a.poses, b.poses);
  ExpectSameImpact(a.impact, b.impact);
  EXPECT_EQ(a.m_per_px_used, b.m_per_px_used);
  EXPECT_EQ(a.m_per_px_from_markers, b.m_per_px_from_markers);
  EXPECT_EQ(a.surface_angle_measured_deg, b.surface_angle_measured_deg);
  ASSERT_EQ(a.marker_distance_ratio.size(), b.marker_distance_ratio.size());
  for (std::size_t f = 0; f < a.marker_distance_ratio.size(); ++f)
    ExpectSame(a.marker_distance_ratio[f], b.marker_distance_ratio[f],
               "marker_distance_ratio " + std::to_string(f));
  EXPECT_EQ(a.out_of_plane_change, b.out_of_plane_change);
  EXPECT_EQ(a.out_of_plane_noise, b.out_of_plane_noise);
  EXPECT_EQ(a.flags, b.flags);
  EXPECT_EQ(a.warnings, b.warnings);
  EXPECT_EQ(a.seconds, b.seconds);
}

TEST(ReadTrialAnalysesTest, TheWrittenTrialsComeBackFieldByField) {
  const auto& w = Study();
  const auto& read = Read();
  ASSERT_EQ(read.size(), 7u);
  for (std::size_t i = 0; i < read.size(); ++i) ExpectSameTrial(read[i], w.trials[i]);
}

TEST(ReadTrialAnalysesTest, TheReadTrialsHoldTheSampleMeasurements) {
  // What the comparison above compares is real: four measured impacts of 40 frames each, with
  // the specimen of study.json and the lens of trial.json.
  const auto& read = Read();
  ASSERT_EQ(read.size(), 7u);
  const std::map<std::string, double> speed = {{"steel_0deg_v3.00_r1", 3.0},
                                               {"steel_20deg_v3.28_r1", 3.28},
                                               {"concrete_20deg_v2.50_r1", 2.5},
                                               {"asphalt_30deg_v4.00_r1", 4.0}};
  for (std::size_t i : {0, 1, 2, 3, 6}) {
    const auto& t = read[i];
    SCOPED_TRACE(t.spec.id);
    ASSERT_TRUE(t.success) << t.error;
    EXPECT_EQ(t.spec.nominal_speed_m_s.value_or(0.0),
              speed.at(i == 6 ? "steel_20deg_v3.28_r1" : t.spec.id));
    EXPECT_EQ(t.spec.specimen_id, "A");
    EXPECT_EQ(t.spec.specimen.mass_kg, 0.008);
    EXPECT_EQ(t.spec.specimen.inertia_kg_m2, 1.5207e-6);
    EXPECT_EQ(t.spec.specimen.d_EC_m, 0.0135);
    EXPECT_EQ(t.spec.specimen.markers_B_m.at(1).second.x(), 0.024);
    EXPECT_EQ(t.spec.camera.camera_matrix.value().at(0), 1500.0);
    EXPECT_EQ(t.spec.camera.distortion.value().at(0), -0.06);
    ASSERT_TRUE(t.spec.surface_line_px.has_value());
    EXPECT_EQ(t.tracks.frames.size(), 40u);
    EXPECT_EQ(t.tracks.names, (std::vector<std::string>{"M1", "M2"}));
    EXPECT_EQ(t.poses.size(), 40u);
    EXPECT_GE(t.impact.before.n, 6);
    EXPECT_GE(t.impact.after.n, 6);
    EXPECT_GT(t.impact.e, 0.3);
    EXPECT_LT(t.impact.e, 1.0);
    EXPECT_NEAR(t.impact.impact_time_s, 0.0024, 2e-4);
    EXPECT_GT(t.m_per_px_from_markers, 1.9e-4);
    ASSERT_TRUE(t.surface_angle_measured_deg.has_value());
    EXPECT_NEAR(*t.surface_angle_measured_deg, t.spec.surface_angle_deg, 1.0);
  }
  // The asphalt trial took its scale from the markers: what CompareTrial projects with.
  EXPECT_EQ(read[3].m_per_px_used, read[3].m_per_px_from_markers);
  EXPECT_NE(read[3].m_per_px_used, read[3].spec.camera.m_per_px);
  EXPECT_EQ(read[2].m_per_px_used, read[2].spec.camera.m_per_px);
  // The occluded trial: M2 lost where painted over, those poses invalid, found again after.
  const auto& occluded = read[6];
  for (int f : kOccludedFrames) {
    const auto frame = static_cast<std::size_t>(f);
    EXPECT_TRUE(occluded.tracks.frames[frame][0].found) << f;
    EXPECT_FALSE(occluded.tracks.frames[frame][1].found) << f;
    EXPECT_EQ(occluded.tracks.frames[frame][1].status, "lost") << f;
    EXPECT_FALSE(occluded.poses[frame].valid) << f;
    EXPECT_EQ(occluded.poses[frame].markers_used, 0) << f;
    EXPECT_TRUE(std::isnan(occluded.marker_distance_ratio[frame])) << f;
  }
  EXPECT_TRUE(occluded.tracks.frames[32][1].found);
  EXPECT_TRUE(occluded.poses[32].valid);
  EXPECT_FALSE(occluded.tracks.warnings.empty());
  // The trial cut before its impact: tracked and posed, impact not measured, its own group.
  const auto& cut = read[4];
  EXPECT_EQ(Study().groups[4], "steel_20deg_v3.28_r1_2");
  EXPECT_EQ(cut.spec.id, "steel_20deg_v3.28_r1");
  EXPECT_EQ(cut.spec.frames.count, 14);
  EXPECT_FALSE(cut.success);
  EXPECT_FALSE(cut.impact.success);
  EXPECT_FALSE(cut.impact.message.empty());
  EXPECT_NE(cut.error.find("trial.json: " + cut.impact.message), std::string::npos) << cut.error;
  EXPECT_EQ(cut.tracks.frames.size(), 14u);
  EXPECT_TRUE(cut.poses.at(0).valid);
  EXPECT_EQ(cut.marker_distance_ratio.size(), 14u);
  // The trial that could not be read: its reason, nothing measured.
  const auto& missing = read[5];
  EXPECT_FALSE(missing.success);
  EXPECT_NE(missing.error.find("no_such_trial"), std::string::npos) << missing.error;
  EXPECT_EQ(missing.spec.id, "no_such_trial");
  EXPECT_TRUE(missing.spec.specimen_id.empty());
  EXPECT_TRUE(missing.tracks.frames.empty());
  EXPECT_TRUE(missing.poses.empty());
  EXPECT_FALSE(missing.spec.nominal_speed_m_s.has_value());
  EXPECT_FALSE(missing.surface_angle_measured_deg.has_value());
  EXPECT_EQ(missing.m_per_px_from_markers, 0.0);
}

void ExpectNear(double read, double written, const std::string& what) {
  if (std::isnan(written))
    EXPECT_TRUE(std::isnan(read)) << what;
  else
    EXPECT_NEAR(read, written, 1e-12) << what;
}

TEST(ReadTrialAnalysesTest, TheReadTrialsSimulateAsTheAnalysedOnes) {
  const auto& w = Study();
  const auto& read = Read();
  ASSERT_EQ(read.size(), w.trials.size());
  const compare::ModelUncertainty uncertainty{0.02, 0.03};
  for (std::size_t i = 0; i < read.size(); ++i) {
    SCOPED_TRACE(w.trials[i].spec.id);
    const bool measured = i < 4 || i == 6;
    const dynamics::ContactParameters contact =
        measured ? dynamics::PaperContact(dynamics::ParseSurface(w.trials[i].spec.surface))
                 : dynamics::PaperContact(dynamics::Surface::kSteel);
    const compare::TrialComparison a = compare::CompareTrial(read[i], contact, uncertainty);
    const compare::TrialComparison b = compare::CompareTrial(w.trials[i], contact, uncertainty);
    ASSERT_EQ(a.success, measured) << a.message;
    EXPECT_EQ(b.success, measured) << b.message;
    EXPECT_EQ(a.message, b.message);
    if (!measured) continue;
    EXPECT_GT(b.t_touch_s, 0.0022);
    EXPECT_LT(b.t_touch_s, 0.0026);
    ExpectNear(a.t_touch_s, b.t_touch_s, "t_touch_s");
    for (int k = 0; k < 2; ++k) {
      ExpectNear(a.v_SC_after_sim(k), b.v_SC_after_sim(k), "v_SC_after_sim");
      ExpectNear(a.v_SC_after_sim_se(k), b.v_SC_after_sim_se(k), "v_SC_after_sim_se");
      ExpectNear(a.v_SC_after_z(k), b.v_SC_after_z(k), "v_SC_after_z");
    }
    EXPECT_GT(b.v_SC_after_sim.y(), 0.5);  // it bounced
    ExpectNear(a.w_after_sim, b.w_after_sim, "w_after_sim");
    ExpectNear(a.w_after_z, b.w_after_z, "w_after_z");
    ExpectNear(a.kinetic_energy_after_sim_J, b.kinetic_energy_after_sim_J, "kinetic energy");
    ASSERT_EQ(a.frames.size(), 40u);
    ASSERT_EQ(a.frames.size(), b.frames.size());
    int finite = 0;
    for (std::size_t f = 0; f < a.frames.size(); ++f) {
      const auto& x = a.frames[f];
      const auto& y = b.frames[f];
      EXPECT_EQ(x.measured, y.measured) << "frame " << f;
      ASSERT_EQ(x.marker_residual_px.size(), 2u);
      ASSERT_EQ(x.marker_residual_px.size(), y.marker_residual_px.size());
      for (std::size_t m = 0; m < x.marker_residual_px.size(); ++m) {
        const std::string what = "frame " + std::to_string(f) + " marker " + std::to_string(m);
        ExpectNear(x.marker_residual_px[m], y.marker_residual_px[m], what + " residual");
        ExpectNear(x.markers_px_sim[m].x(), y.markers_px_sim[m].x(), what + " sim x");
        ExpectNear(x.markers_px_sim[m].y(), y.markers_px_sim[m].y(), what + " sim y");
        if (std::isfinite(y.marker_residual_px[m])) ++finite;
      }
    }
    EXPECT_GE(finite, 60);  // most markers were found and compared
  }
}

// ------------------------------------------------------------------------------------------
// Broken files
// ------------------------------------------------------------------------------------------

/// A copy of the study file, changed by `change` (HDF5 C++ API, read-write).
fs::path BrokenCopy(const std::string& name, const std::function<void(H5::H5File&)>& change) {
  const fs::path copy = Dir() / name;
  fs::copy_file(Study().file, copy, fs::copy_options::overwrite_existing);
  H5::H5File file(copy.string(), H5F_ACC_RDWR);
  change(file);
  return copy;
}

/// Expects ReadTrialAnalyses(`file`) to fail naming the file and `item`.
void ExpectFailureNaming(const fs::path& file, const std::string& item) {
  try {
    ReadTrialAnalyses(file);
    ADD_FAILURE() << "no error reading " << file;
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(file.string()), std::string::npos) << message;
    EXPECT_NE(message.find(item), std::string::npos) << message;
  }
}

TEST(ReadTrialAnalysesTest, AMissingFileIsAnError) {
  ExpectFailureNaming(Dir() / "no-such-study.h5", "no such file");
}

TEST(ReadTrialAnalysesTest, AFileThatIsNotAStudyFileIsAnError) {
  const fs::path text = Dir() / "text.h5";
  std::ofstream(text) << "id,e\nsteel,0.8\n";
  ExpectFailureNaming(text, "is not an HDF5 file");

  const fs::path other = Dir() / "other.h5";
  {
    H5::H5File file(other.string(), H5F_ACC_TRUNC);
    file.createGroup("/results");
  }
  ExpectFailureNaming(other, "has no attribute \"format\"");

  const fs::path renamed = BrokenCopy("renamed.h5", [](H5::H5File& f) {
    const H5::Group root = f.openGroup("/");
    root.removeAttr("format");
    const H5::StrType type(H5::PredType::C_S1, H5T_VARIABLE);
    root.createAttribute("format", type, H5::DataSpace(H5S_SCALAR))
        .write(type, std::string("something-else/1"));
  });
  ExpectFailureNaming(renamed, "format \"something-else/1\"");

  // A study file cut short (half of it, as a copy that stopped leaves it) is named as such.
  const fs::path cut = Dir() / "cut.h5";
  {
    std::ifstream in(Study().file, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  ExpectFailureNaming(cut, "cannot be opened: the HDF5 file is damaged or cut short");
}

TEST(ReadTrialAnalysesTest, AMissingTrialGroupIsNamed) {
  const std::string group = "/trials/" + Study().groups[2];
  const fs::path file = BrokenCopy("no-trial.h5", [&](H5::H5File& f) { f.unlink(group); });
  ExpectFailureNaming(file, ":" + group + " does not exist");
}

TEST(ReadTrialAnalysesTest, AMissingDatasetIsNamed) {
  const std::string trial = "/trials/" + Study().groups[1];
  const fs::path poses =
      BrokenCopy("no-poses.h5", [&](H5::H5File& f) { f.unlink(trial + "/poses/p_WE_m"); });
  ExpectFailureNaming(poses, ":" + trial + "/poses/p_WE_m does not exist");

  const fs::path fit = BrokenCopy(
      "no-fit.h5", [&](H5::H5File& f) { f.unlink(trial + "/fits/after/cov_v_WC_m2_s2"); });
  ExpectFailureNaming(fit, ":" + trial + "/fits/after/cov_v_WC_m2_s2 does not exist");

  // A trial's own specimen is read where the file has it, else the study's (files written
  // before trials kept their own): without either, the study's is named.
  const fs::path own =
      BrokenCopy("no-own-mass.h5", [&](H5::H5File& f) { f.unlink(trial + "/specimen/mass_kg"); });
  ExpectFailureNaming(own, ":" + trial + "/specimen/mass_kg does not exist");
  const fs::path specimen = BrokenCopy("no-specimen.h5", [&](H5::H5File& f) {
    f.unlink("/study/specimens/A");
    for (const std::string& g : Study().groups) f.unlink("/trials/" + g + "/specimen");
  });
  ExpectFailureNaming(specimen, ":/study/specimens/A does not exist");

  const fs::path results =
      BrokenCopy("no-results.h5", [&](H5::H5File& f) { f.unlink("/results/group"); });
  ExpectFailureNaming(results, "no column \"group\"");
}

TEST(ReadTrialAnalysesTest, ABallWithoutASpecimenComesBackAsItWasMeasured) {
  // A ball that is its own specimen (mass and inertia unknown, in no study.json) and its body
  // model come back from the trial's own group: the study file says what it was measured as.
  pipeline::TrialAnalysis t = Study().trials.at(0);
  t.spec.specimen_id = "ball";
  t.spec.specimen_origin = "t/trial.json (a ball without a specimen: mass and inertia unknown)";
  t.spec.body.model = "silhouette";
  t.spec.body.shape = "ball";
  t.spec.body.diameter_m = 0.02;
  auto& s = t.spec.specimen;
  s.shape = pipeline::SpecimenShape::kBall;
  s.inertia = pipeline::BallInertia::kUnknown;
  s.mass_kg = s.inertia_kg_m2 = std::nan("");
  s.end_radius_m = 0.01;
  s.d_EC_m = 0.0;
  s.markers_B_m.clear();
  const fs::path file = Dir() / "ball.h5";
  StudyInfo info = StudyInfo::Of(Study().study, {}, "");
  WriteStudyFile(file, info, {t});
  const auto read = ReadTrialAnalyses(file);
  ASSERT_EQ(read.size(), 1u);
  ExpectSameSpec(read[0].spec, t.spec);
  EXPECT_TRUE(std::isnan(read[0].spec.specimen.mass_kg));
  EXPECT_FALSE(read[0].spec.specimen.mass_known());
}

TEST(ReadTrialAnalysesTest, AMalformedDatasetIsNamed) {
  const std::string trial = "/trials/" + Study().groups[0];
  const fs::path file = BrokenCopy("bad-found.h5", [&](H5::H5File& f) {
    f.unlink(trial + "/tracks/found");
    const hsize_t n = 3;
    f.createDataSet(trial + "/tracks/found", H5::PredType::STD_U8LE, H5::DataSpace(1, &n));
  });
  ExpectFailureNaming(file, ":" + trial + "/tracks/found has shape [3], expected [40, 2]");

  const fs::path text = BrokenCopy("bad-e.h5", [&](H5::H5File& f) {
    f.unlink(trial + "/results/e");
    const H5::StrType type(H5::PredType::C_S1, H5T_VARIABLE);
    f.createDataSet(trial + "/results/e", type, H5::DataSpace(H5S_SCALAR))
        .write(std::string("0.9"), type);
  });
  ExpectFailureNaming(text, ":" + trial + "/results/e is not numeric");
}

}  // namespace
}  // namespace hoof::studyfile
