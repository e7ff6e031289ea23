#include "synth/renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <numbers>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <utility>

#include <opencv2/imgcodecs.hpp>

#include "core/frames.h"
#include "io/atomic_file.h"
#include "synth/calibration_image.h"
#include "synth/camera_model.h"
#include "synth/frame_renderer.h"
#include "synth/temporary_folder.h"
#include "synth/trial_files.h"
#include "tracking/camera_file.h"

namespace hoof::synth {
namespace fs = std::filesystem;
namespace {

using core::kRadPerDeg;

/// A number in a message: four significant digits (synth does not link hoof::format).
std::string Num4(double v) {
  std::ostringstream os;
  os << std::setprecision(4) << v;
  return os.str();
}

/// Largest motion of the body between two exposure sub-samples (px) before more are drawn.
constexpr double kMaxBlurStepPx = 2.0;

/// Which capture each written frame shows, and its defect.
struct CaptureSchedule {
  std::vector<int> capture;
  std::vector<int> slot;  ///< The capture slot each frame was written in (see FrameTruth).
  std::vector<std::string> defect;
  std::vector<int> dropped;  ///< Captures skipped by a drop.
};

CaptureSchedule ScheduleCaptures(int count, const CameraEffects& cam, std::mt19937_64& rng,
                                 std::uint64_t seed) {
  // Frames that must drop (1) or repeat (2): a seeded partial Fisher-Yates over 1..count-1 on
  // a generator of its own, so the trial's stream does not move.
  std::vector<char> force(count, 0);
  if (cam.drop_frames + cam.duplicate_frames > 0) {
    std::mt19937_64 pick(MixSeed(seed, 0xD509));
    std::vector<int> idx;
    for (int j = 1; j < count; ++j) idx.push_back(j);
    const int n = cam.drop_frames + cam.duplicate_frames;
    for (int i = 0; i < n; ++i) {
      const auto k = i + static_cast<int>(pick() % static_cast<std::uint64_t>(idx.size() - i));
      std::swap(idx[i], idx[k]);
      force[idx[i]] = i < cam.drop_frames ? 1 : 2;
    }
  }
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  CaptureSchedule s{
      std::vector<int>(count), std::vector<int>(count), std::vector<std::string>(count), {}};
  int next = 0;
  for (int j = 0; j < count; ++j) {
    const double drop = unit(rng), duplicate = unit(rng);  // always drawn: stable streams
    if (j > 0 && (drop < cam.drop_frame_probability || force[j] == 1)) {
      s.dropped.push_back(next);
      ++next;
      s.defect[j] = "dropped_before";
    }
    if (j > 0 && s.defect[j].empty() &&
        (duplicate < cam.duplicate_frame_probability || force[j] == 2)) {
      s.capture[j] = s.capture[j - 1];  // the previous image again; this capture is lost
      s.slot[j] = next;
      s.defect[j] = "duplicate";
      ++next;
      continue;
    }
    s.slot[j] = next;
    s.capture[j] = next++;
  }
  return s;
}

/// Mid-exposure offsets of the sub-samples (s), symmetric about 0.
std::vector<double> ExposureOffsets(const CameraEffects& cam, int samples) {
  if (!cam.motion_blur) return {0.0};
  std::vector<double> o(samples);
  for (int k = 0; k < samples; ++k) o[k] = cam.exposure_s * ((k + 0.5) / samples - 0.5);
  return o;
}

/// The next touch after impact `r`: the time since that impact's touch when the round end
/// (centre E, radius R) reaches the surface line again in free flight, and the state then.
/// Throws std::invalid_argument (naming --bounces) when the body does not leave the surface
/// or the specimen would touch with something other than its round end.
std::pair<double, dynamics::BodyState> NextTouch(const dynamics::ImpactResult& r,
                                                 const dynamics::SpecimenParameters& body,
                                                 const SpecimenGeometry& g, double phi,
                                                 int impact) {
  const Eigen::Vector2d g_S = dynamics::GravityInSurfaceFrame(phi, dynamics::kStandardGravity_m_s2);
  const double d = body.d_EC_m, R = body.end_radius_m;
  const dynamics::BodyState& s0 = r.at_separation;
  const double v_n = s0.v_SC.y() - d * std::cos(s0.theta_S_rad) * s0.w_rad_s;
  if (!(v_n > 1e-3))
    throw std::invalid_argument("--bounces: after impact " + std::to_string(impact + 1) +
                                " the body leaves the surface at " + Num4(v_n) +
                                " m/s: it does not bounce again");
  const auto state = [&](double t) {
    return dynamics::PropagateFlight(s0, g_S, t - r.t_separation_s);
  };
  const auto height = [&](double t) {  // of E above R: 0 at touch
    const dynamics::BodyState s = state(t);
    return s.p_SC.y() - d * std::sin(s.theta_S_rad) - R;
  };
  const double h = v_n / -g_S.y() / 200;  // 1/200 of the rise time of E
  double a = r.t_separation_s, b = a;
  for (int i = 1;; ++i) {
    if (i > 2000000)
      throw std::invalid_argument("--bounces: no touch found after impact " +
                                  std::to_string(impact + 1));
    b = r.t_separation_s + i * h;
    if (height(b) <= 0 && i > 1) break;
    a = b;
  }
  for (int i = 0; i < 200 && b - a > 1e-15; ++i) {
    const double m = (a + b) / 2;
    (height(m) > 0 ? a : b) = m;
  }
  const dynamics::BodyState s = state(b);
  if (g.body != Body::kBall) {
    // The round end is a half circle clipped by the bar's sides: the lowest point of the circle
    // is on the body while x_B points within asin(w / 2R) of the surface normal.
    const double tilt = std::remainder(s.theta_S_rad - std::numbers::pi / 2, 2 * std::numbers::pi);
    const double limit = std::asin(std::min(1.0, g.width_m / 2 / R));
    if (std::abs(tilt) > limit)
      throw std::invalid_argument(
          "--bounces: at touch " + std::to_string(impact + 2) + " the specimen is turned " +
          Num4(tilt / kRadPerDeg) +
          " deg from upright, beyond where its round end is what touches (" +
          Num4(limit / kRadPerDeg) + " deg); the model cannot represent it");
  }
  return {b, s};
}

/// The impacts of a clip and the model at `times` (since first touch). One impact is one
/// Simulate call; each later one restarts the simulator from the flight state at its touch, in
/// a surface frame shifted along x_S to that touch's contact point.
struct Bounces {
  std::vector<ImpactTruth> impacts;
  std::vector<dynamics::TrajectorySample> samples;  ///< At `times`, in the first impact's S.
  std::vector<int> impact_of;                       ///< Per sample, its impact's index.
};

Bounces SimulateBounces(const dynamics::ImpactSimulator& sim, const TrialSpec& spec,
                        const SpecimenGeometry& g, const std::vector<double>& times) {
  Bounces out;
  out.samples.resize(times.size());
  out.impact_of.assign(times.size(), 0);
  const double phi = spec.angle_deg * kRadPerDeg;
  dynamics::ImpactConditions cond =
      dynamics::ImpactConditions::Paper(spec.speed_m_s, spec.angle_deg);
  double t0 = 0, x0 = 0;
  for (int k = 0; k < spec.bounces; ++k) {
    std::vector<double> local;
    std::vector<std::size_t> index;
    for (std::size_t i = 0; i < times.size(); ++i)
      if (k == 0 || times[i] >= t0) {
        local.push_back(times[i] - t0);
        index.push_back(i);
      }
    dynamics::ImpactResult r = sim.Simulate(cond, local);
    if (!r.success)
      throw std::runtime_error("trial " + spec.id + ": simulation of impact " +
                               std::to_string(k + 1) + " failed: " + r.message);
    for (std::size_t m = 0; m < index.size(); ++m) {
      dynamics::TrajectorySample s = r.samples[m];
      s.t_s += t0;
      s.body.p_SC.x() += x0;
      s.p_SE.x() += x0;
      out.samples[index[m]] = s;
      out.impact_of[index[m]] = k;
    }
    r.samples.clear();
    out.impacts.push_back({t0, x0, r});
    if (k + 1 == spec.bounces) break;
    const auto [t_touch, state] = NextTouch(r, sim.specimen(), g, phi, k);
    const double d = sim.specimen().d_EC_m;
    x0 += state.p_SC.x() - d * std::cos(state.theta_S_rad);
    t0 += t_touch;
    cond.v_SC_m_s = state.v_SC;
    cond.w_rad_s = state.w_rad_s;
    cond.theta_S_rad = state.theta_S_rad;
  }
  return out;
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
  ViewGeometry view{o.m_per_px, {0.0, 0.0}, g.Simulated().d_EC_m};
  const bool ball = g.body == Body::kBall;
  const double pad = ball ? 4.0 : g.patch_size_m / o.m_per_px + 4;
  double x0 = 1e300, x1 = -1e300, y0 = 1e300;
  const auto add = [&](const Eigen::Vector2d& q) {
    x0 = std::min(x0, q.x());
    x1 = std::max(x1, q.x());
    y0 = std::min(y0, q.y());
  };
  const double r_px = g.ball_diameter_m / 2 / o.m_per_px;
  for (const BodyPose& p : poses) {
    if (ball) {
      const Eigen::Vector2d c = ProjectBodyPoint(p, {0.0, 0.0, 0.0}, view);
      add(c + Eigen::Vector2d(-r_px, -r_px));
      add(c + Eigen::Vector2d(r_px, r_px));
      continue;
    }
    for (const Marker& m : g.markers)
      add(ProjectBodyPoint(p, {m.p_BM_m.x(), m.p_BM_m.y(), g.thickness_m / 2}, view));
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

void WriteFrame(const fs::path& trial_dir, int index, const cv::Mat& image,
                const RenderOptions& options) {
  char name[32];
  std::snprintf(name, sizeof(name), "%06d.png", index);
  WritePng(trial_dir / "frames" / name, image, options);
}

std::string ClipFileName(FrameFormat format) {
  switch (format) {
    case FrameFormat::kMraw:
      return "clip.mraw";
    case FrameFormat::kCine:
      return "clip.cine";
    case FrameFormat::kPng:
      break;
  }
  return "";
}

struct FrameWriter::Impl {
  fs::path trial_dir;
  RenderOptions options;
  int next = 0;
  std::optional<tracking::MrawWriter> mraw;
  std::optional<tracking::CineWriter> cine;
};

FrameWriter::FrameWriter(const fs::path& trial_dir, const TrialTruth& truth,
                         const RenderOptions& options)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.trial_dir = trial_dir;
  m.options = options;
  if (options.frame_format == FrameFormat::kPng) return;
  tracking::CameraFileSpec spec;
  spec.width = options.width_px;
  spec.height = options.height_px;
  spec.frame_count = static_cast<int>(truth.frames.size());
  spec.fps = options.fps;
  // The shutter is open for the exposure; without motion blur the renderer draws one instant,
  // so no shutter time is recorded.
  if (options.camera.motion_blur) spec.shutter_s = options.camera.exposure_s;
  spec.camera = "hoofimpact synth";
  const fs::path clip = trial_dir / ClipFileName(options.frame_format);
  if (options.frame_format == FrameFormat::kMraw) {
    spec.bits = options.bit_depth;  // 8, 12 (packed) or 16
    m.mraw.emplace(clip, spec);
  } else {
    // CINE: 8-bit, or 16-bit storage that records 12 or 16 significant bits.
    spec.bits = options.bit_depth == 8 ? 8 : 16;
    spec.effective_bits = options.bit_depth;
    for (const FrameTruth& f : truth.frames) spec.times_s.push_back(f.stamp_s);
    m.cine.emplace(clip, spec);
  }
}

FrameWriter::~FrameWriter() = default;

void FrameWriter::Write(int index, const cv::Mat& image) {
  Impl& m = *impl_;
  if (index != m.next)
    throw std::logic_error("FrameWriter: frame " + std::to_string(index) + " written when " +
                           std::to_string(m.next) + " was next");
  ++m.next;
  if (m.mraw)
    m.mraw->Write(image);
  else if (m.cine)
    m.cine->Write(image);
  else
    WriteFrame(m.trial_dir, index, image, m.options);
}

void FrameWriter::Finish() {
  Impl& m = *impl_;
  if (m.mraw) m.mraw->Finish();
  if (m.cine) m.cine->Finish();
}

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
                                    MixSeed(seed, 1), options.lighting);
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
  const dynamics::SpecimenParameters body = geometry.Simulated();
  TrialTruth t;
  t.spec = spec;
  std::mt19937_64 rng(spec.seed);
  t.draw = DrawContact(spec, body, rng);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double touch_fraction = unit(rng);
  Eigen::Vector2d jitter{unit(rng) * 6 - 3, unit(rng) * 6 - 3};
  t.surface_u_offset_px = (unit(rng) - 0.5) * 400;
  if (!options.camera.subpixel_jitter) jitter.setZero();
  const dynamics::ImpactSimulator sim(body, t.draw.contact);
  const double phi = spec.angle_deg * kRadPerDeg;

