// hoofimpact init: a clip (camera file, video or folder of frames) -> a trial folder with a
// trial.json to review and a contact sheet of what was found (docs/init.md).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/json_output.h"
#include "format/number_format.h"
#include "io/atomic_file.h"
#include "pipeline/calibration_scale.h"
#include "pipeline/trial_setup.h"

namespace hoof::cli {
namespace {

/// init's calibration image options (docs/init.md, "A calibration image").
struct CalibrationArgs {
  std::string checkerboard, corners, ruler;
  double square_m = 0.0, tick_m = 0.0;
  std::vector<double> ruler_from, ruler_to;
};

void AddCalibrationOptions(CLI::App* cmd, CalibrationArgs& c) {
  cmd->add_option("--checkerboard", c.checkerboard,
                  "Calibration image (PNG/TIFF) of a checkerboard in the plane of motion: the "
                  "scale from it (with --corners and --square-m)");
  cmd->add_option("--corners", c.corners, "The checkerboard's inner corners, COLSxROWS (e.g. 9x6)");
  cmd->add_option("--square-m", c.square_m, "The checkerboard's square side (m)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--ruler", c.ruler,
                  "Calibration image (PNG/TIFF) of a ruler in the plane of motion: the scale from "
                  "its ticks (with --ruler-from, --ruler-to and --tick-m)");
  cmd->add_option("--ruler-from", c.ruler_from, "X,Y (px): one end of a segment across the ticks")
      ->delimiter(',')
      ->expected(2);
  cmd->add_option("--ruler-to", c.ruler_to, "X,Y (px): the segment's other end")
      ->delimiter(',')
      ->expected(2);
  cmd->add_option("--tick-m", c.tick_m, "The ruler's tick spacing (m)")->check(CLI::PositiveNumber);
}

/// The calibration options checked and turned into pipeline::InitCalibration (kind empty
/// without one); CLI::ValidationError names the option.
pipeline::InitCalibration ParseCalibration(const CalibrationArgs& c,
                                           const pipeline::TrialSetupOptions& o) {
  pipeline::InitCalibration out;
  if (!c.checkerboard.empty() && !c.ruler.empty())
    throw CLI::ValidationError("--ruler", "give --checkerboard or --ruler, not both");
  const bool other = o.m_per_px > 0 || o.diameter_m > 0;
  if (!c.checkerboard.empty()) {
    if (other)
      throw CLI::ValidationError("--checkerboard",
                                 "give one scale: not with --m-per-px or --diameter-m");
    int cols = 0, rows = 0;
    char x = 0, extra = 0;
    if (c.corners.empty() ||
        std::sscanf(c.corners.c_str(), "%d%c%d%c", &cols, &x, &rows, &extra) != 3 ||
        (x != 'x' && x != 'X') || cols < 3 || rows < 3 || cols > 1000 || rows > 1000)
      throw CLI::ValidationError("--corners",
                                 "must be COLSxROWS inner corners, each 3 to 1000 (e.g. 9x6), "
                                 "with --checkerboard; got '" +
                                     c.corners + "'");
    if (!(c.square_m > 0))
      throw CLI::ValidationError("--square-m", "is needed with --checkerboard");
    out.kind = "checkerboard";
    out.image = c.checkerboard;
    out.cols = cols;
    out.rows = rows;
    out.square_m = c.square_m;
  } else if (!c.ruler.empty()) {
    if (other)
      throw CLI::ValidationError("--ruler", "give one scale: not with --m-per-px or --diameter-m");
    if (c.ruler_from.size() != 2 || c.ruler_to.size() != 2)
      throw CLI::ValidationError("--ruler-from", "and --ruler-to (X,Y px) are needed with --ruler");
    if (!(c.tick_m > 0)) throw CLI::ValidationError("--tick-m", "is needed with --ruler");
    out.kind = "ruler";
    out.image = c.ruler;
    out.from_px = {c.ruler_from[0], c.ruler_from[1]};
    out.to_px = {c.ruler_to[0], c.ruler_to[1]};
    out.tick_m = c.tick_m;
  } else if (!c.corners.empty() || c.square_m > 0 || !c.ruler_from.empty() || !c.ruler_to.empty() ||
             c.tick_m > 0) {
    throw CLI::ValidationError("--checkerboard",
                               "or --ruler names the calibration image that --corners, --square-m, "
                               "--ruler-from, --ruler-to and --tick-m describe");
  }
  if (!out.kind.empty() && !std::filesystem::is_regular_file(out.image))
    throw std::runtime_error(out.image.string() + ": the calibration image (--" + out.kind +
                             ") does not exist");
  return out;
}

}  // namespace

namespace {

/// The ends of the surface edge found ([[x, y], [x, y]] in px), or null.
nlohmann::json SurfaceEnds(const pipeline::TrialSetup& s) {
  if (!s.surface_line) return nullptr;
  const auto& l = *s.surface_line;
  const Eigen::Vector2d a = l.point_I - 0.5 * l.length_px * l.direction_I,
                        b = l.point_I + 0.5 * l.length_px * l.direction_I;
  return {{a.x(), a.y()}, {b.x(), b.y()}};
}

/// What moved and what each path was judged to be, or null when the motion was not examined.
nlohmann::json MovingPaths(const pipeline::TrialSetup& s) {
  if (!s.moving) return nullptr;
  nlohmann::json out = nlohmann::json::array();
  for (const auto& c : s.moving->candidates)
    out.push_back({{"first_frame", c.first_frame},
                   {"last_frame", c.last_frame},
                   {"frames", c.regions},
                   {"first_px", {c.p_first_I.x(), c.p_first_I.y()}},
                   {"diameter_px", c.diameter_px},
                   {"color", pipeline::ColourHex(c.rgb)},
                   {"verdict", pipeline::CandidateVerdictName(c.verdict)},
                   {"reason", c.reason}});
  return out;
}

}  // namespace

void RegisterInit(CLI::App& app, RunState& state) {
  struct Args {
    std::string clip;
    std::string trial_dir;
    bool json = false;
    bool overwrite = false;
    pipeline::TrialSetupOptions options;
    CalibrationArgs calibration;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "init",
      "Set up a trial from a clip: find the body, surface, impacts and scale; write trial.json "
      "and a contact sheet to review");
  cmd->add_option(
         "clip", args->clip,
         "Camera file (.mraw/.cihx/.cih, .cine, .tif), video, or folder of numbered frames")
      ->required();
  cmd->add_option("-o,--output", args->trial_dir, "Trial folder to write (created)")->required();
  cmd->add_option("--body", args->options.body,
                  "Body: auto, markers (white dots on black patches), ball or outline")
      ->check(CLI::IsMember({"auto", "markers", "ball", "outline"}))
      ->capture_default_str();
  cmd->add_option("--diameter-m", args->options.diameter_m,
                  "A ball's known diameter (m): the scale from it")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--m-per-px", args->options.m_per_px, "A known scale (m/px)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--fps", args->options.fps,
                  "Capture rate (1/s): for a clip that does not record it, or a slow-motion "
                  "video, whose container records the rate it plays at")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--color", args->options.color,
                  "The ball's colour (#rrggbb, or red, green, blue, yellow, orange, white, black, "
                  "pink, purple): a cue for finding it by its motion, where several things move");
  cmd->add_option("--surface", args->options.surface, "The surface's name in trial.json")
      ->capture_default_str();
  cmd->add_option("--specimen", args->options.specimen,
                  "The specimen id of an outline, a marked body (its marker layout) or a ball (its "
                  "diameter gives the scale), copied from study.json into the trial");
  cmd->add_option("--study", args->options.study_json,
                  "study.json that defines --specimen (default: the one beside the trial folder)");
  AddCalibrationOptions(cmd, args->calibration);
  cmd->add_flag("--overwrite", args->overwrite, "Replace an existing trial.json");
  AddJsonFlag(cmd, args->json);

  cmd->callback([args, &state] {
    Args& a = *args;
    namespace fs = std::filesystem;
    const fs::path dir(a.trial_dir);
    if (a.options.m_per_px > 0 && a.options.diameter_m > 0)
      throw CLI::ValidationError("--m-per-px", "give --m-per-px or --diameter-m, not both");
    if (fs::exists(dir / "trial.json") && !a.overwrite)
      throw std::runtime_error((dir / "trial.json").string() +
                               ": exists already (--overwrite replaces it)");
    const pipeline::InitCalibration calibration = ParseCalibration(a.calibration, a.options);
    const fs::path sheet = dir / "contact-sheet.png";
    pipeline::TrialSetup s;
    try {
      s = pipeline::SetUpTrial(a.clip, dir, a.options);
    } catch (const pipeline::SetupRefused& refused) {
      // Nothing to measure: the sheet still shows what moved and why each path was refused.
      io::CreateFolder(dir);
      io::WriteTextAtomically(sheet, pipeline::EncodePng(pipeline::ContactSheet(refused.setup())));
      throw std::runtime_error(std::string(refused.what()) + " (what moved: " + sheet.string() +
                               ")");
    }
    pipeline::UseCalibrationScale(calibration, dir, s);
    io::CreateFolder(dir);
    io::WriteTextAtomically(sheet, pipeline::EncodePng(pipeline::ContactSheet(s)));
    // trial.json last: a trial folder whose trial.json exists is whole.
    const auto files = pipeline::TrialFiles(s);
    for (auto f = files.rbegin(); f != files.rend(); ++f)
      io::WriteTextAtomically(dir / f->first, f->second);
    state.exit_code = kExitOk;
    if (a.json) {
      nlohmann::json r = {
          {"trial_json", (dir / "trial.json").string()},
          {"contact_sheet", sheet.string()},
          {"clip", s.clip.string()},
          {"frames", s.frames_reference},
          {"frame_count", s.count},
          {"fps", s.fps},
          {"container_fps", JsonNumber(s.container_fps)},
          {"rotation_deg", s.rotation_deg},
          {"body_shape", s.shape},
          {"found_by", s.found_by},
          {"gravity_image", {s.gravity_image.x(), s.gravity_image.y()}},
          {"gravity_from_arcs", s.gravity_from_arcs},
          {"contact_level_from_arcs", s.contact_level_from_arcs},
          {"capture_fps_from_gravity",
           JsonNumber(s.capture_rate.measured ? s.capture_rate.capture_fps : core::kNaN)},
          {"capture_fps_from_gravity_se",
           JsonNumber(s.capture_rate.measured ? s.capture_rate.capture_fps_se : core::kNaN)},
          {"moving_paths", MovingPaths(s)},
          {"polarity", s.shape == "markers"
                           ? nlohmann::json(nullptr)
                           : nlohmann::json(tracking::PolarityName(s.track.polarity))},
          {"body_diameter_px", JsonNumber(s.body_diameter_px)},
          {"marker_dots", s.marker_dots_px.size()},
          {"marker_layout_known", s.marker_layout_known},
          {"surface_found", s.surface_line.has_value()},
          {"surface_angle_deg", s.surface_angle_deg},
          {"surface_line_px", SurfaceEnds(s)},
          {"impact_frames", s.impact_frames},
          {"scale_source", s.scale_from},
          {"m_per_px", JsonNumber(s.m_per_px)},
          {"m_per_px_se", JsonNumber(s.m_per_px_se)},
          {"gravity_m_per_px", JsonNumber(s.gravity.m_per_px)},
          {"gravity_m_per_px_se", JsonNumber(s.gravity.m_per_px_se)},
          {"trial", nlohmann::json::parse(s.trial_json)}};
      PrintEnvelope("init", kExitOk, std::move(r), {}, s.warnings);
      return;
    }
    using format::Kind;
    std::cout << "Clip " << s.clip.string() << ": " << s.count << " frames at "
              << format::Number(s.fps, Kind::kMeasured) << " fps\n";
    std::cout << "  body     " << s.shape << (s.found_by == "motion" ? " (by its motion)" : "")
              << ", ";
    if (s.shape == "markers")
      std::cout << s.marker_dots_px.size() << " white dots"
                << (s.marker_layout_known ? ", layout from the specimen" : ", layout not given");
    else if (s.found_by == "motion")
      std::cout << "colour " << pipeline::ColourHex(s.moving->rgb);
    else
      std::cout << tracking::PolarityName(s.track.polarity);
    if (s.shape == "ball")
      std::cout << ", diameter " << format::Number(s.body_diameter_px, Kind::kMeasured) << " px";
    std::cout << "\n  surface  "
              << (s.surface_line ? format::Number(s.surface_angle_deg, Kind::kMeasured) + " deg"
                                 : std::string("not found"))
              << "\n  impacts  ";
    if (s.impact_frames.empty()) std::cout << "none found";
    for (int f : s.impact_frames) std::cout << "frame " << f << " ";
    std::cout << "\n  scale    " << format::WithError(s.m_per_px, s.m_per_px_se) << " m/px from "
              << s.scale_from << "\n";
    if (s.moving && s.found_by == "motion")
      for (std::size_t i = 1; i < s.moving->candidates.size() && i <= 5; ++i) {
        const auto& c = s.moving->candidates[i];
        std::cout << "  moving   frames " << c.first_frame << "-" << c.last_frame << ": "
                  << pipeline::CandidateVerdictName(c.verdict) << ": " << c.reason << "\n";
      }
    for (const auto& w : s.warnings) std::cout << "  warning: " << w << "\n";
    std::cout << "Wrote " << (dir / "trial.json").string() << " and " << sheet.string()
              << "; review them, then: hoofimpact track " << dir.string() << "\n";
  });
}

}  // namespace hoof::cli
