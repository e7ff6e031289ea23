// hoofimpact overlay: a trial's measured frames with the tracked markers, the simulated
// markers and outline, the contact point and a time stamp drawn on (PNG per frame and a video).
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/json_output.h"
#include "overlay/overlay.h"

namespace hoof::cli {

void RegisterOverlay(CLI::App& app, RunState& state) {
  struct Args {
    std::string study_file;
    std::string trial_id;
    std::string output_dir = "overlay";
    int slow = 1;
    bool video_only = false, frames_only = false;
    bool json = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "overlay",
      "Replay a trial: its frames with the tracked (green) and simulated (red) markers, the "
      "simulated outline, the contact point and a time stamp; PNG per frame and a video");
  cmd->add_option("study_h5", args->study_file, "HDF5 study file written by `run`")->required();
  cmd->add_option("trial_id", args->trial_id, "Trial id (the `id` column of /results)")->required();
  cmd->add_option("-o,--output", args->output_dir,
                  "Output folder; the trial's files go to DIR/<id>/")
      ->capture_default_str();
  cmd->add_option("--slow", args->slow, "Show each frame N times in the video (25 fps)")
      ->capture_default_str()
      ->check(InRange(1, 10000));
  auto* vo = cmd->add_flag("--video-only", args->video_only, "Write the video only");
  cmd->add_flag("--frames-only", args->frames_only, "Write the PNG frames only")->excludes(vo);
  AddJsonFlag(cmd, args->json);
  cmd->callback([args, &state] {
    if (!std::filesystem::is_regular_file(args->study_file))
      throw std::runtime_error(args->study_file + ": no such study file");
    overlay::OverlayOptions o;
    o.output_dir = args->output_dir;
    o.slow = args->slow;
    o.write_frames = !args->video_only;
    o.write_video = !args->frames_only;
    const auto s = overlay::RenderTrialOverlay(args->study_file, args->trial_id, o);
    state.exit_code = kExitOk;
    if (args->json) {
      PrintEnvelope(
          "overlay", state.exit_code,
          {{"study_h5", args->study_file},
           {"id", args->trial_id},
           {"dir", s.dir.string()},
           {"frames", s.frames},
           {"frames_written", o.write_frames},
           {"video", s.video.empty() ? nlohmann::json(nullptr) : nlohmann::json(s.video.string())},
           {"video_format", s.video_format}},
          {}, s.warnings);
      for (const auto& w : s.warnings) std::cerr << "hoofimpact: warning: " << w << "\n";
      return;
    }
    std::cout << s.frames << " frame(s) of " << args->trial_id << " rendered in " << s.dir.string()
              << (o.write_frames ? " (frame_NNNNNN.png)" : "") << "\n";
    if (!s.video.empty())
      std::cout << "video: " << s.video.string() << " (" << s.video_format << ")\n";
    for (const auto& w : s.warnings) std::cerr << "hoofimpact: warning: " << w << "\n";
    state.exit_code = kExitOk;
  });
}

}  // namespace hoof::cli
