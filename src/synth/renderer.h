#pragma once
/// @file
/// The synthetic high-speed trial renderer (docs/synthetic-trials.md). It samples the dynamics
/// library's ImpactSimulator at the frame and exposure sub-sample times, draws each frame as a
/// camera would record it, and writes a trial folder per docs/format.md: trial.json,
/// frames/%06d.png (or one MRAW or CINE clip) and truth.json. It draws; it never detects.

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "dynamics/impact_simulator.h"
#include "synth/contact_draw.h"
#include "synth/options.h"
#include "synth/projection.h"
#include "synth/specimen_texture.h"
#include "synth/surface_scene.h"

namespace hoof::synth {

/// Read-only drawings shared by the trials of a study (one specimen, one block per surface).
struct SceneAssets {
  SpecimenTexture specimen;
  std::vector<SurfaceTexture> surfaces;  ///< At most one per surface.
  const SurfaceTexture& Surface(dynamics::Surface surface) const;
};

/// Draws the specimen texture and the blocks of `surfaces` from `seed`.
SceneAssets BuildSceneAssets(const SpecimenGeometry& geometry, const RenderOptions& options,
                             const std::vector<dynamics::Surface>& surfaces, std::uint64_t seed);

/// Ground truth of one written frame.
struct FrameTruth {
  int capture_index = 0;  ///< Index of the capture shown (differs from the file's index after
                          ///< dropped frames).
  double t_s = 0.0;       ///< Mid-exposure time since capture 0 (s).
  /// The capture slot this frame was written in, and its time slot_index / fps: what a camera's
  /// clock stamps on the frame (a CINE's time stamp). Equal to capture_index and t_s except on
  /// a duplicate, which repeats the previous image in the slot of the capture it lost.
  int slot_index = 0;
  double stamp_s = 0.0;
  BodyPose pose;                            ///< Pose at t_s.
  Eigen::Vector2d p_WC{0.0, 0.0};           ///< Centre of mass in W (m).
  std::string phase;                        ///< Contact phase at t_s (dynamics::ToString).
  std::string defect;                       ///< "", "dropped_before" or "duplicate".
  std::vector<Eigen::Vector2d> markers_px;  ///< Recorded (distorted) image.
  std::vector<Eigen::Vector2d> markers_px_undistorted;  ///< Ideal image.
  /// Image of the centre of mass C at t_s (the ball's centre), recorded and ideal (px).
  Eigen::Vector2d center_px{0.0, 0.0}, center_px_undistorted{0.0, 0.0};
  /// Flicker: the light's brightness averaged over this frame's exposure (1 without flicker).
  double light_factor = 1.0;
  int impact = 0;  ///< Index into TrialTruth::impacts of the impact whose segment holds t_s.
};

/// One impact of a clip (several with TrialSpec::bounces > 1).
struct ImpactTruth {
  double touch_time_s = 0.0;  ///< Since capture 0 (s).
  /// Where the contact point of this touch lies on the surface line: x along x_S from the
  /// first touch (m). The impact's own S frame is the first one shifted by this.
  double x_S_m = 0.0;
  dynamics::ImpactResult result;  ///< In the impact's own S and time; without samples.
};

/// Everything known about a rendered trial.
struct TrialTruth {
  TrialSpec spec;
  ContactDraw draw;
  dynamics::ImpactResult impact;         ///< Without samples.
  double impact_time_s = 0.0;            ///< First touch since capture 0 (s).
  Eigen::Vector2d contact_px{0.0, 0.0};  ///< Ideal image position of W's origin (px).
  double surface_u_offset_px = 0.0;
  std::array<Eigen::Vector2d, 2> surface_line_px;  ///< Two points on the surface, recorded image.
  std::vector<FrameTruth> frames;
  /// Per written frame, the poses integrated over the exposure (one without motion blur).
  std::vector<std::vector<BodyPose>> exposure_poses;
  int first_frame_after_touch = 0;          ///< Index of the first written frame with t_s >= touch.
  std::vector<ImpactTruth> impacts;         ///< Every impact in time order; [0] is `impact`.
  std::vector<int> dropped_captures;        ///< Captures never written (their times are skipped).
  double flicker_phase_rad = 0.0;           ///< psi of the flicker (0 without flicker).
  int blur_samples_used = 1;                ///< Sub-samples per exposure actually drawn.
  int frames_before = 0, frames_after = 0;  ///< The clip's counts (from flight, or the options').
};

/// Samples the model at the capture and exposure times and places the scene in the frame:
/// everything about a trial except its pixels. Throws std::invalid_argument for invalid
/// settings and std::runtime_error when the simulation fails.
TrialTruth PlanTrial(const TrialSpec& spec, const SpecimenGeometry& geometry,
                     const RenderOptions& options);

/// A rendered trial.
struct TrialResult {
  TrialTruth truth;
  std::filesystem::path path;   ///< The trial folder.
  double render_seconds = 0.0;  ///< Wall time of PlanTrial, drawing and writing.
};

/// Renders a trial into the folder `trial_dir`. The folder is written under a temporary name
/// beside it and renamed when complete, so a crash never leaves half a trial. An existing
/// folder is replaced only when `overwrite` is true; otherwise std::runtime_error names it.
/// `in_study`: the trial is one of a study, whose study.json defines its specimen (a ball's
/// trial.json then names the study's ball; alone, a ball is its own specimen of unknown mass,
/// as a clip from a phone).
TrialResult RenderTrial(const TrialSpec& spec, const SpecimenGeometry& geometry,
                        const RenderOptions& options, const SceneAssets& assets,
                        const std::filesystem::path& trial_dir, bool overwrite = false,
                        bool in_study = false);

/// Writes one frame of a trial: frames/%06d.png under `trial_dir` (8- or 16-bit grey PNG).
void WriteFrame(const std::filesystem::path& trial_dir, int index, const cv::Mat& image,
                const RenderOptions& options);

/// The clip file of a trial in a camera-file format ("clip.mraw", "clip.cine"); "" for PNG.
std::string ClipFileName(FrameFormat format);

/// Writes the frames of one trial in options.frame_format, one frame at a time in index order
/// (never the whole clip in memory): PNG files through WriteFrame, or one camera file through
/// tracking/camera_file.h's MrawWriter or CineWriter with the trial's frame rate, size, bit
/// depth, shutter (the exposure) and, for CINE, each frame's stamp_s. The camera file is
/// written under a temporary name and renamed by Finish(); a writer destroyed before Finish()
/// leaves nothing.
class FrameWriter {
 public:
  /// Throws std::invalid_argument for a bad frame count or size (checked by the writers).
  FrameWriter(const std::filesystem::path& trial_dir, const TrialTruth& truth,
              const RenderOptions& options);
  ~FrameWriter();
  FrameWriter(const FrameWriter&) = delete;
  FrameWriter& operator=(const FrameWriter&) = delete;
  /// Frame `index` (0, 1, 2, ... in order): one channel, CV_8U at 8 bits, else CV_16U.
  void Write(int index, const cv::Mat& image);
  void Finish();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Frames of a planned trial as 8- or 16-bit grey images, without writing them.
std::vector<cv::Mat> RenderFrames(const TrialTruth& truth, const SpecimenGeometry& geometry,
                                  const RenderOptions& options, const SceneAssets& assets);

}  // namespace hoof::synth
