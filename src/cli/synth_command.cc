// hoofimpact synth: render synthetic 8000 fps trials (or a whole study) with ground truth.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <unistd.h>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/json_output.h"
#include "format/number_format.h"
#include "synth/calibration_image.h"
#include "synth/contact_sheet.h"
#include "synth/renderer.h"
#include "synth/study.h"
#include "synth/study_config.h"

namespace hoof::cli {
namespace {

namespace fs = std::filesystem;
using synth::CameraEffects;

struct SynthArgs {
  std::string output;
  bool overwrite = false;
  std::string surface = "steel";
  double angle_deg = 0.0;
  double speed_m_s = 3.0;
  std::uint64_t seed = 1;  // the trial's; a study keeps StudyDesign::seed unless --seed is given
  std::string id;
  std::optional<double> e, mu;
  bool no_scatter = false;
  double scatter_scale = 1.0;
  synth::RenderOptions render;
  synth::SpecimenGeometry geometry;
  std::string markers;
  std::vector<double> distortion;
  bool clean = false, no_noise = false, no_blur = false, no_distortion = false;
  bool no_defocus = false, no_vignetting = false, no_gradient = false, no_jitter = false;
  synth::HiddenEffects hidden;
  bool study = false;
  std::string study_config;
  synth::StudyDesign design;
  // Study options as given on the command line; they override --study-config.
  std::string name;
  std::vector<std::string> surfaces;
  std::vector<double> angles_deg, speeds_m_s;
  int trials_per_cell = 3;
  double out_of_plane_random_deg = 0.0;
  int threads = 0;
  bool json = false;
  std::string contact_sheet;
  std::string body = "markers", lighting = "front", frame_format = "png";
  std::string calibration = "none";
  int bounces = 1;
};

[[noreturn]] void Bad(const std::string& option, const std::string& what) {
  throw std::invalid_argument(option + " " + what);
}

/// Parses "M1=0.006,0;M2=0.024,0" into markers.
std::vector<synth::Marker> ParseMarkers(const std::string& text) {
  std::vector<synth::Marker> markers;
  std::stringstream all(text);
  std::string item;
  while (std::getline(all, item, ';')) {
    const auto eq = item.find('=');
    const auto comma = item.find(',', eq == std::string::npos ? 0 : eq);
    if (eq == std::string::npos || comma == std::string::npos)
      Bad("--markers-b-m", "'" + item + "': expected NAME=x,y (metres), separated by ';'");
    try {
      markers.push_back(
          {item.substr(0, eq),
           {std::stod(item.substr(eq + 1, comma - eq - 1)), std::stod(item.substr(comma + 1))}});
    } catch (const std::logic_error&) {
      Bad("--markers-b-m", "'" + item + "': x and y must be numbers");
    }
  }
  return markers;
}

/// Reads --study-config (synth::ReadStudyConfig) over the design: its design, hidden effects and
/// markers. A bad file is bad input (exit 1) naming the file.
void ApplyStudyConfig(const std::string& path, SynthArgs& a, CLI::App* cmd) {
  synth::StudyConfig c;
  try {
    c = synth::ReadStudyConfig(path, a.design);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("--study-config ") + e.what());
  }
  a.design = std::move(c.design);
  // An option given on the command line wins over the file's key.
  const auto given = [cmd](const char* option) { return cmd->count(option) > 0; };
  if (given("--markers-b-m")) c.markers_B_m.reset();
  if (given("--body")) c.body.reset();
  if (given("--ball-diameter-m")) c.ball_diameter_m.reset();
  if (given("--ball-mass-kg")) c.ball_mass_kg.reset();
  if (given("--flicker-hz")) c.flicker_hz.reset();
  if (given("--flicker-depth")) c.flicker_depth.reset();
  if (given("--drop-frames")) c.drop_frames.reset();
  if (given("--duplicate-frames")) c.duplicate_frames.reset();
  synth::ApplyStudyConfig(c, a.geometry);
  synth::ApplyStudyConfig(c, a.render.camera);
  if (c.body) a.body = synth::ToString(*c.body);
  if (c.lighting && !given("--lighting")) a.lighting = synth::ToString(*c.lighting);
  if (c.frame_format && !given("--frame-format")) a.frame_format = synth::ToString(*c.frame_format);
}

void AddCameraOptions(CLI::App* cmd, SynthArgs& a) {
  CameraEffects& c = a.render.camera;
  cmd->add_flag("--clean", a.clean, "Turn every camera effect off (ideal camera)");
  cmd->add_flag("--no-noise", a.no_noise, "No shot or read noise");
  cmd->add_option("--full-well-e", c.full_well_e, "Electrons at full scale (sets shot noise)")
      ->capture_default_str();
  cmd->add_option("--read-noise-e", c.read_noise_e, "Read noise s.d. (electrons)")
      ->capture_default_str();
  cmd->add_option("--black-level", c.black_level, "Black level, fraction of full scale")
      ->capture_default_str();
  cmd->add_flag("--no-motion-blur", a.no_blur, "Point-in-time exposure");
  cmd->add_option("--exposure-s", c.exposure_s, "Exposure time (s)")->capture_default_str();
  cmd->add_option("--blur-samples", c.blur_samples, "Sub-frame poses per exposure")
      ->capture_default_str();
  cmd->add_flag("--no-distortion", a.no_distortion, "No lens distortion");
  cmd->add_option("--distortion", a.distortion, "k1,k2,p1,p2,k3 (OpenCV model)")
      ->delimiter(',')
      ->expected(5);
  cmd->add_option("--focal-px", c.focal_px, "Focal length of the distortion model (px)")
      ->capture_default_str();
  cmd->add_flag("--no-defocus", a.no_defocus, "No defocus blur");
  cmd->add_option("--defocus-sigma-px", c.defocus_sigma_px, "Gaussian defocus s.d. (px)")
      ->capture_default_str();
  cmd->add_flag("--no-vignetting", a.no_vignetting, "No light fall-off to the corners");
  cmd->add_option("--vignetting-fraction", c.vignetting_fraction, "Fall-off at the corners")
      ->capture_default_str();
  cmd->add_flag("--no-lighting-gradient", a.no_gradient, "Uniform lighting");
  cmd->add_option("--lighting-gradient-fraction", c.lighting_gradient_fraction,
                  "Lighting ramp across the frame, peak to peak")
      ->capture_default_str();
  cmd->add_flag("--no-jitter", a.no_jitter, "No random (sub-pixel) placement of the scene");
  cmd->add_option("--drop-frame-probability", c.drop_frame_probability,
                  "Chance per frame that a capture is dropped (recorded in truth)")
      ->capture_default_str();
  cmd->add_option("--duplicate-frame-probability", c.duplicate_frame_probability,
                  "Chance per frame that the previous image repeats (recorded in truth)")
      ->capture_default_str();
  cmd->add_option("--drop-frames", c.drop_frames,
                  "Drop exactly this many captures, at seeded frames (recorded in truth)")
      ->capture_default_str();
  cmd->add_option("--duplicate-frames", c.duplicate_frames,
                  "Repeat the previous image at exactly this many seeded frames (in truth)")
      ->capture_default_str();
  cmd->add_option("--flicker-hz", c.flicker_hz,
                  "Mains light flicker frequency, e.g. 100 or 120 Hz (0 = none)")
      ->capture_default_str();
  cmd->add_option("--flicker-depth", c.flicker_depth,
                  "Flicker depth D in [0, 1): brightness 1 + D sin(2 pi F t + phase)")
      ->capture_default_str();
}

void AddHiddenOptions(CLI::App* cmd, SynthArgs& a) {
  dynamics::ContactExtensions& x = a.hidden.contact;
  synth::OutOfPlane& o = a.hidden.out_of_plane;
  AddExtensionOptions(cmd, x);  // the same options, bounds and help as simulate and fit
  cmd->add_option("--tilt-deg", o.tilt_deg, "Hidden: out-of-plane tilt about y_B at touch (deg)");
  cmd->add_option("--roll-deg", o.roll_deg,
                  "Hidden: out-of-plane roll about the long axis at touch (deg)");
  cmd->add_option("--tilt-rate-deg-s", o.tilt_rate_deg_s, "Hidden: out-of-plane tilt rate (deg/s)");
  cmd->add_option("--roll-rate-deg-s", o.roll_rate_deg_s, "Hidden: out-of-plane roll rate (deg/s)");
}

void ApplyCameraSwitches(SynthArgs& a) {
  CameraEffects& c = a.render.camera;
  if (a.clean) {
    const CameraEffects clean = CameraEffects::Clean();
    c.noise = clean.noise;
    c.motion_blur = clean.motion_blur;
    c.distortion = clean.distortion;
    c.defocus = clean.defocus;
    c.vignetting = clean.vignetting;
    c.lighting_gradient = clean.lighting_gradient;
    c.subpixel_jitter = clean.subpixel_jitter;
  }
  if (a.no_noise) c.noise = false;
  if (a.no_blur) c.motion_blur = false;
  if (a.no_distortion) c.distortion = false;
  if (a.no_defocus) c.defocus = false;
  if (a.no_vignetting) c.vignetting = false;
  if (a.no_gradient) c.lighting_gradient = false;
  if (a.no_jitter) c.subpixel_jitter = false;
  if (!a.distortion.empty()) {
    c.k1 = a.distortion[0];
    c.k2 = a.distortion[1];
    c.p1 = a.distortion[2];
    c.p2 = a.distortion[3];
    c.k3 = a.distortion[4];
  }
}

/// Checks the main options with their names before the libraries see them.
void CheckArgs(const SynthArgs& a) {
  if (a.output.empty()) Bad("--output", "is required");
  if (!(a.speed_m_s > 0 && a.speed_m_s <= 20))
    Bad("--speed-m-s", "must be in (0, 20], got " + std::to_string(a.speed_m_s));
  if (!(a.angle_deg >= 0 && a.angle_deg <= 60))
    Bad("--angle-deg", "must be in [0, 60], got " + std::to_string(a.angle_deg));
  if (a.e && !(*a.e > 0 && *a.e < 1)) Bad("--e", "must be in (0, 1)");
  if (a.mu && !(*a.mu >= 0 && *a.mu <= 10)) Bad("--mu", "must be in [0, 10]");
  if (!(a.scatter_scale >= 0 && a.scatter_scale <= 4))
    Bad("--scatter-scale", "must be in [0, 4], got " + std::to_string(a.scatter_scale));
  for (double s : a.design.speeds_m_s)
    if (!(s > 0 && s <= 20)) Bad("--speeds", "must each be in (0, 20], got " + std::to_string(s));
  for (double s : a.design.angles_deg)
    if (!(s >= 0 && s <= 60))
      Bad("--angles-deg", "must each be in [0, 60], got " + std::to_string(s));
  if (a.design.trials_per_cell < 1) Bad("--trials-per-cell", "must be >= 1");
  if (a.bounces < 1 || a.bounces > 20)
    Bad("--bounces", "must be in [1, 20], got " + std::to_string(a.bounces));
  if (a.bounces > 1 && a.study) Bad("--bounces", "applies to one trial, not to --study");
  if (!a.contact_sheet.empty() && a.render.frame_format != synth::FrameFormat::kPng)
    Bad("--contact-sheet", "reads PNG frames, and these frames are written as " + a.frame_format);
  const synth::CameraEffects& c = a.render.camera;
  if (c.drop_frames < 0) Bad("--drop-frames", "must be >= 0");
  if (c.duplicate_frames < 0) Bad("--duplicate-frames", "must be >= 0");
  if (c.flicker_hz != 0 && !(c.flicker_hz >= 1 && c.flicker_hz <= 1000))
    Bad("--flicker-hz", "must be 0 (none) or in [1, 1000], got " + format::Number(c.flicker_hz));
  if (!(c.flicker_depth >= 0 && c.flicker_depth < 1))
    Bad("--flicker-depth", "must be in [0, 1), got " + format::Number(c.flicker_depth));
  if (c.flicker_depth > 0 && c.flicker_hz == 0) Bad("--flicker-depth", "needs --flicker-hz");
  if (!(a.geometry.ball_diameter_m >= 1e-3 && a.geometry.ball_diameter_m <= 0.2))
    Bad("--ball-diameter-m", "must be in [0.001, 0.2]");
  if (!(a.geometry.ball_mass_kg > 0 && a.geometry.ball_mass_kg <= 100))
    Bad("--ball-mass-kg", "must be in (0, 100]");
}

/// Creates the output's folder (or its parent, for a trial), once every value is checked: a
/// bad option creates nothing.
void CheckOutput(const SynthArgs& a) {
  const fs::path out(a.output);
  std::error_code ec;
  const fs::path parent =
      a.study ? out : (out.has_parent_path() ? out.parent_path() : fs::path("."));
  fs::create_directories(parent, ec);
  if (ec || !fs::is_directory(parent) || ::access(parent.c_str(), W_OK) != 0)
    Bad("--output", "'" + a.output + "': cannot create or write folder '" + parent.string() + "'" +
                        (ec ? ": " + ec.message() : std::string()));
}

nlohmann::json TrialSummary(const synth::TrialSpec& spec, bool ok, const std::string& error,
                            const synth::TrialResult& r) {
  nlohmann::json j = {{"id", spec.id}, {"success", ok}};
  if (!ok) {
    j["error"] = error;
    return j;
  }
  const auto num = [](double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
  };
  j["path"] = r.path.string();
  j["frames"] = r.truth.frames.size();
  j["e"] = num(r.truth.impact.e);
  j["mu_eff"] = num(r.truth.impact.mu_eff);
  j["impact_time_s"] = r.truth.impact_time_s;
  j["render_seconds"] = r.render_seconds;
  return j;
}

/// Frames around impact of the first trial of each surface, as a PNG (hidden option).
void WriteContactSheet(const std::string& path, const std::vector<synth::StudyTrial>& trials) {
  std::vector<synth::ContactSheetRow> rows;
  std::vector<dynamics::Surface> seen;
  for (const auto& t : trials) {
    if (!t.ok || std::find(seen.begin(), seen.end(), t.spec.surface) != seen.end()) continue;
    seen.push_back(t.spec.surface);
    std::ostringstream label;
    label << t.spec.id << ": " << dynamics::SurfaceName(t.spec.surface) << ", " << t.spec.angle_deg
          << " deg, " << t.spec.speed_m_s << " m/s (touch before frame "
          << t.result.truth.first_frame_after_touch << ")";
    const int n = static_cast<int>(t.result.truth.frames.size());
    const int first = std::clamp(t.result.truth.first_frame_after_touch - 3, 0, std::max(0, n - 6));
    rows.push_back({t.result.path, first, std::min(6, n), label.str()});
  }
  const cv::Mat sheet = synth::MakeContactSheet(rows, 0.5);
  if (!cv::imwrite(path, sheet))
    throw std::runtime_error("cannot write contact sheet '" + path + "'");
}

/// The command line applied on top of --study-config, and every value checked.
void ApplyOptions(SynthArgs& a, CLI::App* cmd) {
  synth::StudyDesign& d = a.design;
  if (cmd->count("--seed") > 0) d.seed = a.seed;
  if (cmd->count("--name") > 0) d.name = a.name;
  if (cmd->count("--surfaces") > 0) d.surfaces = synth::ParseSurfaces(a.surfaces, "--surfaces");
  if (cmd->count("--angles-deg") > 0) d.angles_deg = a.angles_deg;
  if (cmd->count("--speeds") > 0) d.speeds_m_s = a.speeds_m_s;
  if (cmd->count("--trials-per-cell") > 0) d.trials_per_cell = a.trials_per_cell;
  if (cmd->count("--out-of-plane-random-deg") > 0)
    d.out_of_plane_random_deg = a.out_of_plane_random_deg;
  if (cmd->count("--scatter-scale") > 0) d.scatter_scale = a.scatter_scale;
  if (d.out_of_plane_random_deg < 0 || d.out_of_plane_random_deg >= 60)
    Bad("--out-of-plane-random-deg", "must be in [0, 60)");
  if (!a.markers.empty()) a.geometry.markers = ParseMarkers(a.markers);
  try {
    a.geometry.body = synth::ParseBody(a.body);
  } catch (const std::invalid_argument& e) {
    Bad("--body", e.what());
  }
  try {
    a.render.lighting = synth::ParseLighting(a.lighting);
  } catch (const std::invalid_argument& e) {
    Bad("--lighting", e.what());
  }
  try {
    a.render.frame_format = synth::ParseFrameFormat(a.frame_format);
  } catch (const std::invalid_argument& e) {
    Bad("--frame-format", e.what());
  }
  try {
    a.render.calibration = synth::ParseCalibrationTarget(a.calibration);
  } catch (const std::invalid_argument& e) {
    Bad("--calibration", e.what());
  }
  ApplyCameraSwitches(a);
  CheckArgs(a);
  if (a.render.calibration != synth::CalibrationTarget::kNone) {
    try {
      synth::PlanCalibration(a.render, a.seed);
    } catch (const std::invalid_argument& e) {
      Bad("--calibration", e.what());
    }
  }
  a.render.Validate();
  a.geometry.Validate();
  a.hidden.out_of_plane.Validate();
  a.hidden.contact.Validate();
  if (a.study) a.design.Validate();
  CheckOutput(a);
}

void Run(SynthArgs& a, RunState& state, CLI::App* cmd) {
  while (a.output.size() > 1 && a.output.back() == '/') a.output.pop_back();
  if (!a.study_config.empty()) ApplyStudyConfig(a.study_config, a, cmd);  // a bad file: exit 1
  // The options: an out-of-range value is a command-line error (exit 2) naming the option.
  ValidateOptions(cmd, [&] { ApplyOptions(a, cmd); });
  const bool tty = ::isatty(STDERR_FILENO) == 1;
  std::vector<synth::StudyTrial> trials;
  double seconds = 0;
  int failed = 0;
  if (a.study) {
    if (cmd->count("--no-scatter") > 0) a.design.scatter_parameters = false;
    // CLI hidden effects apply on top of the config's when given.
    bool hidden_given = false;
    for (const auto& f : dynamics::ContactExtensionFields())
      hidden_given = hidden_given || cmd->count(f.flag) > 0;
    for (const char* name : {"--tilt-deg", "--roll-deg", "--tilt-rate-deg-s", "--roll-rate-deg-s"})
      hidden_given = hidden_given || cmd->count(name) > 0;
    if (hidden_given) a.design.hidden = a.hidden;
    const auto progress = [tty](int done, int total, const std::string& id) {
      if (tty)
        std::cerr << "\r[" << done << "/" << total << "] " << id << "          " << std::flush;
    };
    synth::StudyResult r = synth::RenderStudy(a.design, a.geometry, a.render, a.output, a.threads,
                                              a.overwrite, progress);
    if (tty) std::cerr << "\n";
    trials = std::move(r.trials);
    seconds = r.seconds;
    failed = r.failed;
  } else {
    synth::TrialSpec spec;
    spec.surface = synth::ParseSurfaces({a.surface}, "--surface").front();
    spec.angle_deg = a.angle_deg;
    spec.speed_m_s = a.speed_m_s;
    spec.seed = a.seed;
    spec.e = a.e;
    spec.mu = a.mu;
    spec.scatter_parameters = !a.no_scatter;
    spec.scatter_scale = a.scatter_scale;
    spec.hidden = a.hidden;
    spec.bounces = a.bounces;
    spec.id = a.id.empty() ? fs::path(a.output).filename().string() : a.id;
    const synth::SceneAssets assets =
        synth::BuildSceneAssets(a.geometry, a.render, {spec.surface}, a.seed);
    synth::TrialResult r =
        synth::RenderTrial(spec, a.geometry, a.render, assets, a.output, a.overwrite);
    seconds = r.render_seconds;
    trials.push_back({spec, true, {}, std::move(r)});
  }
  for (const auto& t : trials)
    if (!t.ok) std::cerr << "hoofimpact: trial " << t.spec.id << " failed: " << t.error << "\n";
  if (!a.contact_sheet.empty()) WriteContactSheet(a.contact_sheet, trials);
  state.exit_code = failed > 0 ? kExitPartial : kExitOk;
  if (a.json) {
    nlohmann::json list = nlohmann::json::array();
    std::vector<JsonError> errors;
    for (const auto& t : trials) {
      list.push_back(TrialSummary(t.spec, t.ok, t.error, t.result));
      if (!t.ok) errors.push_back({t.error, "", "", t.spec.id, ""});
    }
    PrintEnvelope("synth", state.exit_code,
                  {{"output", a.output},
                   {"study", a.study},
                   {"trials", list},
                   {"failed", failed},
                   {"seconds", seconds}},
                  errors);
  } else {
    std::cout << "Wrote " << trials.size() - static_cast<std::size_t>(failed) << " trial(s) to "
              << a.output << " in " << format::Seconds(seconds)
              << (failed ? " (" + std::to_string(failed) + " failed)" : "") << "\n";
  }
}

}  // namespace

