#pragma once
/// @file
/// Setting up a trial from a clip (`hoofimpact init`, docs/init.md): what the clip shows, found
/// from its frames: the body (a ball or an unmarked outline by its silhouette, and its
/// polarity), the surface line and its angle, the impacts, and a scale (stated, a ball's known
/// diameter, or gravity's parabola). The result is a trial.json for a person to review and a
/// contact sheet of what was found; `hoofimpact track` then measures the trial as written.

#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "kinematics/capture_rate.h"
#include "kinematics/gravity_scale.h"
#include "pipeline/moving_body.h"
#include "tracking/silhouette_tracker.h"
#include "tracking/surface_line.h"

namespace hoof::pipeline {

/// The background image init writes beside trial.json for a body found by its motion (the
/// clip's median: tracking/motion_blobs.h), which track then reads instead of making it again.
inline constexpr const char* kBackgroundFile = "background.png";

/// Camera files and clips at kHighSpeedFps or more are taken as a high-speed camera's: their
/// body is found by its silhouette, not by its motion. There the body moves little between
/// frames (so much of it stays in the clip's median). In a clip shorter than kMinMotionClip_s
/// (s) gravity may not bend the path measurably (0.2 s bends a free fall by 0.2 m): its body
/// is looked for by its motion first (a phone's slow-motion clip of a throw, 240 captures a
/// second for a tenth of a second), and by its silhouette where that finds no ball.
inline constexpr double kHighSpeedFps = 400.0;
inline constexpr double kMinMotionClip_s = 0.2;

/// Settings of `init`.
struct TrialSetupOptions {
  std::string body = "auto";        ///< "auto", "markers", "ball" or "outline"
  double diameter_m = 0.0;          ///< a ball's known diameter (> 0: the scale from it)
  double m_per_px = 0.0;            ///< a known scale (> 0: stated in trial.json)
  double fps = 0.0;                 ///< frame rate, for clips that do not record one (> 0)
  std::string surface = "unknown";  ///< trial.json's surface (free text)
  /// A specimen for an outline, a marked body or a ball: its study.json and id; copied into the
  /// trial as specimen_parameters (a marked body's layout, markers_B_m, comes from it; a ball's
  /// must be one, and its diameter_m gives the scale as diameter_m does).
  std::filesystem::path study_json;
  std::string specimen;
  double gravity_m_s2 = core::kStandardGravity_m_s2;
  /// The body's colour (`--color`: "#rrggbb" or a name, ParseColour), a cue for finding it by
  /// its motion; empty: taken from the moving body itself.
  std::string color;
};

/// What `init` found.
struct TrialSetup {
  std::filesystem::path clip;    ///< the clip as given
  std::string clip_kind;         ///< "camera_file", "video" or "frames"
  std::string frames_reference;  ///< camera file, video or pattern, relative to the trial
  int first = 0, count = 0;      ///< frames of a folder
  double fps = 0.0;
  bool fps_recorded = false;  ///< the camera file records it (trial.json leaves it out)
  /// A video: the rate its container plays at (NaN where it records none), and its rotation
  /// tag (clockwise degrees; the frames are read turned upright by it).
  double container_fps = core::kNaN;
  int rotation_deg = 0;
  std::string shape;  ///< "markers", "ball" or "outline"
  /// How the body was found: "markers", "motion" (a ball whose path is ballistic against the
  /// clip's own background: `moving`) or "shape" (a silhouette by its shape in one frame).
  std::string found_by;
  /// What moves in the clip and what each moving path was judged to be (found_by "motion", or
  /// tried before "shape"); null when not tried.
  std::shared_ptr<const MovingBody> moving;
  /// Gravity's direction in the image: from the arcs where measured, else down the image.
  Eigen::Vector2d gravity_image{0.0, 1.0};
  bool gravity_from_arcs = false;
  /// No straight edge where the ball turns: the contact level is where its arcs meet, and the
  /// surface is taken as level with gravity.
  bool contact_level_from_arcs = false;
  /// The capture rate gravity implies, where a scale independent of gravity is known (a ball's
  /// diameter, a stated scale); `measured` false otherwise.
  kinematics::CaptureRate capture_rate;
  tracking::SilhouetteTrack track;
  std::optional<tracking::ImageLine> surface_line;
  double surface_angle_deg = 0.0;
  std::vector<int> impact_frames;  ///< first frame of each contact found
  kinematics::GravityScale gravity;
  /// "m_per_px", "body_diameter", "markers", "end_radius" or "gravity"; UseCalibrationScale
  /// (pipeline/calibration_scale.h) may set "checkerboard" or "ruler" after
  std::string scale_from;
  double m_per_px = core::kNaN, m_per_px_se = core::kNaN;  ///< the scale it implies (NaN: none)
  double body_diameter_px = core::kNaN;                    ///< ball: median fitted diameter
  /// A marked body: the white dots seen in the first frame, and per frame the dots followed
  /// (empty where one was not found).
  std::vector<Eigen::Vector2d> marker_dots_px;
  std::vector<std::vector<Eigen::Vector2d>> marker_frames_px;
  double marker_dot_radius_px = core::kNaN;
  bool marker_layout_known = false;  ///< the specimen's markers_B_m was given
  std::vector<std::string> warnings;
  std::string trial_json;  ///< the trial.json text
};

/// SetUpTrial's refusal when no body can be measured: the message names what failed, and the
/// setup holds what was found (the moving paths and their verdicts) for the contact sheet.
class SetupRefused : public std::runtime_error {
 public:
  SetupRefused(const std::string& message, std::shared_ptr<const TrialSetup> setup)
      : std::runtime_error(message), setup_(std::move(setup)) {}
  const TrialSetup& setup() const { return *setup_; }

 private:
  std::shared_ptr<const TrialSetup> setup_;
};

/// Finds what `clip` (a camera file, a video file, or a folder of numbered images) shows and
/// writes the trial.json text for the trial folder `trial_dir` (the clip referenced relative
/// to it, never copied or modified). Throws std::runtime_error naming the file for an
/// unreadable clip, a clip without frame rate; throws SetupRefused for one without a body
/// that can be measured.
TrialSetup SetUpTrial(const std::filesystem::path& clip, const std::filesystem::path& trial_dir,
                      const TrialSetupOptions& options);

/// The files of the trial folder besides the contact sheet, name and bytes: trial.json, and for
/// a ball found by its motion the background it was found against (kBackgroundFile, PNG).
std::vector<std::pair<std::string, std::string>> TrialFiles(const TrialSetup& setup);

/// The body found, in words: "markers (2 white dots)" or "ball (dark_on_bright)".
std::string BodyText(const TrialSetup& setup);

/// The contact sheet's frames are at most this many px on their longer side.
inline constexpr int kContactSheetTilePx = 320;

/// A contact sheet of the setup (src/pipeline/contact_sheet.cc): up to 12 frames (the impacts and
/// their neighbours first, then frames spread over the clip) with the body's outline, the surface
/// line and the impact frames marked, and a caption of what was found. 8-bit BGR. The frames
/// are the motion finder's thumbnails where it kept them, else read from the clip again.
cv::Mat ContactSheet(const TrialSetup& setup);

/// `image` as PNG bytes.
std::string EncodePng(const cv::Mat& image);

}  // namespace hoof::pipeline