  // Frame counts: the options', or from the flight (the fall since release at rest before the
  // first touch; after the last impact, up to the rebound's apex).
  t.frames_before = options.frames_before;
  t.frames_after = options.frames_after;
  if (spec.bounces > 1 || options.frames_from_flight) {
    const Bounces plan = SimulateBounces(sim, spec, geometry, {});
    const ImpactTruth& last = plan.impacts.back();
    const double g_n = dynamics::kStandardGravity_m_s2 * std::cos(phi);
    const double t_end = last.touch_time_s + last.result.t_separation_s +
                         std::max(last.result.at_separation.v_SC.y(), 0.0) / g_n;
    const double needed_after = std::ceil(t_end * options.fps) + 1;
    const double before =
        std::max(1.0, std::floor(spec.speed_m_s / dynamics::kStandardGravity_m_s2 * options.fps));
    if (options.frames_from_flight) {
      t.frames_before = static_cast<int>(std::min(before, 1e6));
      t.frames_after = static_cast<int>(std::min(needed_after, 1e6));
    } else {
      t.frames_after =
          static_cast<int>(std::min(std::max<double>(t.frames_after, needed_after), 1e6));
    }
    if (t.frames_before + t.frames_after > 200000)
      throw std::invalid_argument("trial " + spec.id + ": the clip would hold " +
                                  std::to_string(t.frames_before + t.frames_after) +
                                  " frames (more than 200000): lower --fps or the speed");
  }
  const int count = t.frames_before + t.frames_after;
  if (options.camera.drop_frames + options.camera.duplicate_frames > count - 1)
    throw std::invalid_argument("--drop-frames + --duplicate-frames must be at most " +
                                std::to_string(count - 1) + " (the frames after the first)");
  const CaptureSchedule schedule = ScheduleCaptures(count, options.camera, rng, spec.seed);
  t.dropped_captures = schedule.dropped;
  t.impact_time_s = (t.frames_before - 1 + touch_fraction) / options.fps;

