#pragma once
/// @file
/// The hand of an everyday clip: a skin-coloured palm, four fingers, a thumb and a forearm,
/// drawn as a flat cut-out parallel to the image plane just in front of the ball. It grips the
/// ball from above (the fingers cover its top), follows it while it carries a throw, lets go at
/// the release time and withdraws (HandOptions::leave_speed_m_s along leave_direction,
/// accelerating at 4 m/s^2) until it leaves the view. For kHandOnly it comes down into view
/// during the first release_time_s, stays 0.3 s and leaves the same way.

#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "synth/ball_flight.h"
#include "synth/footage_options.h"
#include "synth/pinhole_camera.h"

namespace hoof::synth {

/// A round-ended stroke in the image (px).
struct Capsule {
  Eigen::Vector2d a{0.0, 0.0}, b{0.0, 0.0};
  double radius_px = 0.0;
};

/// The hand's outline in the image at one time.
struct HandShape {
  bool present = false;
  std::vector<Capsule> parts;  ///< Fingers, thumb, palm (as a fat stroke) and forearm.
  Eigen::Vector3d p_W_m = Eigen::Vector3d::Zero();  ///< The grip point in W.
  cv::Rect bounds;  ///< Pixels it may touch (may lie partly outside the image).
  /// Signed distance from (x, y) to the outline (px, < 0 inside), and in `shade` how far the
  /// point is from the nearest part's rim (1 on its axis, 0 on its edge).
  double Distance(double x_px, double y_px, double* shade = nullptr) const;
  /// Whether any part of the outline lies inside the image [-0.5, w - 0.5] x [-0.5, h - 0.5].
  bool InView(int width_px, int height_px) const;
};

/// The hand's path through the clip.
class HandModel {
 public:
  /// Keeps copies of `path` and `camera`. No hand unless spec.hand.enabled and the scenario is
  /// kBounce, kNeverLands or kHandOnly.
  HandModel(const FootageSpec& spec, const BallPath& path, const PinholeCamera& camera);
  bool present() const { return present_; }
  /// The grip point in W at t (s).
  Eigen::Vector3d GripAt(double t_s) const;
  /// The outline at t.
  HandShape ShapeAt(double t_s) const;
  /// Linear RGB of the skin.
  const Eigen::Vector3d& skin_rgb() const { return skin_; }

 private:
  Eigen::Vector3d Withdraw(const Eigen::Vector3d& from, double since_s) const;
  bool present_ = false;
  bool hand_only_ = false;
  BallPath path_;
  PinholeCamera camera_;
  Eigen::Vector3d grip_offset_ = Eigen::Vector3d::Zero();  ///< From the ball's centre.
  Eigen::Vector3d rest_ = Eigen::Vector3d::Zero();         ///< kHandOnly: where it pauses.
  Eigen::Vector3d away_ = Eigen::Vector3d::UnitY();        ///< Unit direction of withdrawal.
  double leave_speed_ = 1.0, release_s_ = 0.0, leave_s_ = 0.0;
  Eigen::Vector3d skin_ = Eigen::Vector3d::Zero();
};

}  // namespace hoof::synth
