#pragma once
/// @file
/// The body found by its motion (docs/tracking.md, "Finding the body by its motion"): of the
/// paths of what moves against the clip's own background (tracking/motion_blobs.h), the body
/// is the one whose path is ballistic between contacts, its arcs sharing one acceleration. A
/// still object is not in the motion at all; a hand that moves and leaves, or a shadow that
/// slides along the floor, is refused with its reason. Colour and size are cues, taken from the
/// body's own regions, or stated (`--color`, a known apparent diameter) to choose among paths.
/// The pieces of the body's path that the linking broke (the ball left the view, or was hidden)
/// are joined where the whole stays ballistic. The ball's centre is then measured to sub-pixel
/// accuracy on the likeness image, and the arcs give the direction of "down".

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "kinematics/flight_arcs.h"
#include "tracking/motion_blobs.h"
#include "tracking/silhouette_tracker.h"

namespace hoof::pipeline {

/// What a moving path was judged to be.
enum class CandidateVerdict {
  kBody,          ///< the body
  kJoined,        ///< a piece of the body's path (it left the view or was hidden between)
  kTooShort,      ///< seen in too few frames to test its motion
  kStill,         ///< it hardly moves (flicker, a door ajar, compression)
  kNoFall,        ///< no acceleration beyond its noise: it slides or drifts, it does not fall
  kNotBallistic,  ///< its path does not follow arcs of one acceleration (a hand, a person)
  kNotDown,       ///< it accelerates up or sideways in the upright frames: not falling
  kNotLikeBody,   ///< its colour or size is not the one stated
  kLessLikely,    ///< ballistic too, but another path explains more frames with more contrast
};

/// "body", "joined", "too_short", "still", "no_fall", "not_ballistic", "not_down",
/// "not_like_body", "less_likely".
const char* CandidateVerdictName(CandidateVerdict verdict);

/// One moving path and what it was judged to be.
struct MovingCandidate {
  int path = -1;  ///< index in MotionScene::paths
  int first_frame = -1, last_frame = -1, regions = 0;
  Eigen::Vector2d p_first_I{0, 0}, p_last_I{0, 0};  ///< where it was first and last seen (px)
  double travel_px = 0.0, diameter_px = 0.0, likeness = 0.0;
  Eigen::Vector3d rgb{0, 0, 0};
  /// Its joint arc fit (px, times from the frame rate): samples on fitted arcs over all,
  /// the acceleration (px/s^2) and its significance, its angle from the image's down (deg),
  /// the rms residual (px). NaN where not fitted.
  double arc_fraction = 0.0, a_px_s2 = 0.0, a_sigmas = 0.0, down_angle_deg = 0.0, rms_px = 0.0;
  int arcs = 0;
  double score = 0.0;  ///< frames on arcs x contrast: the body has the highest
  CandidateVerdict verdict = CandidateVerdict::kTooShort;
  std::string reason;  ///< the verdict in words, with its numbers
};

/// Settings of the choice.
struct MovingBodyOptions {
  /// The body's colour (0..255 each), where stated (`--color`): a path whose median colour lies
  /// farther from it than `max_colour_distance` is not the body.
  std::optional<Eigen::Vector3d> rgb;
  double max_colour_distance = 90.0;
  /// The body's apparent diameter (px), where known: a path whose median size differs from it
  /// by more than the factor `max_size_ratio` is not the body; 0: not known.
  double diameter_px = 0.0;
  double max_size_ratio = 1.8;
  /// A path seen in fewer frames is not tested; >= 4.
  int min_frames = 6;
  /// A path that moves less than this many of its own diameters is still; > 0.
  double min_travel_diameters = 1.5;
  /// Ballistic: at least this fraction of its frames on fitted arcs, and a residual of at most
  /// max(min_rms_px, max_rms_diameters x its diameter); in (0, 1], > 0, > 0.
  double min_arc_fraction = 0.6;
  double min_rms_px = 1.5;
  double max_rms_diameters = 0.08;
  /// The acceleration must exceed this many of its standard errors (else it does not fall); > 0.
  double min_a_sigmas = 5.0;
  /// ... and point within this angle of the upright frame's down (deg); in (0, 180].
  double max_down_angle_deg = 60.0;
  /// A ball whose apparent size changes by more than this fraction between its first and its
  /// last arc moves in depth: a warning, as it biases e; > 0.
  double depth_warning_fraction = 0.08;
  tracking::MotionOptions motion;
  tracking::SilhouetteOptions silhouette;

  /// Throws std::invalid_argument naming the field.
  void Validate() const;
};

/// The outcome.
struct MovingBody {
  bool found = false;
  /// Why no body was found: what failed, naming the frames ("no moving body", "no path with
  /// enough frames", "no path is ballistic"); empty when found.
  std::string message;
  tracking::MotionScene scene;
  std::vector<MovingCandidate> candidates;  ///< every path tested, the body first
  tracking::MotionPath path;                ///< the body's regions (pieces joined)
  tracking::SilhouetteTrack track;          ///< the ball's sub-pixel centre, one per frame
  /// Per frame: a copy of an image another frame shows at its capture time (no sample of the
  /// motion; ballistic::CopiesOn); empty when no body was found.
  std::vector<bool> copies;
  Eigen::Vector3d rgb{0, 0, 0};  ///< the body's median colour
  double diameter_px = 0.0;      ///< its median fitted diameter
  /// The body's shape from its regions: a ball (a disc) or an elongated outline.
  bool round = true;
  /// Its arcs on the measured centres (px in W: x right, y up; times from the frame rate).
  kinematics::FlightArcs arcs;
  /// Gravity's direction in the image from the arcs' shared acceleration, and whether it was
  /// measured (else (0, 1)); its s.e. (deg).
  Eigen::Vector2d down_I{0.0, 1.0};
  bool down_measured = false;
  double down_se_deg = 0.0;
  std::vector<std::string> warnings;
};

/// Judges the paths of `scene` (frames at `fps`), picks the body and measures it. `named`
/// names the clip's frames in messages. Never throws for a clip without a body: `found` is
/// false and `message` says why; invalid options throw std::invalid_argument.
MovingBody FindMovingBody(tracking::MotionScene scene, double fps, const std::string& named,
                          const MovingBodyOptions& options = {});

/// A colour in words: "#c8283c" from 0..255 components.
std::string ColourHex(const Eigen::Vector3d& rgb);

/// Parses "#rrggbb", "rrggbb" or a common name (red, green, blue, yellow, orange, white,
/// black, pink, purple). Throws std::invalid_argument naming the text.
Eigen::Vector3d ParseColour(const std::string& text);

}  // namespace hoof::pipeline
