// hoofimpact synth footage: render everyday footage (a ball bouncing in a room, filmed by a phone
// or a slow-motion camera) with its truth (docs/synthetic-trials.md, "Everyday footage").
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/json_output.h"
#include "format/number_format.h"
#include "synth/footage_renderer.h"

namespace hoof::cli {
namespace {

namespace fs = std::filesystem;

struct FootageArgs {
  std::string output;
  bool overwrite = false, json = false;
  int jobs = 0;
  synth::FootageSpec spec;  // the command line's values; defaults as FootageSpec's
  std::string scenario = "bounce", timing = "phone", delivery = "each-capture";
  std::string color = "red", texture = "plain", inertia = "solid", surface = "floor";
  std::string codec = "h264";
  std::vector<double> camera_m{0.05, 0.30, 1.30}, light_m{0.3, 2.2, 0.5};
  std::vector<double> velocity{0, 0, 0}, spin{0, 0, 0};
  bool no_clutter = false, no_hand = false, no_blur = false, no_noise = false;
};

/// The library's field names and the options that set them (ValidateOptions).
const std::map<std::string, std::string> kFields = {
    {"ball.radius_m", "--ball-radius-m"},
    {"ball.specular", "--specular"},
    {"ball.shininess", "--shininess"},
    {"launch.x_m", "--release-x-m"},
    {"launch.z_m", "--release-z-m"},
    {"launch.drop_height_m", "--drop-height-m"},
    {"launch.v_W_m_s", "--velocity-m-s"},
    {"launch.w_W_rad_s", "--spin-rad-s"},
    {"launch.release_time_s", "--release-time-s"},
    {"launch.throw_duration_s", "--throw-duration-s"},
    {"bounce.e_mean", "--e"},
    {"bounce.e_sd", "--e-sd"},
    {"bounce.mu", "--mu"},
    {"bounce.g_m_s2", "--gravity-m-s2"},
    {"bounce.min_rebound_height_m", "--min-rebound-height-m"},
    {"camera.width_px", "--width-px"},
    {"camera.height_px", "--height-px"},
    {"camera.focal_px", "--focal-px"},
    {"camera.horizontal_fov_deg", "--fov-deg"},
    {"camera.p_W_m", "--camera-m"},
    {"camera.pan_deg", "--pan-deg"},
    {"camera.tilt_deg", "--tilt-deg"},
    {"camera.roll_deg", "--roll-deg"},
    {"camera.rotation_tag_deg", "--rotation-tag-deg"},
    {"room.wall_z_m", "--wall-z-m"},
    {"room.table_front_z_m", "--release-z-m"},
    {"room.light_p_W_m", "--light-m"},
    {"room.light_radius_m", "--light-radius-m"},
    {"room.ambient", "--ambient"},
    {"room.brightness", "--brightness"},
    {"hand.skin_tone", "--skin-tone"},
    {"hand.leave_speed_m_s", "--hand-speed-m-s"},
    {"timing.capture_fps", "--fps"},
    {"timing.container_fps", "--container-fps"},
    {"timing.duration_s", "--duration-s"},
    {"timing.exposure_s", "--exposure-s"},
    {"timing.capture_jitter_fraction", "--capture-jitter-fraction"},
    {"timing.repeat_frames", "--repeat-frames"},
    {"timing.drop_frames", "--drop-frames"},
    {"sensor.max_blur_samples", "--max-blur-samples"},
    {"sensor.read_noise", "--read-noise"},
    {"sensor.shot_noise", "--shot-noise"},
    {"sensor.vignetting", "--vignetting"},
    {"png_compression", "--png-compression"},
};

template <class Parse>
auto Named(const char* option, const std::string& value, Parse parse) {
  try {
    return parse(value);
  } catch (const std::invalid_argument& e) {
    throw CLI::ValidationError(option, e.what());
  }
}

Eigen::Vector3d Vector3(const std::vector<double>& v) { return {v[0], v[1], v[2]}; }

/// The spec: the scenario's and the timing preset's defaults, under every option given.
synth::FootageSpec BuildSpec(FootageArgs& a, const CLI::App* cmd) {
  const auto given = [cmd](const char* option) { return cmd->count(option) > 0; };
  synth::FootageSpec spec = a.spec;
  spec.scenario = Named("--scenario", a.scenario, synth::ParseFootageScenario);
  const synth::FootageSpec d = synth::DefaultFootageSpec(spec.scenario);
  const synth::FootageTimingOptions preset =
      synth::TimingOf(Named("--timing", a.timing, synth::ParseTimingPreset));
  spec.ball.color = Named("--ball-color", a.color, synth::ParseBallColor);
  spec.ball.texture = Named("--ball-texture", a.texture, synth::ParseBallTexture);
  spec.ball.inertia = Named("--inertia", a.inertia, synth::ParseBallInertia);
  spec.room.surface = Named("--surface", a.surface, synth::ParseContactSurface);
  spec.codec = Named("--codec", a.codec, synth::ParseFootageCodec);
  spec.timing.delivery = given("--delivery")
                             ? Named("--delivery", a.delivery, synth::ParseFrameDelivery)
                             : preset.delivery;
  if (!given("--fps")) spec.timing.capture_fps = preset.capture_fps;
  if (!given("--container-fps")) spec.timing.container_fps = preset.container_fps;
  spec.camera.p_W_m = Vector3(a.camera_m);
  spec.room.light_p_W_m = Vector3(a.light_m);
  spec.launch.v_W_m_s = given("--velocity-m-s") ? Vector3(a.velocity) : d.launch.v_W_m_s;
  spec.launch.w_W_rad_s = given("--spin-rad-s") ? Vector3(a.spin) : d.launch.w_W_rad_s;
  if (!given("--release-x-m")) spec.launch.x_m = d.launch.x_m;
  if (!given("--drop-height-m")) spec.launch.drop_height_m = d.launch.drop_height_m;
  spec.room.clutter = !a.no_clutter;
  spec.hand.enabled = !a.no_hand && d.hand.enabled;
  spec.sensor.motion_blur = !a.no_blur;
  spec.sensor.noise = !a.no_noise;
  return spec;
}

/// Options of `synth` itself (for its trials) given with `footage` are an error.
void RefuseTrialOptions(const CLI::App* synth_cmd) {
  for (const CLI::Option* o : synth_cmd->get_options())
    if (o->count() > 0 && o->get_name() != "--help")
      throw CLI::ValidationError(o->get_name(false, false),
                                 "is an option of synth's trials; footage has its own (synth "
                                 "footage --help)");
}

void CheckOutput(const std::string& output) {
  const fs::path out(output);
  const fs::path parent = out.has_parent_path() ? out.parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(parent, ec);
  if (ec || !fs::is_directory(parent) || ::access(parent.c_str(), W_OK) != 0)
    throw CLI::ValidationError(
        "--output", "'" + output + "': cannot create or write folder '" + parent.string() + "'");
}

nlohmann::json Summary(const synth::FootageResult& r) {
  int in_view = 0;
  for (const auto& b : r.truth.bounces) in_view += b.in_view ? 1 : 0;
  return {{"output", r.path.string()},
          {"footage", true},
          {"clip", r.clip.string()},
          {"truth", (r.path / "truth.json").string()},
          {"frames", r.truth.frames.size()},
          {"width_px", r.truth.width_px},
          {"height_px", r.truth.height_px},
          {"capture_fps", r.truth.schedule.capture_fps},
          {"container_fps", r.truth.schedule.container_fps},
          {"rotation_tag_deg", r.truth.spec.camera.rotation_tag_deg},
          {"bounces", r.truth.bounces.size()},
          {"bounces_in_view", in_view},
          {"seconds", r.render_seconds}};
}

void Run(FootageArgs& a, RunState& state, const CLI::App* cmd, const CLI::App* synth_cmd) {
  RefuseTrialOptions(synth_cmd);
  while (a.output.size() > 1 && a.output.back() == '/') a.output.pop_back();
  synth::FootageSpec spec = BuildSpec(a, cmd);
  // Out-of-range values and clips that cannot be drawn: command-line errors naming the option.
  ValidateOptions(
      cmd, [&spec] { (void)synth::PlanFootage(spec); }, kFields);
  CheckOutput(a.output);
  const synth::FootageResult r = synth::RenderFootage(spec, a.output, a.overwrite, a.jobs);
  state.exit_code = kExitOk;
  if (a.json) {
    PrintEnvelope("synth", state.exit_code, Summary(r));
    return;
  }
  int in_view = 0;
  for (const auto& b : r.truth.bounces) in_view += b.in_view ? 1 : 0;
  std::cout << "Wrote " << r.clip.string() << " (" << r.truth.frames.size() << " frames, "
            << r.truth.width_px << " x " << r.truth.height_px << " delivered, "
            << format::Number(r.truth.schedule.capture_fps) << " captures/s in a "
            << format::Number(r.truth.schedule.container_fps) << " fps file; " << in_view
            << " bounce(s) in view) and truth.json in " << format::Seconds(r.render_seconds)
            << "\n";
  if (spec.camera.rotation_tag_deg != 0)
    std::cout << "The file must carry rotation tag " << spec.camera.rotation_tag_deg
              << " (truth.json is for the frames turned upright): tools/tag-rotation " << a.output
              << "\n";
}

void AddPhysicsOptions(CLI::App* c, FootageArgs& a) {
  synth::FootageSpec& s = a.spec;
  c->add_option("--ball-radius-m", s.ball.radius_m, "Ball radius (m)")->capture_default_str();
  c->add_option("--ball-color", a.color, "red, yellow, orange, white, green or blue")
      ->capture_default_str();
  c->add_option("--ball-texture", a.texture, "plain, stripes or cross (shows the spin)")
      ->capture_default_str();
  c->add_option("--inertia", a.inertia, "solid (I = 2/5 m r^2) or hollow (2/3 m r^2)")
      ->capture_default_str();
  c->add_option("--specular", s.ball.specular, "Strength of the highlight, 0 = matt")
      ->capture_default_str();
  c->add_option("--shininess", s.ball.shininess, "Blinn-Phong exponent of the highlight")
      ->capture_default_str();
  c->add_option("--drop-height-m", s.launch.drop_height_m,
                "Ball's lowest point above the surface at release (m; never-lands: 0.4)")
      ->capture_default_str();
  c->add_option("--release-x-m", s.launch.x_m,
                "Sideways position of the release (m; never-lands: -0.3)")
      ->capture_default_str();
  c->add_option("--release-z-m", s.launch.z_m, "Depth of the release, + toward the camera (m)")
      ->capture_default_str();
  c->add_option("--velocity-m-s", a.velocity,
                "Velocity at release x,y,z (m/s; a throw; default 0,0,0; never-lands: 3,1.5,0)")
      ->delimiter(',')
      ->expected(3);
  c->add_option("--spin-rad-s", a.spin,
                "Spin at release x,y,z (rad/s; default 0,0,0; never-lands: 0,0,-20)")
      ->delimiter(',')
      ->expected(3);
  c->add_option("--release-time-s", s.launch.release_time_s,
                "When the hand lets go (s since capture 0; hand-only: when it pauses)")
      ->capture_default_str();
  c->add_option("--throw-duration-s", s.launch.throw_duration_s,
                "A throw: the hand carries the ball this long before release (s)")
      ->capture_default_str();
  c->add_option("--e", s.bounce.e_mean, "Mean normal restitution per bounce")
      ->capture_default_str();
  c->add_option("--e-sd", s.bounce.e_sd, "S.d. of e drawn per bounce (0 = fixed)")
      ->capture_default_str();
  c->add_option("--mu", s.bounce.mu, "Coulomb friction at the bounces")->capture_default_str();
  c->add_option("--gravity-m-s2", s.bounce.g_m_s2, "Gravity (m/s^2)")->capture_default_str();
  c->add_option("--min-rebound-height-m", s.bounce.min_rebound_height_m,
                "Bouncing ends when a rebound would rise less (m); the ball then rolls")
      ->capture_default_str();
}

void AddSceneOptions(CLI::App* c, FootageArgs& a) {
  synth::FootageSpec& s = a.spec;
  c->add_option("--width-px", s.camera.width_px, "Delivered (upright) frame width (px)")
      ->capture_default_str();
  c->add_option("--height-px", s.camera.height_px, "Delivered (upright) frame height (px)")
      ->capture_default_str();
  c->add_option("--focal-px", s.camera.focal_px, "Focal length (px); 0 = from --fov-deg")
      ->capture_default_str();
  c->add_option("--fov-deg", s.camera.horizontal_fov_deg, "Horizontal field of view (deg)")
      ->capture_default_str();
  c->add_option("--camera-m", a.camera_m,
                "Camera position x,y,z in W (m; y up from the surface, z toward the camera; "
                "default 0.05,0.3,1.3)")
      ->delimiter(',')
      ->expected(3);
  c->add_option("--pan-deg", s.camera.pan_deg, "Camera pan, > 0 toward +x (deg)")
      ->capture_default_str();
  c->add_option("--tilt-deg", s.camera.tilt_deg, "Camera tilt, > 0 looks down (deg)")
      ->capture_default_str();
  c->add_option("--roll-deg", s.camera.roll_deg, "Camera roll, > 0 turns the scene clockwise (deg)")
      ->capture_default_str();
  c->add_option("--rotation-tag-deg", s.camera.rotation_tag_deg,
                "0, 90, 180 or 270: store the frames turned as a phone does; the file must then "
                "carry this tag (tools/tag-rotation)")
      ->capture_default_str();
  c->add_option("--surface", a.surface, "floor, or table (its front edge nearer the camera)")
      ->capture_default_str();
  c->add_flag("--no-clutter", a.no_clutter,
              "A plain wall over a plain floor (no shelves, objects, ruler)");
  c->add_option("--wall-z-m", s.room.wall_z_m, "The back wall's plane (m, behind the ball)")
      ->capture_default_str();
  c->add_option("--light-m", a.light_m, "Ceiling light position x,y,z (m; default 0.3,2.2,0.5)")
      ->delimiter(',')
      ->expected(3);
  c->add_option("--light-radius-m", s.room.light_radius_m,
                "Light radius: the shadow's softness (m)")
      ->capture_default_str();
  c->add_option("--ambient", s.room.ambient, "Share of ambient light, [0, 1]")
      ->capture_default_str();
  c->add_option("--brightness", s.room.brightness, "Exposure factor on every colour")
      ->capture_default_str();
  c->add_flag("--no-hand", a.no_hand, "No hand holding and releasing the ball");
  c->add_option("--skin-tone", s.hand.skin_tone, "0 light to 1 dark")->capture_default_str();
  c->add_option("--hand-speed-m-s", s.hand.leave_speed_m_s, "How fast the hand withdraws (m/s)")
      ->capture_default_str();
}

void AddCameraOptions(CLI::App* c, FootageArgs& a) {
  synth::FootageSpec& s = a.spec;
  c->add_option("--timing", a.timing,
                "phone (30/s in 30 fps), slow-motion (240/s in 30 fps) or screen-recording "
                "(about 30/s sampled by a 60 fps file): the defaults of the four below")
      ->capture_default_str();
  c->add_option("--fps", s.timing.capture_fps, "Captures per second (default from --timing)");
  c->add_option("--container-fps", s.timing.container_fps,
                "The file's frame rate (default from --timing; 0 = --fps)");
  c->add_option("--delivery", a.delivery,
                "each-capture (one frame per capture) or latest-capture (a screen recording)");
  c->add_option("--capture-jitter-fraction", s.timing.capture_jitter_fraction,
                "latest-capture: s.d. of capture times, in capture periods")
      ->capture_default_str();
  c->add_option("--duration-s", s.timing.duration_s, "Scene time the clip covers (s)")
      ->capture_default_str();
  c->add_option("--exposure-s", s.timing.exposure_s, "Exposure (s); 0 = half the capture period")
      ->capture_default_str();
  c->add_option("--repeat-frames", s.timing.repeat_frames,
                "Frames that repeat the one before, at seeded places")
      ->capture_default_str()
      ->check(kNotNegative);
  c->add_option("--drop-frames", s.timing.drop_frames, "Captures left out, at seeded places")
      ->capture_default_str()
      ->check(kNotNegative);
  c->add_flag("--no-motion-blur", a.no_blur, "Point-in-time exposure");
  c->add_option("--max-blur-samples", s.sensor.max_blur_samples,
                "Most sub-frame samples per exposure")
      ->capture_default_str();
  c->add_flag("--no-noise", a.no_noise, "No read or shot noise");
  c->add_option("--read-noise", s.sensor.read_noise, "Read noise s.d. (8-bit levels)")
      ->capture_default_str();
  c->add_option("--shot-noise", s.sensor.shot_noise, "Shot-noise variance per level")
      ->capture_default_str();
  c->add_option("--vignetting", s.sensor.vignetting, "Brightness lost in the corners")
      ->capture_default_str();
  c->add_option("--codec", a.codec, "h264 (clip.mp4) or png (lossless frames/%06d.png, upright)")
      ->capture_default_str();
  c->add_option("--png-compression", s.png_compression, "PNG zlib level 0-9")
      ->capture_default_str();
}

}  // namespace

CLI::App* RegisterSynthFootage(CLI::App* synth_cmd, RunState& state) {
  auto args = std::make_shared<FootageArgs>();
  FootageArgs& a = *args;
  CLI::App* c = synth_cmd->add_subcommand(
      "footage",
      "Render everyday footage with known truth: a coloured ball bouncing in a room, filmed by a "
      "phone or a slow-motion camera (DIR/clip.mp4 or DIR/frames, and DIR/truth.json)");
  c->add_option("-o,--output", a.output, "Output folder (clip and truth.json; no trial.json)")
      ->required();
  c->add_flag("--overwrite", a.overwrite, "Replace an existing output folder");
  c->add_option("--seed", a.spec.seed,
                "Seed of every draw (e per bounce, room, noise, frame faults)")
      ->check(kNotNegative)
      ->capture_default_str();
  c->add_option("--scenario", a.scenario,
                "bounce, never-lands (thrown out of view before it lands), still (nothing "
                "moves) or hand-only (no ball)")
      ->capture_default_str();
  AddPhysicsOptions(c, a);
  AddSceneOptions(c, a);
  AddCameraOptions(c, a);
  c->add_option("--jobs", a.jobs, "Worker threads drawing frames (0 = all cores)")
      ->check(InRange(0, 4096))
      ->capture_default_str();
  AddJsonFlag(c, a.json);
  c->callback([args, &state, c, synth_cmd] { Run(*args, state, c, synth_cmd); });
  return c;
}

}  // namespace hoof::cli
