// The silhouette tracker on frames drawn by the renderer (src/synth: a Lambertian ball lit from
// the upper left on a dark studio, or the unmarked specimen, over a textured surface block),
// against the renderer's truth: the image of the centre of mass per frame
// (FrameTruth::center_px). Small clips around the contact (a few seconds in all).
#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "synth/renderer.h"
#include "tracking/silhouette_tracker.h"

namespace hoof::tracking {
namespace {

class VectorSource : public FrameSource {
 public:
  std::vector<cv::Mat> frames;
  int count() const override { return static_cast<int>(frames.size()); }
  cv::Mat Read(int i) override { return frames.at(static_cast<std::size_t>(i)); }
  std::string Describe(int i) const override { return "rendered frame " + std::to_string(i); }
};

/// Frames that a track's warnings name: one for "F: ...", N for "F to L (N frames): ...".
int FramesWarnedOf(const std::vector<std::string>& warnings) {
  int frames = 0;
  for (const std::string& w : warnings) {
    const auto run = w.find(" frames): ");
    if (run == std::string::npos) {
      ++frames;
      continue;
    }
    const auto open = w.rfind('(', run);
    frames += std::stoi(w.substr(open + 1, run - open - 1));
  }
  return frames;
}

struct Rendered {
  synth::SpecimenGeometry geometry;
  synth::RenderOptions options;
  synth::TrialTruth truth;
  VectorSource source;
};

/// A trial at 8000 fps with the renderer's default nuisances (noise, motion blur, defocus, lens
/// distortion, vignetting), `before` frames before the first touch and `after` from it; the
/// scene's textures from `scene_seed` (a study's seed), by default the trial's.
Rendered Render(synth::Body body, synth::Lighting lighting, dynamics::Surface surface,
                double angle_deg, std::uint64_t seed, int before, int after,
                std::optional<std::uint64_t> scene_seed = std::nullopt,
                double speed_m_s = synth::TrialSpec{}.speed_m_s) {
  Rendered r;
  r.geometry.body = body;
  r.options.lighting = lighting;
  r.options.frames_before = before;
  r.options.frames_after = after;
  synth::TrialSpec spec;
  spec.surface = surface;
  spec.angle_deg = angle_deg;
  spec.seed = seed;
  spec.speed_m_s = speed_m_s;
  r.truth = synth::PlanTrial(spec, r.geometry, r.options);
  const synth::SceneAssets assets =
      synth::BuildSceneAssets(r.geometry, r.options, {surface}, scene_seed.value_or(seed));
  r.source.frames = synth::RenderFrames(r.truth, r.geometry, r.options, assets);
  return r;
}

/// Distance (px) of `p` from the surface line, positive on the side of `side`.
double AboveSurface(const synth::TrialTruth& truth, const Eigen::Vector2d& p,
                    const Eigen::Vector2d& side) {
  const Eigen::Vector2d a = truth.surface_line_px[0], b = truth.surface_line_px[1];
  const Eigen::Vector2d d = (b - a).normalized();
  const Eigen::Vector2d n{-d.y(), d.x()};
  const double s = (side - a).dot(n) > 0 ? 1.0 : -1.0;
  return s * (p - a).dot(n);
}

TEST(SilhouetteRenderedTest, FrontLitBallIsCentredStablyThroughTheBounce) {
  // A front-lit ball is a shaded sphere: its limb on the side away from the light is as dark as
  // the studio behind it, and near the contact the surface block lies beside it. The centre
  // may carry one constant offset (the shaded limb is found slightly inside on the dark side,
  // the same in every frame since the lights do not move), but must not walk: per frame, the
  // error minus the clip's median error is within 5 of the tracker's own reported standard
  // deviations (measured here: about 0.02 px) wherever the ball is clear of the surface by
  // 2 px or more; in the frames at the contact, within 0.25 px.
  int frames_checked = 0;
  for (const auto surface : {dynamics::Surface::kSteel, dynamics::Surface::kAsphalt}) {
    const std::uint64_t seed = surface == dynamics::Surface::kSteel ? 3 : 2;
    Rendered r = Render(synth::Body::kBall, synth::Lighting::kFront, surface, 20.0, seed, 6, 10);
    const double radius_px = r.geometry.ball_diameter_m / 2 / r.options.m_per_px;
    const SilhouetteTrack track = TrackSilhouette(r.source, SilhouetteOptions{});
    ASSERT_EQ(track.frame_count(), static_cast<int>(r.truth.frames.size()));
    std::vector<double> ex, ey;
    for (int j = 0; j < track.frame_count(); ++j) {
      const auto& o = track.frames[static_cast<std::size_t>(j)];
      ASSERT_TRUE(o.found) << "frame " << j << ": " << o.status;
      const Eigen::Vector2d e = o.p_I - r.truth.frames[static_cast<std::size_t>(j)].center_px;
      ex.push_back(e.x());
      ey.push_back(e.y());
      EXPECT_NEAR(o.diameter_px, 2 * radius_px, 1.5) << "frame " << j;
    }
    const auto median = [](std::vector<double> v) {
      std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
      return v[v.size() / 2];
    };
    const Eigen::Vector2d bias{median(ex), median(ey)};
    std::cout << dynamics::SurfaceName(surface) << ": constant offset " << bias.transpose()
              << " px\n";
    EXPECT_LT(bias.norm(), 0.5);
    const Eigen::Vector2d up = r.truth.frames[0].center_px;  // the ball starts above the surface
    for (int j = 0; j < track.frame_count(); ++j) {
      const auto& o = track.frames[static_cast<std::size_t>(j)];
      const auto& t = r.truth.frames[static_cast<std::size_t>(j)];
      const Eigen::Vector2d d =
          Eigen::Vector2d(ex[static_cast<std::size_t>(j)], ey[static_cast<std::size_t>(j)]) - bias;
      const double gap = AboveSurface(r.truth, t.center_px, up) - radius_px;
      if (gap >= 2.0) {
        EXPECT_LT(std::abs(d.x()), 5 * std::sqrt(o.cov_p_I(0, 0))) << "frame " << j;
        EXPECT_LT(std::abs(d.y()), 5 * std::sqrt(o.cov_p_I(1, 1))) << "frame " << j;
        ++frames_checked;
      } else {
        EXPECT_LT(d.norm(), 0.25) << "frame " << j << " (" << gap << " px from the surface)";
      }
    }
  }
  EXPECT_GT(frames_checked, 20);
}

// A front-lit ball on a 10 deg steel block in a 320 x 320 frame (where `hoofimpact init` on a
// rendered CINE first met it): in the four frames at the contact the lit block joins the
// ball's lower limb (from 2.8 px before they touch), and every edge point of the joined shape lies
// near one circle 3.7 px wider whose centre is 1.0-1.9 px off toward the block, so the robust refit
// keeps them all. Its diameter gives it away: those frames are left out as joined (the ball's size
// does not change), and every frame still found is centred on the truth.
TEST(SilhouetteRenderedTest, AFrontLitBallJoinedByTheLitBlockIsLeftOutNotMisplaced) {
  Rendered r;
  r.options.lighting = synth::Lighting::kFront;
  r.options.width_px = 320;
  r.options.height_px = 320;
  synth::TrialSpec spec;
  spec.surface = dynamics::Surface::kSteel;
  spec.angle_deg = 10.0;
  spec.seed = 2;
  r.geometry.body = synth::Body::kBall;
  r.truth = synth::PlanTrial(spec, r.geometry, r.options);
  const synth::SceneAssets assets =
      synth::BuildSceneAssets(r.geometry, r.options, {spec.surface}, spec.seed);
  r.source.frames = synth::RenderFrames(r.truth, r.geometry, r.options, assets);
  const double radius_px = r.geometry.ball_diameter_m / 2 / r.options.m_per_px;
  const SilhouetteTrack track = TrackSilhouette(r.source, SilhouetteOptions{});
  ASSERT_EQ(track.frame_count(), static_cast<int>(r.truth.frames.size()));
  const Eigen::Vector2d up = r.truth.frames[0].center_px;
  std::vector<double> ex, ey;
  for (int j = 0; j < track.frame_count(); ++j) {
    const auto& o = track.frames[static_cast<std::size_t>(j)];
    if (!o.found) continue;
    ex.push_back(o.p_I.x() - r.truth.frames[static_cast<std::size_t>(j)].center_px.x());
    ey.push_back(o.p_I.y() - r.truth.frames[static_cast<std::size_t>(j)].center_px.y());
  }
  const auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  const Eigen::Vector2d bias{median(ex), median(ey)};
  int left_out = 0;
  for (int j = 0; j < track.frame_count(); ++j) {
    const auto& o = track.frames[static_cast<std::size_t>(j)];
    const auto& t = r.truth.frames[static_cast<std::size_t>(j)];
    const double gap = AboveSurface(r.truth, t.center_px, up) - radius_px;
    if (!o.found) {
      ++left_out;
      // Defocus and motion blur spread each edge over about 2 px, so the ball's and the block's
      // blurred edges merge a few px before they touch (frame 31: 2.8 px).
      EXPECT_LT(gap, 4.0) << "frame " << j << " left out (" << o.status << ") away from the block";
      continue;
    }
    EXPECT_LT((o.p_I - t.center_px - bias).norm(), 0.25)
        << "frame " << j << " (" << gap << " px from the block)";
  }
  EXPECT_GE(left_out, 1);
  EXPECT_LE(left_out, 6);
  // Every frame left out is named by a warning: one per frame, or one per run of frames.
  EXPECT_EQ(FramesWarnedOf(track.warnings), left_out);
}

TEST(SilhouetteRenderedTest, AnOutlineJoinedByTheSurfaceAtTheContactDoesNotJump) {
  // At the contact the unmarked specimen's outline joins the surface block (back-lit: both
  // dark on the bright light; front-lit: the lit face beside the lit block). The area
  // centroid of the joined region would jump by many px toward the block; such frames must be
  // refused, not measured. The centroid is a fixed point of the body, so in body axes its
  // offset from the centre of mass is the same in every frame measured: it may not move by
  // more than 0.1 px (5 times the frame-to-frame scatter measured on these clips, about 0.02
  // px; the tracker's reported s.d. of an outline's centroid, 0.001-0.003 px, is too small to
  // bound it). At most 3 frames about the contact are lost.
  for (const auto lighting : {synth::Lighting::kBacklit, synth::Lighting::kFront}) {
    Rendered r =
        Render(synth::Body::kUnmarked, lighting, dynamics::Surface::kConcrete, 40.0, 2, 6, 10);
    SilhouetteOptions options;
    options.shape = SilhouetteShape::kOutline;
    const SilhouetteTrack track = TrackSilhouette(r.source, options);
    std::vector<Eigen::Vector2d> offsets_B;
    std::vector<int> lost;
    for (int j = 0; j < track.frame_count(); ++j) {
      const auto& o = track.frames[static_cast<std::size_t>(j)];
      const auto& t = r.truth.frames[static_cast<std::size_t>(j)];
      if (!o.found) {
        lost.push_back(j);
        continue;
      }
      // Image (y down) to body axes: x_B along the measured axis direction of the truth.
      const double a = o.angle_I_rad;
      const Eigen::Vector2d e = o.p_I - t.center_px;
      offsets_B.emplace_back(std::cos(a) * e.x() + std::sin(a) * e.y(),
                             -std::sin(a) * e.x() + std::cos(a) * e.y());
    }
    ASSERT_GE(offsets_B.size(), r.truth.frames.size() - 3) << synth::ToString(lighting);
    for (int j : lost)
      EXPECT_LE(std::abs(j - r.truth.first_frame_after_touch), 2)
          << synth::ToString(lighting) << ": frame " << j << " lost away from the contact";
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& v : offsets_B) mean += v / static_cast<double>(offsets_B.size());
    double worst = 0;
    for (const auto& v : offsets_B) worst = std::max(worst, (v - mean).norm());
    std::cout << synth::ToString(lighting) << ": centroid - C in body axes " << mean.transpose()
              << " px, worst frame off it by " << worst << " px, " << lost.size()
              << " frames lost\n";
    EXPECT_LT(worst, 0.1) << synth::ToString(lighting);
  }
}

TEST(SilhouetteRenderedTest, AnOutlineJoinedByAGrainOfTheSurfaceIsLeftOut) {
  // The unmarked specimen falling upright at 2 m/s onto asphalt at 20 deg, as trial
  // asphalt_20deg_v2.00_r3 of `hoofimpact synth --study --seed 20 --body unmarked --surfaces
  // asphalt --angles-deg 20 --speeds 2,3` draws it (its trial seed; the scene's textures from the
  // study's seed). e is 0.35, so the round end leaves the surface at 0.4 px per frame, and for
  // the five frames from just before the touch a lit grain of the asphalt beside it joins the
  // outline: the region is 1.1 px longer (218.2 px for 217.2), its centroid 0.46 px toward the
  // grain and its axis 2.5 mrad off. Too little for the "outline grew" refusal, it passed as the
  // body's motion (a jump of the normal velocity as the grain let go, taken for a second bounce
  // three frames after the impact, which left 1 frame for the fit after it). Those frames are
  // now left out by their length; every frame kept sits at the same point of the body to within
  // 0.1 px (the bound of AnOutlineJoinedByTheSurfaceAtTheContactDoesNotJump).
  Rendered r = Render(synth::Body::kUnmarked, synth::Lighting::kFront, dynamics::Surface::kAsphalt,
                      20.0, 4645975589145387511ULL, 8, 16, /*scene_seed=*/20, /*speed_m_s=*/2.0);
  SilhouetteOptions options;
  options.shape = SilhouetteShape::kOutline;
  const SilhouetteTrack track = TrackSilhouette(r.source, options);
  std::vector<Eigen::Vector2d> offsets_B;
  int lost = 0;
  for (int j = 0; j < track.frame_count(); ++j) {
    const auto& o = track.frames[static_cast<std::size_t>(j)];
    const auto& t = r.truth.frames[static_cast<std::size_t>(j)];
    if (!o.found) {
      ++lost;
      EXPECT_LE(std::abs(j - r.truth.first_frame_after_touch), 5)
          << "frame " << j << " lost away from the contact (" << o.status << ")";
      continue;
    }
    const double a = o.angle_I_rad;
    const Eigen::Vector2d e = o.p_I - t.center_px;
    offsets_B.emplace_back(std::cos(a) * e.x() + std::sin(a) * e.y(),
                           -std::sin(a) * e.x() + std::cos(a) * e.y());
  }
  EXPECT_GE(lost, 1);
  EXPECT_LE(lost, 6);
  EXPECT_EQ(FramesWarnedOf(track.warnings), lost);
  ASSERT_GE(offsets_B.size(), 18u);
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& v : offsets_B) mean += v / static_cast<double>(offsets_B.size());
  double worst = 0;
  for (const auto& v : offsets_B) worst = std::max(worst, (v - mean).norm());
  std::cout << "centroid - C in body axes " << mean.transpose() << " px, worst frame off it by "
            << worst << " px, " << lost << " frames lost\n";
  EXPECT_LT(worst, 0.1);
}

}  // namespace
}  // namespace hoof::tracking
