#include "synth/renderer.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <system_error>

#include <unistd.h>

#include <opencv2/imgcodecs.hpp>

#include "core/frames.h"
#include "io/atomic_file.h"
#include "io/interrupt.h"
#include "synth/camera_model.h"
#include "synth/frame_renderer.h"
#include "synth/trial_files.h"

namespace hoof::synth {
namespace fs = std::filesystem;
namespace {

using core::kRadPerDeg;

/// Which capture each written frame shows, and its defect.
struct CaptureSchedule {
  std::vector<int> capture;
  std::vector<std::string> defect;
};

CaptureSchedule ScheduleCaptures(int count, const CameraEffects& cam, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  CaptureSchedule s{std::vector<int>(count), std::vector<std::string>(count)};
  int next = 0;
  for (int j = 0; j < count; ++j) {
    const double drop = unit(rng), duplicate = unit(rng);  // always drawn: stable streams
    if (j > 0 && drop < cam.drop_frame_probability) {
      ++next;
      s.defect[j] = "dropped_before";
    }
    if (j > 0 && s.defect[j].empty() && duplicate < cam.duplicate_frame_probability) {
      s.capture[j] = s.capture[j - 1];  // the previous image again; this capture is lost
      s.defect[j] = "duplicate";
      ++next;
      continue;
    }
    s.capture[j] = next++;
  }
  return s;
}

/// Mid-exposure offsets of the sub-samples (s), symmetric about 0.
std::vector<double> ExposureOffsets(const CameraEffects& cam) {
  if (!cam.motion_blur) return {0.0};
  std::vector<double> o(cam.blur_samples);
  for (int k = 0; k < cam.blur_samples; ++k)
    o[k] = cam.exposure_s * ((k + 0.5) / cam.blur_samples - 0.5);
  return o;
}

BodyPose ToPose(const dynamics::TrajectorySample& s, double phi, const OutOfPlane& oop) {
  const core::SurfaceRotation R_WS(phi);
  BodyPose p;
  p.p_WE = R_WS.ToW(s.p_SE);
  p.theta_W_rad = R_WS.AngleToW(s.body.theta_S_rad);
  p.tilt_rad = (oop.tilt_deg + oop.tilt_rate_deg_s * s.t_s) * kRadPerDeg;
  p.roll_rad = (oop.roll_deg + oop.roll_rate_deg_s * s.t_s) * kRadPerDeg;
  return p;
}

/// Places the contact point in the frame so that every marker patch stays in view (when it
/// can), the surface in the lower part, plus a random offset when jitter is on.
Eigen::Vector2d FrameContact(const std::vector<BodyPose>& poses, const SpecimenGeometry& g,
                             const RenderOptions& o, const Eigen::Vector2d& jitter_px) {
  ViewGeometry view{o.m_per_px, {0.0, 0.0}, g.dynamics.d_EC_m};
  const double pad = g.patch_size_m / o.m_per_px + 4;
  double x0 = 1e300, x1 = -1e300, y0 = 1e300;
  for (const BodyPose& p : poses)
    for (const Marker& m : g.markers) {
      const Eigen::Vector2d q =
          ProjectBodyPoint(p, {m.p_BM_m.x(), m.p_BM_m.y(), g.thickness_m / 2}, view);
      x0 = std::min(x0, q.x());
      x1 = std::max(x1, q.x());
      y0 = std::min(y0, q.y());
    }
  Eigen::Vector2d c{o.width_px / 2.0 - (x0 + x1) / 2, std::max(0.76 * o.height_px, pad - y0)};
  c.y() = std::min(c.y(), o.height_px - 16.0);
  return c + jitter_px;
}

/// Two points of the surface line inside the frame (ideal image), then distorted.
std::array<Eigen::Vector2d, 2> SurfaceLine(const Eigen::Vector2d& c, double phi,
                                           const RenderOptions& o, const LensModel& lens) {
  const Eigen::Vector2d d{std::cos(phi), std::sin(phi)};
  double t0 = (8.0 - c.x()) / d.x(), t1 = (o.width_px - 9.0 - c.x()) / d.x();
  if (std::abs(d.y()) > 1e-12) {
    const double a = (8.0 - c.y()) / d.y(), b = (o.height_px - 9.0 - c.y()) / d.y();
    t0 = std::max(t0, std::min(a, b));
    t1 = std::min(t1, std::max(a, b));
  }
  return {lens.Distort(c + t0 * d), lens.Distort(c + t1 * d)};
}

/// A folder written under a temporary name and renamed into place by Commit().
class TemporaryFolder {
 public:
  explicit TemporaryFolder(const fs::path& target) : target_(target) {
    static std::atomic<int> counter{0};
    temp_ = target.parent_path() / ("." + target.filename().string() + ".tmp-" +
                                    std::to_string(::getpid()) + "-" + std::to_string(counter++));
    const io::CreatingTemporary creating;
    io::TrackTemporary(temp_);  // an interrupt removes it
    std::error_code ec;
    fs::create_directories(temp_ / "frames", ec);
    if (ec)
      throw std::runtime_error("cannot create output folder '" + temp_.parent_path().string() +
                               "': " + ec.message());
  }
  ~TemporaryFolder() {
    std::error_code ec;
    if (!committed_) fs::remove_all(temp_, ec);
    io::UntrackTemporary(temp_);
  }
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  const fs::path& path() const { return temp_; }
  void Commit(bool overwrite) {
    std::error_code ec;
    fs::path trash;
    if (fs::exists(target_)) {
      if (!overwrite) throw std::runtime_error("output folder '" + target_.string() + "' exists");
      trash = temp_.string() + ".old";
      fs::rename(target_, trash, ec);
      if (ec)
        throw std::runtime_error("cannot replace '" + target_.string() + "': " + ec.message());
    }
    fs::rename(temp_, target_, ec);
    if (ec)
      throw std::runtime_error("cannot rename '" + temp_.string() + "' to '" + target_.string() +
                               "': " + ec.message());
    committed_ = true;
    if (!trash.empty()) fs::remove_all(trash, ec);
  }

