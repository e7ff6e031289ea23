#include "synth/footage_options.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <vector>

namespace hoof::synth {
namespace {

[[noreturn]] void Throw(std::string_view field, const std::string& value, std::string_view rule) {
  std::ostringstream os;
  os << "FootageSpec." << field << " = " << value << ": " << rule;
  throw std::invalid_argument(os.str());
}

std::string Text(double value) {
  std::ostringstream os;
  os << value;
  return os.str();
}

void Range(std::string_view field, double value, double lo, double hi) {
  if (!std::isfinite(value) || value < lo || value > hi)
    Throw(field, Text(value), "must be in [" + Text(lo) + ", " + Text(hi) + "]");
}

void Range3(std::string_view field, const Eigen::Vector3d& v, double lo, double hi) {
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(v[i]) || v[i] < lo || v[i] > hi)
      Throw(field, Text(v[i]),
            "must have each component in [" + Text(lo) + ", " + Text(hi) + "] (component " +
                std::to_string(i) + ")");
}

/// The name of `value` among `names` (in enum order).
template <class E>
const char* NameOf(E value, const std::vector<const char*>& names) {
  const auto i = static_cast<std::size_t>(value);
  return i < names.size() ? names[i] : names.front();
}

/// The enum whose name is `name`; std::invalid_argument listing the names otherwise.
template <class E>
E ParseName(const std::string& name, const std::vector<const char*>& names, const char* what) {
  std::string list;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (name == names[i]) return static_cast<E>(i);
    list += (i == 0 ? "" : (i + 1 == names.size() ? " or " : ", ")) + std::string(names[i]);
  }
  throw std::invalid_argument(std::string(what) + " '" + name + "' must be " + list);
}

const std::vector<const char*> kScenarios = {"bounce", "never-lands", "still", "hand-only"};
const std::vector<const char*> kInertias = {"solid", "hollow"};
const std::vector<const char*> kColors = {"red", "yellow", "orange", "white", "green", "blue"};
const std::vector<const char*> kTextures = {"plain", "stripes", "cross"};
const std::vector<const char*> kSurfaces = {"floor", "table"};
const std::vector<const char*> kDeliveries = {"each-capture", "latest-capture"};
const std::vector<const char*> kCodecs = {"h264", "png"};
const std::vector<const char*> kPresets = {"phone", "slow-motion", "screen-recording"};

}  // namespace

const char* ToString(FootageScenario s) { return NameOf(s, kScenarios); }
FootageScenario ParseFootageScenario(const std::string& n) {
  return ParseName<FootageScenario>(n, kScenarios, "scenario");
}
const char* ToString(BallInertia i) { return NameOf(i, kInertias); }
BallInertia ParseBallInertia(const std::string& n) {
  return ParseName<BallInertia>(n, kInertias, "inertia");
}
double InertiaFactor(BallInertia inertia) {
  return inertia == BallInertia::kHollow ? 2.0 / 3.0 : 2.0 / 5.0;
}
const char* ToString(BallColor c) { return NameOf(c, kColors); }
BallColor ParseBallColor(const std::string& n) {
  return ParseName<BallColor>(n, kColors, "ball colour");
}
const char* ToString(BallTexture t) { return NameOf(t, kTextures); }
BallTexture ParseBallTexture(const std::string& n) {
  return ParseName<BallTexture>(n, kTextures, "ball texture");
}
const char* ToString(ContactSurface s) { return NameOf(s, kSurfaces); }
ContactSurface ParseContactSurface(const std::string& n) {
  return ParseName<ContactSurface>(n, kSurfaces, "surface");
}
const char* ToString(FrameDelivery d) { return NameOf(d, kDeliveries); }
FrameDelivery ParseFrameDelivery(const std::string& n) {
  return ParseName<FrameDelivery>(n, kDeliveries, "delivery");
}
const char* ToString(FootageCodec c) { return NameOf(c, kCodecs); }
FootageCodec ParseFootageCodec(const std::string& n) {
  return ParseName<FootageCodec>(n, kCodecs, "codec");
}
const char* ToString(TimingPreset p) { return NameOf(p, kPresets); }
TimingPreset ParseTimingPreset(const std::string& n) {
  return ParseName<TimingPreset>(n, kPresets, "timing");
}