void RegisterSynth(CLI::App& app, RunState& state) {
  auto args = std::make_shared<SynthArgs>();
  SynthArgs& a = *args;
  CLI::App* cmd = app.add_subcommand(
      "synth",
      "Render synthetic 8000 fps trials with ground truth (trial or study folders); `synth "
      "footage`: everyday footage of a ball in a room, as a phone films it");
  // Required, but checked in the callback (CheckArgs): `synth footage` has its own -o.
  cmd->add_option("-o,--output", a.output,
                  "Output folder (required): the trial folder to write (the study folder with "
                  "--study)");
  cmd->add_flag("--overwrite", a.overwrite,
                "Replace existing trial folders; with --study, render into a folder that holds a "
                "study already (its other trials stay listed in study.json)");
  cmd->add_option("--surface", a.surface, "steel, concrete or asphalt")->capture_default_str();
  cmd->add_option("--angle-deg", a.angle_deg, "Surface angle phi, in [0, 60] (deg)")
      ->capture_default_str();
  cmd->add_option("--speed-m-s", a.speed_m_s, "Vertical speed at first touch (m/s)")
      ->capture_default_str();
  cmd->add_option(
         "--seed", a.seed,
         "Seed of every random draw: of the trial (default 1) or of the study (default 2024)")
      ->check(kNotNegative);
  cmd->add_option("--id", a.id, "Trial id (default: the output folder's name)");
  cmd->add_option("--e", a.e, "Fix the normal restitution that sets zeta (no draw)");
  cmd->add_option("--mu", a.mu, "Fix the friction coefficient (no draw)");
  cmd->add_flag("--no-scatter", a.no_scatter,
                "Use the paper's coefficients without per-trial draws");
  cmd->add_option("--scatter-scale", a.scatter_scale,
                  "Multiply the spread of the per-trial e and mu draws, in [0, 4] "
                  "(1 = the paper's, 0.5 = half, 0 = no scatter)")
      ->capture_default_str();
  cmd->add_option("--width-px", a.render.width_px, "Frame width (px)")->capture_default_str();
  cmd->add_option("--height-px", a.render.height_px, "Frame height (px)")->capture_default_str();
  cmd->add_option("--bit-depth", a.render.bit_depth,
                  "8 or 16 bits per pixel; 12 (0..4095) with --frame-format mraw or cine")
      ->capture_default_str();
  cmd->add_option("--frame-format", a.frame_format,
                  "png (frames/%06d.png), mraw (one Photron clip.mraw + clip.cihx) or cine (one "
                  "Phantom clip.cine with time stamps)")
      ->capture_default_str();
  cmd->add_option("--calibration", a.calibration,
                  "none, checkerboard or ruler: also write calibration.png showing it at the "
                  "trial's scale, and take trial.json's scale from it (truth.json: calibration)")
      ->capture_default_str();
  cmd->add_option("--m-per-px", a.render.m_per_px, "Scale in the plane of motion (m/px)")
      ->capture_default_str();
  cmd->add_option("--fps", a.render.fps, "Frame rate (1/s)")->capture_default_str();
  cmd->add_option("--frames-before", a.render.frames_before, "Frames before first touch")
      ->capture_default_str();
  cmd->add_option("--frames-after", a.render.frames_after, "Frames from first touch on")
      ->capture_default_str();
  cmd->add_option("--png-compression", a.render.png_compression, "PNG zlib level 0-9")
      ->capture_default_str();
  cmd->add_option("--markers-b-m", a.markers,
                  "Markers in the body frame, e.g. \"M1=0.006,0;M2=0.024,0\" (m)");
  cmd->add_option("--body", a.body,
                  "markers (the specimen with its dots), unmarked (no dots) or ball")
      ->capture_default_str();
  cmd->add_option("--ball-diameter-m", a.geometry.ball_diameter_m, "Diameter of the ball (m)")
      ->capture_default_str();
  cmd->add_option("--ball-mass-kg", a.geometry.ball_mass_kg,
                  "Mass of the ball (kg; a solid sphere's inertia)")
      ->capture_default_str();
  cmd->add_option("--lighting", a.lighting,
                  "front (lit body on a dark studio) or backlit (dark silhouette on bright)")
      ->capture_default_str();
  cmd->add_option("--bounces", a.bounces,
                  "Impacts per clip (trial only); frames-after grows to hold them all")
      ->capture_default_str();
  cmd->add_flag("--frames-from-flight", a.render.frames_from_flight,
                "Frame counts from the flight: from release at rest to the apex after the last "
                "impact (for low frame rates)");
  AddCameraOptions(cmd, a);
  AddHiddenOptions(cmd, a);
  cmd->add_flag("--study", a.study,
                "Render a whole study (paper design: 3 x 4 x 4 x 3 = 144 trials)");
  cmd->add_option("--study-config", a.study_config,
                  "JSON with the study design and hidden effects");
  cmd->add_option("--name", a.name, "Study name (default synthetic-paper-replica)");
  cmd->add_option("--surfaces", a.surfaces, "Study surfaces, comma-separated (default all three)")
      ->delimiter(',');
  cmd->add_option("--angles-deg", a.angles_deg,
                  "Study angles (deg), comma-separated (default 0,10,20,30)")
      ->delimiter(',');
  cmd->add_option("--speeds", a.speeds_m_s,
                  "Study speeds (m/s), comma-separated (default 1.5,2.33,3.17,4)")
      ->delimiter(',');
  cmd->add_option("--trials-per-cell", a.trials_per_cell, "Repetitions per surface x angle x speed")
      ->capture_default_str();
  cmd->add_option("--out-of-plane-random-deg", a.out_of_plane_random_deg,
                  "Study: per-trial random tilt and roll within +- this (deg)");
  // --jobs, as in every other command; --threads, its earlier name, still works.
  cmd->add_option("--jobs", a.threads, "Worker threads for a study (0 = all cores)")
      ->check(InRange(0, 4096))
      ->capture_default_str();
  // Checked in the callback, in the name of --jobs (a hidden option's own check names nothing).
  cmd->add_option("--threads", a.threads, "Deprecated: --jobs")->group("");
  AddJsonFlag(cmd, a.json);
  cmd->add_option("--contact-sheet", a.contact_sheet, "Write a contact sheet PNG")->group("");
  const CLI::App* footage = RegisterSynthFootage(cmd, state);
  cmd->callback([args, &state, cmd, footage] {
    if (footage->parsed()) return;  // `synth footage` ran in its own callback
    if (args->threads < 0 || args->threads > 4096)
      throw CLI::ValidationError("--jobs",
                                 "must be in [0, 4096], got " + std::to_string(args->threads));
    Run(*args, state, cmd);
  });
}

}  // namespace hoof::cli
