#pragma once
/// @file
/// The static room of an everyday clip, drawn once by ray casting (2 x 2 rays a pixel): a back
/// wall with a colour gradient, the floor (wooden planks) or a table top on which the ball
/// lands, and with clutter a side wall (a corner), a skirting board, shelves with books, a tin
/// and a box, a picture, a plant pot and a box on the floor, and a ruler on the floor; one
/// ceiling light whose light falls off with distance and angle, plus ambient light darkened
/// near the wall-floor junction and under things. Colours are linear BGR.

#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "synth/footage_options.h"
#include "synth/pinhole_camera.h"

namespace hoof::synth {

/// The ceiling light and the room's ambient light, shared by the room, the ball and the hand.
/// Irradiance is relative: 1 (times brightness) on the contact surface below the release point.
class RoomLight {
 public:
  RoomLight(const RoomOptions& room, const Eigen::Vector3d& reference_W);
  const Eigen::Vector3d& p_W() const { return p_W_; }
  double radius_m() const { return radius_; }
  /// The light's direct share at p with unit normal n (0 when it faces away).
  double Direct(const Eigen::Vector3d& p, const Eigen::Vector3d& n) const;
  /// The ambient share (times `occlusion`, 1 in the open).
  double Ambient(double occlusion = 1.0) const { return ambient_ * occlusion; }

 private:
  Eigen::Vector3d p_W_;
  double radius_ = 0.0, ambient_ = 0.0, direct_scale_ = 0.0;
};

/// The room as the camera sees it.
struct RoomImage {
  cv::Mat linear;  ///< CV_32FC3, linear BGR: the room without the ball, its shadow or the hand.
  /// CV_32FC3: the part of `linear` that the light gives to the contact surface (y_W = 0, the
  /// surface the ball lands on, and the ruler lying on it); 0 elsewhere. The ball's shadow takes
  /// away its share of this.
  cv::Mat direct;
};

/// Draws the room of `spec` through `camera`, lit by `light`, on `jobs` threads (0 = all
/// cores; the pixels do not depend on it).
RoomImage RenderRoom(const FootageSpec& spec, const PinholeCamera& camera, const RoomLight& light,
                     int jobs = 1);

/// Fraction of a disc light of radius `light_radius` at `light` hidden from the point p by a
/// sphere (centre c, radius r): the overlap of the two discs as seen from p (angular radii
/// asin(radius / distance), centres apart by the angle between the directions), over the
/// light's disc. In [0, 1]; the shadow's soft edge is the penumbra.
double ShadowFraction(const Eigen::Vector3d& p, const Eigen::Vector3d& light, double light_radius,
                      const Eigen::Vector3d& c, double r);

}  // namespace hoof::synth