Eigen::Vector3d BallAlbedoRgb(BallColor color) {
  switch (color) {
    case BallColor::kRed:
      return {0.62, 0.03, 0.05};
    case BallColor::kYellow:
      return {0.75, 0.58, 0.04};
    case BallColor::kOrange:
      return {0.80, 0.22, 0.02};
    case BallColor::kWhite:
      return {0.80, 0.80, 0.78};
    case BallColor::kGreen:
      return {0.06, 0.42, 0.08};
    case BallColor::kBlue:
      return {0.03, 0.10, 0.55};
  }
  return {0.62, 0.03, 0.05};
}

void BallOptions::Validate() const {
  Range("ball.radius_m", radius_m, 0.005, 0.2);
  Range("ball.specular", specular, 0, 2);
  Range("ball.shininess", shininess, 1, 2000);
}

void LaunchOptions::Validate() const {
  Range("launch.x_m", x_m, -3, 3);
  Range("launch.z_m", z_m, -3, 3);
  Range("launch.drop_height_m", drop_height_m, 0, 3);
  Range3("launch.v_W_m_s", v_W_m_s, -20, 20);
  Range3("launch.w_W_rad_s", w_W_rad_s, -500, 500);
  Range("launch.release_time_s", release_time_s, 0, 60);
  Range("launch.throw_duration_s", throw_duration_s, 0, 2);
}

void BounceOptions::Validate() const {
  Range("bounce.e_mean", e_mean, 0.05, 0.98);
  Range("bounce.e_sd", e_sd, 0, 0.2);
  Range("bounce.mu", mu, 0, 2);
  Range("bounce.g_m_s2", g_m_s2, 0.1, 100);
  Range("bounce.min_rebound_height_m", min_rebound_height_m, 1e-5, 1);
}

void FootageCameraOptions::Validate() const {
  Range("camera.width_px", width_px, 16, 4096);
  Range("camera.height_px", height_px, 16, 4096);
  Range("camera.focal_px", focal_px, 0, 1e5);
  if (focal_px == 0) Range("camera.horizontal_fov_deg", horizontal_fov_deg, 5, 150);
  if (!std::isnan(cx_px)) Range("camera.cx_px", cx_px, -width_px, 2.0 * width_px);
  if (!std::isnan(cy_px)) Range("camera.cy_px", cy_px, -height_px, 2.0 * height_px);
  Range3("camera.p_W_m", p_W_m, -20, 20);
  Range("camera.pan_deg", pan_deg, -60, 60);
  Range("camera.tilt_deg", tilt_deg, -60, 80);
  Range("camera.roll_deg", roll_deg, -45, 45);
  if (rotation_tag_deg != 0 && rotation_tag_deg != 90 && rotation_tag_deg != 180 &&
      rotation_tag_deg != 270)
    Throw("camera.rotation_tag_deg", std::to_string(rotation_tag_deg), "must be 0, 90, 180 or 270");
}

void RoomOptions::Validate() const {
  Range("room.wall_z_m", wall_z_m, -20, -0.05);
  Range("room.side_wall_x_m", side_wall_x_m, -20, -0.1);
  Range("room.table_height_m", table_height_m, 0.2, 2);
  Range("room.table_front_z_m", table_front_z_m, wall_z_m + 0.05, 5);
  Range("room.table_half_width_m", table_half_width_m, 0.1, 10);
  Range3("room.light_p_W_m", light_p_W_m, -20, 20);
  if (light_p_W_m.y() <= 0.05)
    Throw("room.light_p_W_m", Text(light_p_W_m.y()), "must be above the surface (height > 0.05)");
  Range("room.light_radius_m", light_radius_m, 0, 2);
  Range("room.ambient", ambient, 0, 1);
  Range("room.brightness", brightness, 0.05, 4);
}

void HandOptions::Validate() const {
  Range("hand.skin_tone", skin_tone, 0, 1);
  Range("hand.leave_speed_m_s", leave_speed_m_s, 0.05, 20);
  if (!leave_direction.allFinite() || leave_direction.norm() < 1e-6)
    Throw("hand.leave_direction", Text(leave_direction.norm()), "must be a non-zero direction");
}

