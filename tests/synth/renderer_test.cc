// Tests of the synthetic trial renderer against independent truth: the dynamics simulator run
// again from the recorded model, the projection written out here, and dot centroids measured
// in the written PNGs by the test's own simple method.
#include "synth/renderer.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "dynamics/impact_simulator.h"
#include "synth/test_support.h"

namespace hoof::synth {
namespace {

using testing::DotCentroid;
using testing::FreshDir;
using testing::ReadJson;
namespace fs = std::filesystem;

constexpr double kPi = 3.14159265358979323846;

struct Rendered {
  fs::path dir;
  nlohmann::json trial, truth;
  std::vector<cv::Mat> frames;
};

Rendered Render(const std::string& name, const TrialSpec& spec, const RenderOptions& options,
                const SpecimenGeometry& geometry = {}) {
  Rendered r;
  r.dir = FreshDir(name);
  const SceneAssets assets = BuildSceneAssets(geometry, options, {spec.surface}, spec.seed);
  RenderTrial(spec, geometry, options, assets, r.dir);
  r.trial = ReadJson(r.dir / "trial.json");
  r.truth = ReadJson(r.dir / "truth.json");
  for (int i = 0; i < r.trial["frames"]["count"].get<int>(); ++i) {
    char file[32];
    std::snprintf(file, sizeof(file), "%06d.png", i);
    r.frames.push_back(cv::imread((r.dir / "frames" / file).string(), cv::IMREAD_UNCHANGED));
  }
  return r;
}

TrialSpec Spec(dynamics::Surface surface, double angle_deg, double speed, std::uint64_t seed) {
  TrialSpec s;
  s.id = "t";
  s.surface = surface;
  s.angle_deg = angle_deg;
  s.speed_m_s = speed;
  s.seed = seed;
  return s;
}

/// Noise, motion blur, distortion and defocus off; lighting, vignetting and jitter stay on.
RenderOptions Sharp() {
  RenderOptions o;
  o.camera.noise = o.camera.motion_blur = o.camera.distortion = o.camera.defocus = false;
  return o;
}

cv::Point2d Px(const nlohmann::json& xy) { return {xy[0].get<double>(), xy[1].get<double>()}; }

/// Largest distance between the dot centroids measured in the frames and truth's markers_px,
/// over frames whose index passes `use`.
template <class Use>
double MaxCentroidError(const Rendered& r, double window_px, Use use) {
  double worst = 0;
  int n = 0;
  for (std::size_t i = 0; i < r.frames.size(); ++i) {
    if (!use(r.truth["frames"][i])) continue;
    for (const auto& [name, xy] : r.truth["frames"][i]["markers_px"].items()) {
      const cv::Point2d truth = Px(xy);
      const cv::Point2d c = DotCentroid(r.frames[i], truth, window_px);
      worst = std::max(worst, std::hypot(c.x - truth.x, c.y - truth.y));
      ++n;
    }
  }
  EXPECT_GT(n, 0);
  return worst;
}

// Dot radius 1.5 mm at 0.2 mm/px is 7.5 px; the window adds 3 px for the box prefilter, blur
// and defocus, and its 2 px background ring stays inside the 6 mm (15 px half-width) patch.
constexpr double kWindowPx = 10.5;

TEST(RendererTest, TruthVelocitiesMatchAnIndependentSimulation) {
  const Rendered r =
      Render("truth-velocities", Spec(dynamics::Surface::kSteel, 20, 3.17, 7), RenderOptions{});
  const nlohmann::json& t = r.truth;
  const nlohmann::json& m = t["model"];
  dynamics::ContactParameters contact(m["k_N_m"].get<double>(), m["b_N_s_m"].get<double>(),
                                      m["mu"].get<double>());
  const dynamics::ImpactSimulator sim(dynamics::SpecimenParameters{}, contact);
  const dynamics::ImpactResult ref = sim.Simulate(dynamics::ImpactConditions::Paper(3.17, 20));
  ASSERT_TRUE(ref.success);
  EXPECT_NEAR(t["v_SC_before_m_s"][0].get<double>(), ref.at_touch.v_SC.x(), 1e-12);
  EXPECT_NEAR(t["v_SC_before_m_s"][1].get<double>(), ref.at_touch.v_SC.y(), 1e-12);
  EXPECT_NEAR(t["v_SC_after_m_s"][0].get<double>(), ref.at_separation.v_SC.x(), 1e-12);
  EXPECT_NEAR(t["v_SC_after_m_s"][1].get<double>(), ref.at_separation.v_SC.y(), 1e-12);
  EXPECT_NEAR(t["w_after_rad_s"].get<double>(), ref.at_separation.w_rad_s, 1e-9);
  EXPECT_NEAR(t["e"].get<double>(), ref.e, 1e-12);
  EXPECT_NEAR(t["mu_eff"].get<double>(), ref.mu_eff, 1e-12);
  // The vertical drop of the paper: v_C before is (v sin phi, -v cos phi) in S.
  EXPECT_NEAR(t["v_SC_before_m_s"][0].get<double>(), 3.17 * std::sin(20 * kPi / 180), 1e-12);
  // zeta and b agree with the definition zeta = b / (2 sqrt(k m)) (docs/science.md, "Specimen
  // defaults").
  EXPECT_NEAR(m["zeta"].get<double>(),
              m["b_N_s_m"].get<double>() / (2 * std::sqrt(m["k_N_m"].get<double>() * 0.008)),
              1e-12);
}

TEST(RendererTest, TruthPosesAndMarkersFollowTheModelAndAnOrthographicView) {
  const Rendered r = Render("truth-poses", Spec(dynamics::Surface::kAsphalt, 30, 4.0, 11), Sharp());
  const nlohmann::json& t = r.truth;
  const nlohmann::json& m = t["model"];
  const dynamics::ImpactSimulator sim(
      dynamics::SpecimenParameters{},
      dynamics::ContactParameters(m["k_N_m"].get<double>(), m["b_N_s_m"].get<double>(),
                                  m["mu"].get<double>()));
  std::vector<double> times;
  const double t_touch = t["impact_time_s"].get<double>();
  for (const auto& f : t["frames"]) times.push_back(f["t_s"].get<double>() - t_touch);
  const dynamics::ImpactResult ref =
      sim.Simulate(dynamics::ImpactConditions::Paper(4.0, 30), times);
  const double phi = 30 * kPi / 180, s = 2e-4;
  const cv::Point2d c = Px(t["contact_point_px_undistorted"]);
  for (std::size_t i = 0; i < times.size(); ++i) {
    const nlohmann::json& f = t["frames"][i];
    EXPECT_NEAR(f["t_s"].get<double>(), static_cast<double>(i) / 8000.0, 1e-15);
    // S -> W: x_S = (cos phi, -sin phi), y_S = (sin phi, cos phi).
    const Eigen::Vector2d p_SE = ref.samples[i].p_SE;
    const double ex = p_SE.x() * std::cos(phi) + p_SE.y() * std::sin(phi);
    const double ey = -p_SE.x() * std::sin(phi) + p_SE.y() * std::cos(phi);
    const double th = ref.samples[i].body.theta_S_rad - phi;
    EXPECT_NEAR(f["p_WE_m"][0].get<double>(), ex, 1e-12);
    EXPECT_NEAR(f["p_WE_m"][1].get<double>(), ey, 1e-12);
    EXPECT_NEAR(f["theta_W_rad"].get<double>(), th, 1e-12);
    // Markers on the long axis: p = E + x_B (cos th, sin th); image y runs down.
    for (const auto& [name, x_B] :
         std::vector<std::pair<std::string, double>>{{"M1", 0.006}, {"M2", 0.024}}) {
      const cv::Point2d u = Px(f["markers_px_undistorted"][name]);
      EXPECT_NEAR(u.x, c.x + (ex + x_B * std::cos(th)) / s, 1e-9);
      EXPECT_NEAR(u.y, c.y - (ey + x_B * std::sin(th)) / s, 1e-9);
    }
  }
  EXPECT_NEAR(t_touch, (t["first_frame_after_touch"].get<int>() - 0.5) / 8000.0, 0.5 / 8000.0);
}

TEST(RendererTest, DotCentroidsOfASharpRenderMatchTruthToFiveHundredthsOfAPixel) {
  // Three markers, two surfaces, all 60 frames each: sub-pixel positions sweep the grid.
  SpecimenGeometry g;
  g.markers.push_back({"M3", {0.015, 0.0035}});
  double worst = 0;
  for (const auto& [surface, angle, seed] : std::vector<std::tuple<dynamics::Surface, double, int>>{
           {dynamics::Surface::kSteel, 0, 21}, {dynamics::Surface::kConcrete, 30, 22}}) {
    const Rendered r = Render("sharp-centroids", Spec(surface, angle, 3.5, seed), Sharp(), g);
    worst =
        std::max(worst, MaxCentroidError(r, kWindowPx, [](const nlohmann::json&) { return true; }));
  }
  RecordProperty("max_centroid_error_px", std::to_string(worst));
  std::printf("sharp render: max centroid error %.4f px\n", worst);
  EXPECT_LT(worst, 0.05);
}

TEST(RendererTest, MotionBlurKeepsTheDotCentroidAtMidExposure) {
  // Blur and defocus on, noise and distortion off. The centroid is linear in the image, so
  // the blurred centroid is the mean of the sub-sample centroids, each as accurate as a sharp
  // render (< 0.05 px); a symmetric sampling of a constant-velocity path averages to the
  // mid-exposure point, and gravity's curvature adds g T^2 / 24 = 2e-9 m = 1e-5 px over
  // T = 1/16000 s. Frames whose exposure overlaps the contact are left out: there the velocity
  // turns within the exposure and the blur centroid is not the mid-exposure pose.
  RenderOptions o = Sharp();
  o.camera.motion_blur = o.camera.defocus = true;
  const Rendered r = Render("blurred-centroids", Spec(dynamics::Surface::kSteel, 20, 4.0, 31), o);
  const double t0 = r.truth["impact_time_s"].get<double>();
  const double t1 = t0 + r.truth["contact_duration_s"].get<double>();
  const double half = o.camera.exposure_s / 2;
  const double worst = MaxCentroidError(r, kWindowPx, [&](const nlohmann::json& f) {
    const double t = f["t_s"].get<double>();
    return t + half < t0 || t - half > t1;
  });
  std::printf("blurred render: max centroid error %.4f px\n", worst);
  EXPECT_LT(worst, 0.05 + 1e-3);
}

TEST(RendererTest, DistortedTruthIsOpenCvsModelAndTheImageAgrees) {
  RenderOptions o = Sharp();
  o.camera.distortion = true;
  o.camera.k1 = -0.2;  // stronger than the default, to make the check bite
  const Rendered r = Render("distorted", Spec(dynamics::Surface::kConcrete, 10, 3.0, 41), o);
  const auto& k = r.trial["camera"]["distortion"];
  const auto& cm = r.trial["camera"]["camera_matrix"];
  const double f = cm[0][0].get<double>(), cx = cm[0][2].get<double>(), cy = cm[1][2].get<double>();
  const double k1 = k[0], k2 = k[1], p1 = k[2], p2 = k[3], k3 = k[4];
  for (const auto& fr : r.truth["frames"])
    for (const auto& [name, xy] : fr["markers_px_undistorted"].items()) {
      const double x = (xy[0].get<double>() - cx) / f, y = (xy[1].get<double>() - cy) / f;
      const double r2 = x * x + y * y, radial = 1 + k1 * r2 + k2 * r2 * r2 + k3 * r2 * r2 * r2;
      const double xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x);
      const double yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y;
      EXPECT_NEAR(fr["markers_px"][name][0].get<double>(), cx + f * xd, 1e-9);
      EXPECT_NEAR(fr["markers_px"][name][1].get<double>(), cy + f * yd, 1e-9);
    }
  // The distorted dot is a slightly warped disc whose centroid moves by a second-order term
  // (k1 (r/f)^2 over the dot's 7.5 px, far below 0.01 px).
  const double worst = MaxCentroidError(r, kWindowPx, [](const nlohmann::json&) { return true; });
  std::printf("distorted render: max centroid error %.4f px\n", worst);
  EXPECT_LT(worst, 0.05);
}

TEST(RendererTest, OutOfPlaneTiltForeshortensTheMarkerSeparation) {
  TrialSpec spec = Spec(dynamics::Surface::kSteel, 10, 3.0, 51);
  spec.hidden.out_of_plane = {25.0, 10.0, 800.0, 0.0};  // tilt 25 deg + 800 deg/s, roll 10 deg
  const Rendered r = Render("out-of-plane", spec, Sharp());
  const nlohmann::json& oop = r.truth["model"]["hidden_effects"]["out_of_plane"];
  EXPECT_EQ(oop["tilt_deg"].get<double>(), 25.0);
  const double t_touch = r.truth["impact_time_s"].get<double>();
  for (const auto& f : r.truth["frames"]) {
    const double tilt = (25.0 + 800.0 * (f["t_s"].get<double>() - t_touch)) * kPi / 180;
    EXPECT_NEAR(f["out_of_plane_tilt_rad"].get<double>(), tilt, 1e-12);
    const cv::Point2d a = Px(f["markers_px_undistorted"]["M1"]),
                      b = Px(f["markers_px_undistorted"]["M2"]);
    // 18 mm apart on the long axis: the tilt about y_B turns it out of the image plane.
    EXPECT_NEAR(std::hypot(a.x - b.x, a.y - b.y), 0.018 * std::cos(tilt) / 2e-4, 1e-9);
  }
  // The foreshortened dots (ellipses) are drawn where truth says.
  const double worst = MaxCentroidError(r, kWindowPx, [](const nlohmann::json&) { return true; });
  std::printf("out-of-plane render: max centroid error %.4f px\n", worst);
  EXPECT_LT(worst, 0.05);
}

TEST(RendererTest, DroppedAndDuplicatedFramesAreRecorded) {
  RenderOptions o;
  o.camera.drop_frame_probability = 0.1;
  o.camera.duplicate_frame_probability = 0.1;
  const Rendered r = Render("defects", Spec(dynamics::Surface::kAsphalt, 0, 2.0, 61), o);
  int dropped = 0, duplicated = 0;
  const auto& frames = r.truth["frames"];
  for (std::size_t i = 1; i < frames.size(); ++i) {
    const double dt = frames[i]["t_s"].get<double>() - frames[i - 1]["t_s"].get<double>();
    const std::string defect = frames[i].value("defect", "");
    if (defect == "duplicate") {
      ++duplicated;
      EXPECT_EQ(dt, 0.0);
      EXPECT_EQ(cv::norm(r.frames[i], r.frames[i - 1], cv::NORM_INF), 0.0);
    } else if (defect == "dropped_before") {
      ++dropped;
      EXPECT_NEAR(dt,
                  2 / 8000.0 + (frames[i - 1].value("defect", "") == "duplicate" ? 1 / 8000.0 : 0),
                  1e-12);
    }
  }
  EXPECT_GT(dropped, 0);
  EXPECT_GT(duplicated, 0);
  EXPECT_EQ(r.truth["frame_defects"].size(), static_cast<std::size_t>(dropped + duplicated));
}

}  // namespace
}  // namespace hoof::synth
