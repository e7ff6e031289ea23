#pragma once
/// @file
/// The known truth of an everyday clip (docs/synthetic-trials.md, "Everyday footage truth"):
/// plain data on the standard library and Eigen. Image quantities are in the frames as they
/// are delivered upright (OpenCV with the rotation tag applied), in px with the origin at the
/// centre of the top-left pixel; world quantities are in W (x right, y up, z toward the
/// camera, the contact surface at y = 0), SI.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "synth/ball_flight.h"
#include "synth/footage_options.h"
#include "synth/footage_timing.h"

namespace hoof::synth {

/// The truth file's format string.
inline constexpr const char* kFootageTruthFormat = "hoofimpact-footage-truth/1";

/// How much of the ball a frame shows.
enum class BallVisibility {
  kAbsent,           ///< No ball in the clip.
  kOutOfView,        ///< No part of its image lies in the frame.
  kOccluded,         ///< Part of it is behind the hand.
  kPartlyOutOfView,  ///< Cut by the frame's edge, not behind the hand.
  kVisible,          ///< Whole and uncovered.
};
/// "absent", "out_of_view", "occluded", "partly_out_of_view" or "visible".
const char* ToString(BallVisibility visibility);

/// The ball in one delivered frame, at the mid-exposure time of the capture it shows (not
/// blurred).
struct FootageFrameTruth {
  DeliveredFrame frame;
  BallPhase phase = BallPhase::kAbsent;
  int arc = 0;  ///< Bounces before t_s: 0 on the drop, 1 after the first bounce, ...
  Eigen::Vector3d p_WC_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_WC_m_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_W_rad_s = Eigen::Vector3d::Zero();
  bool image_valid = false;  ///< The sphere is wholly in front of the camera.
  /// Centre of the ball's true image (the ellipse's centre, = its centroid) and the projection
  /// of the ball's centre, which differs off the optical axis (px).
  Eigen::Vector2d center_px{0.0, 0.0}, projection_px{0.0, 0.0};
  double radius_px = 0.0;  ///< sqrt(semi_major * semi_minor).
  double semi_major_px = 0.0, semi_minor_px = 0.0, major_angle_rad = 0.0;
  double m_per_px = 0.0;  ///< At the ball centre's depth: depth / focal.
  BallVisibility visibility = BallVisibility::kAbsent;
  double in_view_fraction = 0.0;  ///< Of the ball's image area, inside the frame.
  double occluded_fraction =
      0.0;  ///< Of the ball's image area, inside the frame and under the hand.
  double visible_fraction = 0.0;  ///< in_view - occluded.
  bool hand_in_view = false;
  int blur_samples = 1;  ///< Sub-frame samples the capture was drawn with.
};

/// One bounce, in W and in the delivered image.
struct FootageBounceTruth {
  BallBounce world;
  Eigen::Vector2d contact_px{0.0, 0.0};  ///< Image of the contact point.
  Eigen::Vector2d center_px{0.0, 0.0};   ///< Centre of the ball's image at contact.
  double radius_px = 0.0;
  /// d(center_px)/dt just before and just after the contact (px/s).
  Eigen::Vector2d v_before_px_s{0.0, 0.0}, v_after_px_s{0.0, 0.0};
  /// The contact point is inside the frame and at least half the ball's image is too.
  bool in_view = false;
  int first_frame_after = -1;  ///< First delivered frame with t_s >= the contact (-1: none).
};

/// Everything known about a rendered clip.
struct FootageTruth {
  FootageSpec spec;
  int width_px = 0, height_px = 0;                ///< Delivered (upright).
  int stored_width_px = 0, stored_height_px = 0;  ///< As stored in the file (turned by the tag).
  double focal_px = 0.0;
  Eigen::Vector2d principal_point_px{0.0, 0.0};
  Eigen::Matrix3d R_CW = Eigen::Matrix3d::Identity();
  FrameSchedule schedule;
  double release_time_s = 0.0, carry_start_s = 0.0;  ///< NaN without a release.
  double settle_time_s = 0.0, rolling_time_s = 0.0;  ///< NaN when they do not happen.
  /// The point that scale and gravity's direction refer to: the ball's centre at the first
  /// bounce, else at release, else at rest, else the hand's pause point.
  Eigen::Vector3d reference_p_W_m = Eigen::Vector3d::Zero();
  double m_per_px = 0.0;                    ///< At the reference point's depth.
  Eigen::Vector2d gravity_image{0.0, 1.0};  ///< Unit direction of -y_W in the image there.
  Eigen::Vector2d reference_px{0.0, 0.0};   ///< The reference point's image.
  /// Where the contact surface meets the back wall (kFloor) or ends in front (kTable, its
  /// front edge): two image points of that line at the frame's left and right edges (px).
  std::vector<Eigen::Vector2d> surface_edge_px;
  std::vector<FootageFrameTruth> frames;
  std::vector<FootageBounceTruth> bounces;
};

}  // namespace hoof::synth