 private:
  fs::path target_, temp_;
  bool committed_ = false;
};

void WritePng(const fs::path& path, const cv::Mat& image, const RenderOptions& options) {
  bool ok = false;
  std::vector<int> params = {cv::IMWRITE_PNG_COMPRESSION, options.png_compression};
  if (options.png_huffman_only)
    params.insert(params.end(), {cv::IMWRITE_PNG_STRATEGY, cv::IMWRITE_PNG_STRATEGY_HUFFMAN_ONLY});
  try {
    ok = cv::imwrite(path.string(), image, params);
  } catch (const cv::Exception& e) {
    throw std::runtime_error("cannot write '" + path.string() + "': " + e.what());
  }
  if (!ok) throw std::runtime_error("cannot write '" + path.string() + "'");
}

}  // namespace

const SurfaceTexture& SceneAssets::Surface(dynamics::Surface surface) const {
  for (const SurfaceTexture& s : surfaces)
    if (s.surface == surface) return s;
  throw std::invalid_argument("no surface texture for '" + dynamics::SurfaceName(surface) + "'");
}

SceneAssets BuildSceneAssets(const SpecimenGeometry& geometry, const RenderOptions& options,
                             const std::vector<dynamics::Surface>& surfaces, std::uint64_t seed) {
  geometry.Validate();
  options.Validate();
  SceneAssets a;
  a.specimen = BuildSpecimenTexture(geometry, options.m_per_px, options.texture_oversampling,
                                    MixSeed(seed, 1));
  for (dynamics::Surface s : surfaces) {
    bool have = false;
    for (const SurfaceTexture& t : a.surfaces) have = have || t.surface == s;
    if (!have)
      a.surfaces.push_back(BuildSurfaceTexture(s, options.m_per_px,
                                               cv::Size(options.width_px, options.height_px),
                                               MixSeed(seed, 10 + static_cast<std::uint64_t>(s))));
  }
  return a;
}

TrialTruth PlanTrial(const TrialSpec& spec, const SpecimenGeometry& geometry,
                     const RenderOptions& options) {
  spec.Validate();
  geometry.Validate();
  options.Validate();
  TrialTruth t;
  t.spec = spec;
  std::mt19937_64 rng(spec.seed);
  t.draw = DrawContact(spec, geometry.dynamics, rng);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double touch_fraction = unit(rng);
  Eigen::Vector2d jitter{unit(rng) * 6 - 3, unit(rng) * 6 - 3};
  t.surface_u_offset_px = (unit(rng) - 0.5) * 400;
  if (!options.camera.subpixel_jitter) jitter.setZero();
  const int count = options.frames_before + options.frames_after;
  const CaptureSchedule schedule = ScheduleCaptures(count, options.camera, rng);
  t.impact_time_s = (options.frames_before - 1 + touch_fraction) / options.fps;

  // All sample times since first touch: frame centres, then exposure sub-samples.
  const std::vector<double> offsets = ExposureOffsets(options.camera);
  std::vector<double> times;
  for (int j = 0; j < count; ++j)
    times.push_back(schedule.capture[j] / options.fps - t.impact_time_s);
  for (int j = 0; j < count; ++j)
    for (double o : offsets) times.push_back(times[j] + o);
  const dynamics::ImpactSimulator sim(geometry.dynamics, t.draw.contact);
  const double phi = spec.angle_deg * kRadPerDeg;
  t.impact = sim.Simulate(dynamics::ImpactConditions::Paper(spec.speed_m_s, spec.angle_deg), times);
  if (!t.impact.success)
    throw std::runtime_error("trial " + spec.id + ": simulation failed: " + t.impact.message);

  std::vector<BodyPose> centres;
  for (int j = 0; j < count; ++j)
    centres.push_back(ToPose(t.impact.samples[j], phi, spec.hidden.out_of_plane));
  t.contact_px = FrameContact(centres, geometry, options, jitter);
  const LensModel lens(options.camera, options.width_px, options.height_px);
  const ViewGeometry view{options.m_per_px, t.contact_px, geometry.dynamics.d_EC_m};
  t.surface_line_px = SurfaceLine(t.contact_px, phi, options, lens);
  t.first_frame_after_touch = count;
  for (int j = 0; j < count; ++j) {
    const dynamics::TrajectorySample& s = t.impact.samples[j];
    FrameTruth f;
    f.capture_index = schedule.capture[j];
    f.t_s = schedule.capture[j] / options.fps;
    f.pose = centres[j];
    f.p_WC = core::SurfaceRotation(phi).ToW(s.body.p_SC);
    f.phase = dynamics::ToString(s.phase);
    f.defect = schedule.defect[j];
    for (const Marker& m : geometry.markers) {
      const Eigen::Vector2d u =
          ProjectBodyPoint(f.pose, {m.p_BM_m.x(), m.p_BM_m.y(), geometry.thickness_m / 2}, view);
      f.markers_px_undistorted.push_back(u);
      f.markers_px.push_back(lens.Distort(u));
    }
    if (f.t_s >= t.impact_time_s && t.first_frame_after_touch == count)
      t.first_frame_after_touch = j;
    std::vector<BodyPose> exposure;
    for (std::size_t k = 0; k < offsets.size(); ++k)
      exposure.push_back(
          ToPose(t.impact.samples[count + j * offsets.size() + k], phi, spec.hidden.out_of_plane));
    t.exposure_poses.push_back(std::move(exposure));
    t.frames.push_back(std::move(f));
  }
  t.impact.samples.clear();
  return t;
}

std::vector<cv::Mat> RenderFrames(const TrialTruth& truth, const SpecimenGeometry& geometry,
                                  const RenderOptions& options, const SceneAssets& assets) {
  const FrameRenderer renderer(truth, geometry, options, assets);
  std::vector<cv::Mat> frames;
  for (std::size_t j = 0; j < truth.frames.size(); ++j)
    frames.push_back(truth.frames[j].defect == "duplicate" && j > 0
                         ? frames.back().clone()
                         : renderer.Render(static_cast<int>(j)));
  return frames;
}

TrialResult RenderTrial(const TrialSpec& spec, const SpecimenGeometry& geometry,
                        const RenderOptions& options, const SceneAssets& assets,
                        const fs::path& trial_dir, bool overwrite) {
  const auto start = std::chrono::steady_clock::now();
  if (!overwrite && fs::exists(trial_dir))
    throw std::runtime_error("output folder '" + trial_dir.string() +
                             "' exists (use --overwrite to replace it)");
  TrialResult result;
  result.truth = PlanTrial(spec, geometry, options);
  result.path = trial_dir;
  const TrialTruth& truth = result.truth;
  TemporaryFolder folder(trial_dir);
  const FrameRenderer renderer(truth, geometry, options, assets);
  cv::Mat previous;
  char name[32];
  for (std::size_t j = 0; j < truth.frames.size(); ++j) {
    const bool duplicate = truth.frames[j].defect == "duplicate" && j > 0;
    cv::Mat image = duplicate ? previous : renderer.Render(static_cast<int>(j));
    std::snprintf(name, sizeof(name), "%06zu.png", j);
    WritePng(folder.path() / "frames" / name, image, options);
    previous = image;
  }
  io::WriteTextAtomically(folder.path() / "trial.json", TrialJson(truth, options).dump(2) + "\n");
  io::WriteTextAtomically(folder.path() / "truth.json",
                          TruthJson(truth, geometry, options).dump(2) + "\n");
  folder.Commit(overwrite);
  result.render_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace hoof::synth