  // Frame centres since first touch.
  std::vector<double> times;
  for (int j = 0; j < count; ++j)
    times.push_back(schedule.capture[j] / options.fps - t.impact_time_s);
  // Exposure sub-samples: blur_samples, or more where the body would move more than
  // kMaxBlurStepPx between two of them (at low frame rates with long exposures). At the
  // default 8000 fps and scale no speed the options allow gets there, so those renders keep
  // blur_samples.
  const CameraEffects& cam = options.camera;
  t.blur_samples_used = cam.motion_blur ? cam.blur_samples : 1;
  if (cam.motion_blur) {
    const Bounces centres = SimulateBounces(sim, spec, geometry, times);
    const double reach = geometry.body == Body::kBall
                             ? 0.0
                             : std::max(body.d_EC_m + body.end_radius_m,
                                        geometry.length_m - body.end_radius_m - body.d_EC_m) +
                                   geometry.width_m / 2;
    double speed = 0;
    for (const auto& s : centres.samples)
      speed = std::max(speed, s.body.v_SC.norm() + std::abs(s.body.w_rad_s) * reach);
    const double step_px = speed * cam.exposure_s / options.m_per_px;  // over the exposure
    t.blur_samples_used = std::clamp(static_cast<int>(std::ceil(step_px / kMaxBlurStepPx)),
                                     cam.blur_samples, std::max(cam.blur_samples, 4096));
  }
  const std::vector<double> offsets = ExposureOffsets(cam, t.blur_samples_used);
  for (int j = 0; j < count; ++j)
    for (double o : offsets) times.push_back(times[j] + o);
  Bounces b;
  if (spec.bounces == 1) {
    // One impact: one Simulate call with every time, as it always was.
    dynamics::ImpactResult r =
        sim.Simulate(dynamics::ImpactConditions::Paper(spec.speed_m_s, spec.angle_deg), times);
    if (!r.success)
      throw std::runtime_error("trial " + spec.id + ": simulation failed: " + r.message);
    b.samples = std::move(r.samples);
    r.samples.clear();
    b.impact_of.assign(b.samples.size(), 0);
    b.impacts.push_back({0.0, 0.0, std::move(r)});
  } else {
    b = SimulateBounces(sim, spec, geometry, times);
  }
  t.impact = b.impacts.front().result;
  for (ImpactTruth& it : b.impacts) it.touch_time_s += t.impact_time_s;
  t.impacts = b.impacts;

