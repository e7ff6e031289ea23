#pragma once
/// @file
/// Replay and overlay: a trial's measured frames drawn over with what was measured and what
/// the contact model simulated, so that a reader can see where the two part.
///
/// On each frame: the tracked marker centres (green crosses), the simulated marker centres (red
/// circles), the simulated specimen outline (red; the bar with its round end), the surface line
/// and the contact point T at the simulated first touch (yellow), and a time stamp with the
/// legend. Geometry is computed in W and taken to image px by tracking::ImageToWorld::ToImage
/// (scale, gravity direction, lens distortion), so every drawn point is where the camera would
/// have seen it.
///
/// The data come from the study file that `hoofimpact run` writes (docs/hdf5-schema.md:
/// `/results`, `/comparison/trials`, `/comparison/frames/<id>`) and the trial folder recorded
/// there (trial.json and its frames, read again).

#include <filesystem>
#include <string>
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
  std::vector<Eigen::Vector2d> markers_sim_px;   ///< simulated centres
  std::vector<Eigen::Vector2d> outline_sim_px;   ///< simulated outline (closed polygon)
  bool has_contact = false;                      ///< draw T and the surface line
  Eigen::Vector2d contact_px{0, 0};              ///< T at the simulated first touch
  Eigen::Vector2d surface_a_px{0, 0}, surface_b_px{0, 0};  ///< two points of the surface line
  double marker_radius_px = 6.0;  ///< radius of the simulated markers' circles
  std::string title;              ///< e.g. the trial id
};

/// A colour (BGR, 8-bit) copy of `frame` (one channel of any depth, or 3 channels) with
/// `overlay` drawn on it. Line widths and text scale grow with the image size.
cv::Mat DrawOverlay(const cv::Mat& frame, const FrameOverlay& overlay);

/// Settings of RenderTrialOverlay.
struct OverlayOptions {
  std::filesystem::path output_dir = "overlay";  ///< frames go to output_dir/<group>/
  /// Each frame is shown `slow` times in the video (>= 1): at video_fps = 25 a frame lasts
  /// slow / 25 s; the 8000 fps capture then plays 320 * slow times slower than real time.
  int slow = 1;
  double video_fps = 25.0;   ///< frames per second of the video (> 0)
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
  std::vector<std::string> warnings;  ///< e.g. no video encoder
};

/// Renders the overlay of trial `trial_id` of the study file `study_h5` (written by
/// `hoofimpact run`). The output folder output_dir/<group> is built in a temporary folder
/// beside it and renamed into place when complete (an existing one is replaced). Throws
/// std::runtime_error naming the file and the id for an unknown trial, a file without
/// `/comparison` ("run `hoofimpact run` first"), a trial that was not compared, or missing
/// frames.
OverlaySummary RenderTrialOverlay(const std::filesystem::path& study_h5,
                                  const std::string& trial_id, const OverlayOptions& options);

}  // namespace hoof::overlay
