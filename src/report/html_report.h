#pragma once
/// @file
/// The study report: one self-contained HTML page (inline CSS and JS, figures and replay frames
/// as data URIs, no network) made from a study file that `hoofimpact run` wrote. It shows the
/// study summary and the contact model per surface (/comparison/surfaces), the statistics
/// (/stats), the study figures (Figures 4 and 5), one row per trial (/results with the z-scores
/// of /comparison/trials) and, for a few trials, a replay of the frames around the impact that
/// can be scrubbed frame by frame with the simulated and measured markers drawn over it
/// (/comparison/frames/<id>). When the study file has `/discovery` (`hoofimpact discover`), a
/// Discovery section follows the figures: the verdict, the findings, per round the candidate
/// evidence and the significant structure tests, and the discovery figures.

#include <filesystem>
#include <string>
#include <string_view>

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
};

/// Escapes text for HTML element content and attribute values (& < > " ').
std::string HtmlEscape(std::string_view text);

/// Base64 (RFC 4648, with padding) of `bytes`, for data URIs.
std::string Base64(std::string_view bytes);

/// Writes the report of `study_h5` to `output` (atomically; parent folders created). Throws
/// std::runtime_error naming the file when it is missing, is not a study file, or lacks
/// /comparison ("run `hoofimpact run` first"). A trial whose frames cannot be read gets no
/// replay; the summary's notes say why.
HtmlReportSummary WriteHtmlReport(const std::filesystem::path& study_h5,
                                  const std::filesystem::path& output,
                                  const HtmlReportOptions& options = {});

}  // namespace hoof::report
