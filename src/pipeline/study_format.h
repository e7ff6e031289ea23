#pragma once
/// @file
/// Reading trial and study folders (docs/format.md, the input contract). Errors name the file
/// and the field; unknown fields are reported as warnings and otherwise ignored.

#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/specimen.h"
#include "tracking/frame_source.h"

namespace hoof::pipeline {

/// What a specimen is: the hoof-wall specimen (a bar with a round end, the paper's) or a ball.
enum class SpecimenShape {
  kBar,   ///< study.json's specimen without "shape": mass, inertia, R and d given
  kBall,  ///< "shape": "ball": R half its diameter, its centre of mass at its centre (d = 0)
};

/// Where a ball's moment of inertia about its centre comes from (study.json's "inertia").
enum class BallInertia {
  kSolid,    ///< "solid": I = 2/5 m R^2 (the default)
  kHollow,   ///< "hollow": a thin shell, I = 2/3 m R^2
  kGiven,    ///< a number (kg m^2), at most 2/3 m R^2
  kUnknown,  ///< a ball without a specimen (trial.json names none): mass and inertia unknown
};

/// "solid", "hollow", "given" or "unknown".
std::string BallInertiaName(BallInertia inertia);

/// I / (m R^2) of a ball whose inertia is `inertia` (solid 2/5, hollow 2/3); NaN for kGiven and
/// kUnknown.
double BallInertiaFactor(BallInertia inertia);

/// A specimen of study.json: the rigid body (the project's one specimen type) and what the
/// camera sees of it. A ball's mass may be unknown (NaN, and its inertia then NaN too):
/// velocities, e and mu_eff do not need it; kinetic energies and the contact law's k and b do.
struct SpecimenSpec : core::SpecimenParameters {
  SpecimenShape shape = SpecimenShape::kBar;
  BallInertia inertia = BallInertia::kSolid;                ///< a ball's; unused for the bar
  double length_m = 0.0, width_m = 0.0, thickness_m = 0.0;  ///< 0 when not given
  /// Centres of the white dots in the body frame B (origin E, x toward C), in metres, in the
  /// order of the file.
  std::vector<std::pair<std::string, Eigen::Vector2d>> markers_B_m;

