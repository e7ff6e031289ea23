#pragma once
/// @file
/// Replay and overlay: a trial's measured frames drawn over with what was measured and what
/// the contact model simulated, so that a reader can see where the two part.
///
/// On each frame, in the glyphs and colours every replay of hoofimpact uses
/// (compare/replay_convention.h; the report's replay draws the same): the tracked marker
/// centres (green rings), the simulated marker centres (magenta plus signs) and the simulated
/// specimen outline (magenta; the bar with its round end, or a ball's circle; a body without
/// markers has its measured and simulated centre of mass drawn instead of markers), the
/// residual of each marker (or of the centre) as an
/// arrow from the measured centre to measured + F (simulated - measured) (sky blue, F stated in
/// the legend: a 0.3 px disagreement is drawn 6 px long at F = 20), the surface line and the
/// contact point T at the simulated first touch (yellow), and a time stamp with the legend and
/// the replay's pace. Geometry is computed in W and taken to image px by
/// tracking::ImageToWorld::ToImage (scale, gravity direction, lens distortion), so every drawn
/// point is where the camera would have seen it.
///
/// The data come from the study file that `hoofimpact run` writes (docs/hdf5-schema.md:
/// `/results`, `/comparison/trials`, `/comparison/frames/<id>`) and the trial folder recorded
/// there (trial.json and its frames, read again), or its new place under a moved study folder.

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "pipeline/study_format.h"
#include "tracking/pose.h"