void FootageTimingOptions::Validate() const {
  Range("timing.capture_fps", capture_fps, 1, 2000);
  if (container_fps != 0) Range("timing.container_fps", container_fps, 1, 2000);
  Range("timing.duration_s", duration_s, 1e-3, 120);
  Range("timing.exposure_s", exposure_s, 0, 1.0 / capture_fps);
  Range("timing.capture_jitter_fraction", capture_jitter_fraction, 0, 0.3);
  const double frames = duration_s * std::max(capture_fps, ContainerFps(*this));
  if (frames > 100000)
    Throw("timing.duration_s", Text(duration_s), "must make at most 100000 frames");
  Range("timing.repeat_frames", repeat_frames, 0, std::max(0.0, frames / 4));
  Range("timing.drop_frames", drop_frames, 0, std::max(0.0, frames / 4));
  if (drop_frames > 0 && delivery != FrameDelivery::kEachCapture)
    Throw("timing.drop_frames", std::to_string(drop_frames),
          "must be 0 with latest-capture delivery");
}

void SensorOptions::Validate() const {
  Range("sensor.max_blur_samples", max_blur_samples, 1, 1024);
  Range("sensor.read_noise", read_noise, 0, 50);
  Range("sensor.shot_noise", shot_noise, 0, 5);
  Range("sensor.vignetting", vignetting, 0, 0.9);
}

void FootageSpec::Validate() const {
  ball.Validate();
  launch.Validate();
  bounce.Validate();
  camera.Validate();
  room.Validate();
  hand.Validate();
  timing.Validate();
  sensor.Validate();
  Range("png_compression", png_compression, 0, 9);
  if (codec == FootageCodec::kH264 && camera.width_px % 2 != 0)
    Throw("camera.width_px", std::to_string(camera.width_px),
          "must be even for the h264 codec (yuv420p halves the colour resolution)");
  if (codec == FootageCodec::kH264 && camera.height_px % 2 != 0)
    Throw("camera.height_px", std::to_string(camera.height_px),
          "must be even for the h264 codec (yuv420p halves the colour resolution)");
  if (camera.rotation_tag_deg != 0 && codec != FootageCodec::kH264)
    Throw("camera.rotation_tag_deg", std::to_string(camera.rotation_tag_deg),
          "must be 0 with the png codec (PNG frames are stored upright)");
  if (launch.release_time_s >= timing.duration_s && scenario != FootageScenario::kStill &&
      scenario != FootageScenario::kHandOnly)
    Throw("launch.release_time_s", Text(launch.release_time_s),
          "must be before the clip ends at " + Text(timing.duration_s) + " s");
  if (room.surface == ContactSurface::kTable && launch.z_m >= room.table_front_z_m)
    Throw("launch.z_m", Text(launch.z_m), "must be behind the table's front edge");
  if (launch.z_m - ball.radius_m <= room.wall_z_m)
    Throw("launch.z_m", Text(launch.z_m), "must keep the ball in front of the back wall");
  if (camera.p_W_m.z() <= launch.z_m + ball.radius_m)
    Throw("camera.p_W_m", Text(camera.p_W_m.z()), "must be in front of the ball (larger z)");
}

FootageSpec DefaultFootageSpec(FootageScenario scenario) {
  FootageSpec spec;
  spec.scenario = scenario;
  if (scenario == FootageScenario::kNeverLands) {
    spec.launch.x_m = -0.3;
    spec.launch.drop_height_m = 0.4;
    spec.launch.v_W_m_s = {3.0, 1.5, 0.0};
    spec.launch.w_W_rad_s = {0.0, 0.0, -20.0};
  } else if (scenario == FootageScenario::kStill) {
    spec.hand.enabled = false;
    spec.launch.drop_height_m = 0;
  }
  return spec;
}

FootageTimingOptions TimingOf(TimingPreset preset) {
  FootageTimingOptions t;
  if (preset == TimingPreset::kSlowMotion) {
    t.capture_fps = 240;
    t.container_fps = 30;
  } else if (preset == TimingPreset::kScreenRecording) {
    t.capture_fps = 30;
    t.container_fps = 60;
    t.delivery = FrameDelivery::kLatestCapture;
  }
  return t;
}

double ContainerFps(const FootageTimingOptions& timing) {
  return timing.container_fps > 0 ? timing.container_fps : timing.capture_fps;
}

double ExposureSeconds(const FootageTimingOptions& timing) {
  return timing.exposure_s > 0 ? timing.exposure_s : 0.5 / timing.capture_fps;
}

}  // namespace hoof::synth
