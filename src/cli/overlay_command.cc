// hoofimpact overlay: a trial's measured frames with the tracked markers, the simulated
// markers and outline, the magnified residuals, the contact point and a time stamp drawn on (PNG
// per frame and a slowed video).
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/json_output.h"
#include "compare/replay_convention.h"
#include "overlay/overlay.h"

namespace hoof::cli {

void RegisterOverlay(CLI::App& app, RunState& state) {
  struct Args {
    std::string study_file;
    std::string trial_id;
    std::string output_dir = "overlay";
    std::string study_dir;
    overlay::OverlayOptions options;
    bool video_only = false, frames_only = false;
    bool json = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "overlay",
      "Replay a trial: its frames with the tracked markers (green rings), the simulated markers "
      "(magenta +) and outline, each marker's residual magnified into an arrow (sky blue), the "
      "contact point and a time stamp; PNG per frame and a slowed video");
  cmd->add_option("study_h5", args->study_file, "HDF5 study file written by `run`")->required();
  cmd->add_option("trial_id", args->trial_id, "Trial id (the `id` column of /results)")->required();
  cmd->add_option("-o,--output", args->output_dir,
                  "Output folder; the trial's files go to DIR/<id>/")
      ->capture_default_str();
  cmd->add_option("--slowdown", args->options.slowdown,
                  "The video plays N times slower than real time (1..1000000): 1000 shows an "
                  "8000 fps capture at 8 frames per second (each frame written 3 times at 24 "
                  "fps). The video runs at 20 to 60 fps; a pace that needs more than 60 fps plays "
                  "at 60 fps, slower than asked (the command warns). The pace is written on "
                  "every frame")
      ->capture_default_str();
  cmd->add_option("--residual-scale", args->options.residual_scale,
                  "Magnification F of the residual arrows, drawn from each measured marker to "
                  "measured + F (simulated - measured); a whole number 1..1000, stated on every "
                  "frame")
      ->capture_default_str();
  cmd->add_option("--study-dir", args->study_dir,
                  "The study folder's place when it has moved since `run`: a trial folder "
                  "missing at its recorded path is looked for here");
  auto* vo = cmd->add_flag("--video-only", args->video_only, "Write the video only");
  cmd->add_flag("--frames-only", args->frames_only, "Write the PNG frames only")->excludes(vo);
  AddJsonFlag(cmd, args->json);
  cmd->callback([cmd, args, &state] {
    overlay::OverlayOptions& o = args->options;
    o.output_dir = args->output_dir;
    o.study_dir = args->study_dir;
    o.write_frames = !args->video_only;
    o.write_video = !args->frames_only;
    ValidateOptions(cmd, [&] { o.Validate(); });
    if (!std::filesystem::is_regular_file(args->study_file))
      throw std::runtime_error(args->study_file + ": no such study file");
    if (!args->study_dir.empty() && !std::filesystem::is_directory(args->study_dir))
      throw CLI::ValidationError("--study-dir", args->study_dir + ": no such folder");
    const auto s = overlay::RenderTrialOverlay(args->study_file, args->trial_id, o);
    state.exit_code = kExitOk;
    if (args->json) {
      PrintEnvelope(
          "overlay", state.exit_code,
          {{"study_h5", args->study_file},
           {"id", args->trial_id},
           {"trial_dir", s.trial_dir.string()},
           {"dir", s.dir.string()},
           {"frames", s.frames},
           {"frames_written", o.write_frames},
           {"video", s.video.empty() ? nlohmann::json(nullptr) : nlohmann::json(s.video.string())},
           {"video_format", s.video_format},
           {"residual_scale", o.residual_scale},
           {"slowdown", o.slowdown}},
          {}, s.warnings);
      for (const auto& w : s.warnings) std::cerr << "hoofimpact: warning: " << w << "\n";
      return;
    }
    std::cout << s.frames << " frame(s) of " << args->trial_id << " (from " << s.trial_dir.string()
              << ") rendered in " << s.dir.string() << (o.write_frames ? " (frame_NNNNNN.png)" : "")
              << "\n";
    if (!s.video.empty())
      std::cout << "video: " << s.video.string() << " (" << s.video_format << "), "
                << s.pace.Legend() << "\n";
    for (const auto& w : s.warnings) std::cerr << "hoofimpact: warning: " << w << "\n";
    state.exit_code = kExitOk;
  });
}

}  // namespace hoof::cli