namespace hoof::overlay {

/// The specimen outline in the body frame B (origin E, x_B toward C; m), closed, counter-
/// clockwise: the round end of radius end_radius_m about E joined to a bar of width width_m
/// whose far end lies at length_m - end_radius_m along x_B. Consecutive points are at most
/// `max_step_m` apart (> 0), so that lens distortion bends long edges correctly. Without
/// length_m or width_m (0: not given) the outline is the round end's circle alone.
std::vector<Eigen::Vector2d> OutlineInBody(const pipeline::SpecimenSpec& specimen,
                                           double max_step_m);

/// A body point p_B (m, in B) in the image (px) for the pose of C in W (p_WC in m, theta_W_rad
/// the angle of x_B from x_W): p_WE = p_WC - d_EC (cos theta, sin theta), p_W = p_WE + R(theta)
/// p_B, then camera.ToImage(p_W).
Eigen::Vector2d BodyPointToImage(const Eigen::Vector2d& p_B, const Eigen::Vector2d& p_WC,
                                 double theta_W_rad, double d_EC_m,
                                 const tracking::ImageToWorld& camera);

/// The specimen outline (OutlineInBody with a step of 0.2 mm) in the image for a pose of C.
std::vector<Eigen::Vector2d> OutlineToImage(const pipeline::SpecimenSpec& specimen,
                                            const Eigen::Vector2d& p_WC, double theta_W_rad,
                                            const tracking::ImageToWorld& camera);

/// What is drawn on one frame; NaN coordinates are not drawn.
struct FrameOverlay {
  int frame = 0;                                 ///< frame index (0 = first frame of the trial)
  double t_since_impact_s = 0.0;                 ///< NaN when the impact time is unknown
  std::vector<Eigen::Vector2d> markers_meas_px;  ///< tracked centres; NaN where not found
  std::vector<Eigen::Vector2d> markers_sim_px;   ///< simulated centres (same order)
  std::vector<Eigen::Vector2d> outline_sim_px;   ///< simulated outline (closed polygon)
  bool has_contact = false;                      ///< draw T and the surface line
  Eigen::Vector2d contact_px{0, 0};              ///< T at the simulated first touch
  Eigen::Vector2d surface_a_px{0, 0}, surface_b_px{0, 0};  ///< two points of the surface line
  double marker_radius_px = 6.0;  ///< the glyphs' size unit (compare::replay::Glyph::size)
  /// The glyphs mark the centre of mass C (one measured, one simulated), not markers: a body
  /// without markers (a ball, drawn as its circle, or an unmarked outline).
  bool centre_of_mass = false;
  /// Magnification F of the residual arrows (measured -> measured + F (simulated - measured),
  /// for each marker with both centres); 0 = no arrows.
  int residual_scale = 0;
  std::string pace;   ///< the replay's pace for the legend (VideoPace::Legend()); "" = none
  std::string title;  ///< e.g. the trial id
  /// The image corner the legend is written in, on a darkened box: 0 top left, 1 top right,
  /// 2 bottom left, 3 bottom right (RenderTrialOverlay picks the one that hides the fewest
  /// markers over the trial: LegendCorner).
  int legend_corner = 0;
};

/// The legend DrawOverlay writes on a frame, line by line, with each line's colour (BGR).
std::vector<std::pair<std::string, cv::Scalar>> OverlayLegend(const FrameOverlay& overlay);

/// The box of the legend of `overlay` on an image of `size` (px), in its legend_corner.
cv::Rect LegendRect(const cv::Size& size, const FrameOverlay& overlay);

/// The legend corner (FrameOverlay::legend_corner) for frames of `size` that covers the fewest
/// drawn points over all of `frames`: measured and simulated centres, the residual arrows'
/// ends, the outline; the first such corner in the order top left, top right, bottom left,
/// bottom right.
int LegendCorner(const cv::Size& size, const std::vector<FrameOverlay>& frames);

/// A colour (BGR, 8-bit) copy of `frame` (one channel of any depth, or 3 channels) with
/// `overlay` drawn on it. Line widths and text scale grow with the image size.
cv::Mat DrawOverlay(const cv::Mat& frame, const FrameOverlay& overlay);

/// The video's frame rate at most, and at least where captured frames are shown repeatedly.
inline constexpr double kMaxVideoFps = 60.0;
inline constexpr double kMinVideoFps = 20.0;

/// How a video replays a capture `slowdown` times slower than real time.
struct VideoPace {
  double video_fps = 0;  ///< frames per second of the video file
  int repeats = 1;       ///< each captured frame is written this many times
  double slowdown = 0;   ///< the video's pace: capture_fps * repeats / video_fps
  bool limited = false;  ///< slower than asked: the asked pace needs more than kMaxVideoFps
  /// "1/1000 of real time, 8 frames/s" (captured frames per second of video).
  std::string Legend() const;
};

/// The pace of a video of a capture at `capture_fps` (> 0) replayed `slowdown` (>= 1) times
/// slower than real time: captured frames r = capture_fps / slowdown per video second. With r
/// above kMaxVideoFps, the video runs at kMaxVideoFps, each frame once, slower than asked
/// (limited). Otherwise each frame is written the fewest times k that lifts the video's rate
/// k r to at least kMinVideoFps, and the video runs at k r: exactly the asked pace.
/// Throws std::invalid_argument for a capture_fps or a slowdown out of range.
VideoPace PlanVideo(double capture_fps, int slowdown);

/// Settings of RenderTrialOverlay.
struct OverlayOptions {
  std::filesystem::path output_dir = "overlay";  ///< frames go to output_dir/<group>/
  /// The video replays the capture this many times slower than real time (>= 1; PlanVideo):
  /// 1000 shows an 8000 fps capture at 8 frames per second (each frame thrice, at 24 fps).
  int slowdown = 1000;
  /// Magnification of the residual arrows (compare::replay::kDefaultResidualScale; 1..1000).
  int residual_scale = 20;
  /// The study folder's place, when it has moved since the study file was written: the trial
  /// folder is looked for there when it is not at its recorded path
  /// (compare::replay::LocateTrialFolder). Empty = only where recorded.
  std::filesystem::path study_dir;
  bool write_frames = true;  ///< PNG per frame (frame_000012.png): stepping frame by frame
  bool write_video = true;   ///< overlay.webm (VP8) or, without that encoder, overlay.avi (MJPG)
  /// Throws std::invalid_argument naming the field.
  void Validate() const;
};

/// What RenderTrialOverlay wrote.
struct OverlaySummary {
  std::filesystem::path dir;  ///< output_dir/<group>
  int frames = 0;             ///< frames rendered
  std::vector<std::filesystem::path> frame_files;
  std::filesystem::path video;        ///< empty when no video was written
  std::string video_format;           ///< "WebM (VP8)", "AVI (MJPG)" or "" (none)
  VideoPace pace;                     ///< the video's pace
  std::filesystem::path trial_dir;    ///< where the trial's frames were read
  std::vector<std::string> warnings;  ///< e.g. no video encoder
};

/// Renders the overlay of trial `trial_id` of the study file `study_h5` (written by
/// `hoofimpact run`). The output folder output_dir/<group> is built in a temporary folder
/// beside it and renamed into place when complete (an existing one is replaced). Throws
/// std::runtime_error naming the file and the id for an unknown trial, a file without
/// `/comparison` ("run `hoofimpact run` first"), a trial that was not compared, or missing
/// frames (naming every folder looked at).
OverlaySummary RenderTrialOverlay(const std::filesystem::path& study_h5,
                                  const std::string& trial_id, const OverlayOptions& options);

}  // namespace hoof::overlay