  if (cam.flicker_hz > 0) {
    std::mt19937_64 flicker(MixSeed(spec.seed, 0xF11C));
    t.flicker_phase_rad = unit(flicker) * 2 * std::numbers::pi;
  }
  std::vector<BodyPose> centres;
  for (int j = 0; j < count; ++j)
    centres.push_back(ToPose(b.samples[j], phi, spec.hidden.out_of_plane));
  t.contact_px = FrameContact(centres, geometry, options, jitter);
  const LensModel lens(options.camera, options.width_px, options.height_px);
  const ViewGeometry view{options.m_per_px, t.contact_px, body.d_EC_m};
  t.surface_line_px = SurfaceLine(t.contact_px, phi, options, lens);
  t.first_frame_after_touch = count;
  for (int j = 0; j < count; ++j) {
    const dynamics::TrajectorySample& s = b.samples[j];
    FrameTruth f;
    f.capture_index = schedule.capture[j];
    f.t_s = schedule.capture[j] / options.fps;
    f.slot_index = schedule.slot[j];
    f.stamp_s = schedule.slot[j] / options.fps;
    f.pose = centres[j];
    f.p_WC = core::SurfaceRotation(phi).ToW(s.body.p_SC);
    f.phase = dynamics::ToString(s.phase);
    f.defect = schedule.defect[j];
    f.impact = b.impact_of[j];
    if (geometry.body == Body::kMarkers)
      for (const Marker& m : geometry.markers) {
        const Eigen::Vector2d u =
            ProjectBodyPoint(f.pose, {m.p_BM_m.x(), m.p_BM_m.y(), geometry.thickness_m / 2}, view);
        f.markers_px_undistorted.push_back(u);
        f.markers_px.push_back(lens.Distort(u));
      }
    f.center_px_undistorted = {t.contact_px.x() + f.p_WC.x() / options.m_per_px,
                               t.contact_px.y() - f.p_WC.y() / options.m_per_px};
    f.center_px = lens.Distort(f.center_px_undistorted);
    if (cam.flicker_hz > 0) {
      // The mean of 1 + D sin(2 pi F t + psi) over the exposure [t - T/2, t + T/2].
      const double w = 2 * std::numbers::pi * cam.flicker_hz;
      const double half = cam.motion_blur ? cam.exposure_s / 2 : 0.0;
      const double sinc = half > 0 ? std::sin(w * half) / (w * half) : 1.0;
      f.light_factor = 1 + cam.flicker_depth * sinc * std::sin(w * f.t_s + t.flicker_phase_rad);
    }
    if (f.t_s >= t.impact_time_s && t.first_frame_after_touch == count)
      t.first_frame_after_touch = j;
    std::vector<BodyPose> exposure;
    for (std::size_t k = 0; k < offsets.size(); ++k)
      exposure.push_back(
          ToPose(b.samples[count + j * offsets.size() + k], phi, spec.hidden.out_of_plane));
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
                        const fs::path& trial_dir, bool overwrite, bool in_study) {
  const auto start = std::chrono::steady_clock::now();
  if (!overwrite && fs::exists(trial_dir))
    throw std::runtime_error("output folder '" + trial_dir.string() +
                             "' exists (use --overwrite to replace it)");
  TrialResult result;
  result.truth = PlanTrial(spec, geometry, options);
  result.path = trial_dir;
  const TrialTruth& truth = result.truth;
  TemporaryFolder folder(trial_dir, options.frame_format == FrameFormat::kPng);
  const FrameRenderer renderer(truth, geometry, options, assets);
  FrameWriter writer(folder.path(), truth, options);  // the frame-file seam
  cv::Mat previous;
  for (std::size_t j = 0; j < truth.frames.size(); ++j) {
    const bool duplicate = truth.frames[j].defect == "duplicate" && j > 0;
    cv::Mat image = duplicate ? previous : renderer.Render(static_cast<int>(j));
    writer.Write(static_cast<int>(j), image);
    previous = image;
  }
  writer.Finish();
  if (options.calibration != CalibrationTarget::kNone) {
    const CalibrationPlan plan = PlanCalibration(options, spec.seed);
    const fs::path file = folder.path() / plan.file;
    if (!cv::imwrite(file.string(), RenderCalibrationImage(plan, options, spec.seed)))
      throw std::runtime_error("cannot write the calibration image '" + file.string() + "'");
  }
  io::WriteTextAtomically(folder.path() / "trial.json",
                          TrialJson(truth, options, geometry, in_study).dump(2) + "\n");
  io::WriteTextAtomically(folder.path() / "truth.json",
                          TruthJson(truth, geometry, options).dump(2) + "\n");
  folder.Commit(overwrite);
  result.render_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace hoof::synth
