#pragma once
/// @file
/// The study report: one self-contained HTML page (inline CSS and JS, figures and replay frames
/// as data URIs, no network) made from a study file that `hoofimpact run` wrote. It shows the
/// study summary with how the study file and the page were made (command lines, analysis,
/// statistics and discovery options, versions), the contact model per surface
/// (/comparison/surfaces), the statistics (/stats), the study figures (Figures 4 and 5), one
/// row per trial (/results with the z-scores of /comparison/trials) and, for a few trials, a
/// replay of the frames around the impact that can be scrubbed frame by frame with the
/// simulated and measured markers and their magnified residuals drawn over it
/// (/comparison/frames/<id>; the glyphs of compare/replay_convention.h, as the overlay video
/// draws them). When the study file has `/discovery` (`hoofimpact discover`), a
/// Discovery section follows the figures: the verdict, the findings, per round the candidate
/// evidence and the significant structure tests, and the discovery figures.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace hoof::report {

/// What goes into the page.
struct HtmlReportOptions {
  /// Trials with a replay: one per surface first, then more in file order; 0 = no replay.
  /// Range 0..50 (each costs about frames_per_replay JPEG frames).
  int replay_trials = 4;
  /// Frames per replay, centred on the impact frame; range 2..400.
  int frames_per_replay = 20;
  /// Replay frames are downscaled to at most this width (px); range 64..4096.
  int replay_max_width_px = 480;
  /// JPEG quality of the replay frames, 1..100.
  int jpeg_quality = 80;
  /// Magnification F of the replay's residual arrows: measured -> measured + F (simulated -
  /// measured); 1..1000 (compare/replay_convention.h).
  int residual_scale = 20;
  /// The study folder's place when it has moved since the study file was written: a trial
  /// folder missing at its recorded path is looked for here (compare::replay::
  /// LocateTrialFolder). Empty = only where recorded.
  std::filesystem::path study_dir;
  /// The command that made the report, shown in the page; "" = not known.
  std::string command_line;

  /// Throws std::invalid_argument naming the field and the value when out of range.
  void Validate() const;
};

/// What WriteHtmlReport did.
struct HtmlReportSummary {
  std::filesystem::path output;  ///< the page written
  std::size_t bytes = 0;         ///< its size
  int trials = 0;                ///< rows of the trial table
  int figures = 0;               ///< figures embedded
  int replays = 0;               ///< trials with a replay
  bool discovery = false;        ///< the page has a Discovery section (/discovery exists)
  std::string notes;             ///< what was left out and why (e.g. frames not found), "" if none
  std::vector<std::string> missing_replays;  ///< "<id>: why", one per replay not drawn
};

/// Escapes text for HTML element content and attribute values (& < > " ').
std::string HtmlEscape(std::string_view text);

/// Base64 (RFC 4648, with padding) of `bytes`, for data URIs.
std::string Base64(std::string_view bytes);

/// Writes the report of `study_h5` to `output` (atomically; parent folders created). Throws
/// std::runtime_error naming the file when it is missing, is not a study file, or lacks
/// /comparison ("run `hoofimpact run` first"). A trial whose frames cannot be read gets no
/// replay and is not an error: the page's Replay section and the summary's notes say why (the
/// trial's id and every folder looked at).
HtmlReportSummary WriteHtmlReport(const std::filesystem::path& study_h5,
                                  const std::filesystem::path& output,
                                  const HtmlReportOptions& options = {});

}  // namespace hoof::report