  bool is_ball() const { return shape == SpecimenShape::kBall; }
  /// The mass (and with it the inertia) is known: a number, not NaN.
  bool mass_known() const { return std::isfinite(mass_kg) && std::isfinite(inertia_kg_m2); }
};

/// A calibration image of trial.json's camera (docs/format.md, "The scale"): a checkerboard or a
/// ruler lying in the plane of motion, in an image file or a frame of the clip.
struct CalibrationImageSpec {
  std::string image;  ///< PNG/TIFF file relative to the trial folder; empty when `frame` is used
  int frame = -1;     ///< else a frame of the clip (0-based, among the frames trial.json selects)
  /// Checkerboard: inner corners per row (cols) and per column (rows), and the square's side.
  int cols = 0, rows = 0;
  double square_m = 0.0;
  /// Ruler: two points on it (recorded image px), the ticks crossing the segment between them,
  /// and the tick spacing.
  Eigen::Vector2d from_px{0.0, 0.0}, to_px{0.0, 0.0};
  double tick_m = 0.0;
};

/// Camera of trial.json.
struct CameraSpec {
  /// Scale in the plane of motion; 0 when trial.json gives none (a ball's `body.diameter_m`
  /// gives it then).
  double m_per_px = 0.0;
  /// Where the scale comes from (docs/format.md, "The scale"): "m_per_px" (stated),
  /// "body_diameter" (a ball's diameter_m), "markers" (the marker spacing), "gravity" (the
  /// free-flight parabola at the frame rate), "checkerboard" or "ruler" (a calibration image);
  /// empty: m_per_px where given, else a ball's diameter.
  std::string scale_from;
  std::optional<CalibrationImageSpec> checkerboard, ruler;  ///< camera.checkerboard, camera.ruler
  Eigen::Vector2d gravity_image{0.0, 1.0};             ///< unit direction of gravity in the image
  std::optional<std::array<double, 5>> distortion;     ///< OpenCV k1 k2 p1 p2 k3
  std::optional<std::array<double, 9>> camera_matrix;  ///< row-major 3x3
};

/// Where the frames are: an image sequence, a video file or a camera file.
struct FramesSpec {
  std::string pattern;  ///< printf pattern relative to the trial folder, e.g. frames/%06d.png
  /// Pattern: the first frame's number. Camera file: the first frame used (0-based).
  int first = 0;
  /// Pattern: the number of frames. Camera file: the frames used (all from `first` on when
  /// trial.json does not say).
  int count = 0;
  std::string video;  ///< video file relative to the trial folder (instead of a pattern)
  /// Camera file (.mraw/.cihx/.cih, .cine, .tif/.tiff) relative to the trial folder
  /// (tracking/camera_file.h), instead of a pattern.
  std::string camera_file;
  bool is_video() const { return !video.empty(); }
  bool is_camera_file() const { return !camera_file.empty(); }
  /// The pattern, video or camera file, as trial.json names it.
  const std::string& Source() const {
    return is_camera_file() ? camera_file : is_video() ? video : pattern;
  }
};

/// How the body is tracked: trial.json's optional "body" (docs/format.md). Without it, by its
/// markers.
struct BodySpec {
  std::string model = "markers";  ///< "markers" or "silhouette"
  std::string shape;              ///< silhouette: "ball" or "outline"
  /// Silhouette: "auto", "dark_on_bright" (back-lit) or "bright_on_dark".
  std::string polarity = "auto";
  /// Ball: its known diameter, a scale (m per px = diameter_m / fitted diameter in px); 0 when
  /// not given.
  double diameter_m = 0.0;
  /// Ball: how it is found in the frames: "shape" (the silhouette of one polarity) or "motion"
  /// (against the clip's background, its path ballistic: pipeline/moving_body.h).
  std::string find = "shape";
  /// find "motion": the background image relative to the trial folder (init writes it); empty:
  /// made from the clip (one more pass over its frames).
  std::string background;
  /// find "motion": the ball's colour (0..255 each) and apparent diameter (px) as cues for
  /// choosing among moving paths; nullopt and 0 where not given.
  std::optional<Eigen::Vector3d> rgb;
  double diameter_px = 0.0;
  bool is_silhouette() const { return model == "silhouette"; }
  bool by_motion() const { return is_silhouette() && find == "motion"; }
  bool is_ball() const { return is_silhouette() && shape == "ball"; }
};

/// One trial: trial.json plus its specimen from study.json.
struct TrialSpec {
  std::filesystem::path dir;
  std::string id;
  std::string specimen_id;
  SpecimenSpec specimen;
  std::string surface;
  double surface_angle_deg = 0.0;
  double fps = 0.0;
  FramesSpec frames;
  CameraSpec camera;
  /// The body model. A ball needs no specimen: without one, the ball is the specimen (radius
  /// diameter_m / 2, centre of mass at its centre, mass and inertia unknown: NaN).
  BodySpec body;
  /// Where the specimen was defined, for messages: "S/study.json, specimens.A",
  /// "S/t1/trial.json, specimen_parameters" or "S/t1/trial.json (a ball without a specimen)".
  std::string specimen_origin;
  std::optional<std::array<Eigen::Vector2d, 2>> surface_line_px;
  std::optional<double> nominal_speed_m_s;
  std::string notes;
  std::vector<std::string> warnings;  ///< unknown fields and the like, with file names
};

/// A study: study.json and the trial folders it lists (or every sub-folder with a trial.json).
struct StudySpec {
  std::filesystem::path dir;
  std::string name;
  std::map<std::string, SpecimenSpec> specimens;
  std::vector<std::filesystem::path> trial_dirs;
  std::vector<std::string> warnings;
};

/// Opens the frames of a trial: its image sequence, video, or camera file (the range that
/// trial.json selects). Throws std::runtime_error naming the file.
std::unique_ptr<tracking::FrameSource> OpenFrames(const TrialSpec& spec);

/// Reads `dir/study.json`. Throws std::runtime_error naming the file and the field.
StudySpec ReadStudy(const std::filesystem::path& dir);

/// Reads `trial_dir/trial.json` and takes its specimen from `study`. Throws
/// std::runtime_error naming the file and the field (also for a specimen the study lacks).
TrialSpec ReadTrial(const std::filesystem::path& trial_dir, const StudySpec& study);

/// Reads a trial on its own: the study is `study_json` if given, else study.json in the
/// trial's parent folder.
TrialSpec ReadTrial(const std::filesystem::path& trial_dir,
                    const std::optional<std::filesystem::path>& study_json = std::nullopt);

}  // namespace hoof::pipeline
