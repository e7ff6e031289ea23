#pragma once
/// @file
/// Whether a moving path is ballistic (pipeline/moving_body.h, docs/tracking.md, "Finding the
/// body by its motion"): its positions fitted as flight arcs sharing one acceleration (the joint
/// fit of kinematics/flight_arcs.h), or flight by flight between bounces where that explains
/// more of its frames.

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "kinematics/flight_arcs.h"
#include "tracking/motion_blobs.h"

namespace hoof::pipeline::ballistic {

/// One position per frame, in image px (nullopt where none), from `first` on.
struct Positions {
  int first = 0;
  std::vector<std::optional<Eigen::Vector2d>> p;
  std::vector<Eigen::Matrix2d> cov;  ///< empty: none
  std::vector<double> size;          ///< apparent size per frame (NaN where none)
};

/// The positions of `path`'s regions (none where a region touches the frame's edge), without
/// the frames at its start and end where it holds still (moving less than a tenth of its size
/// from one region to the next): a hand holding the ball before it lets go, a ball come to
/// rest. A release from rest would otherwise look like a contact to the arc fit.
/// Frames in `copy` (per clip frame; shorter or empty: none) are no samples.
Positions PositionsOf(const tracking::MotionPath& path, const std::vector<bool>& copy = {});

/// Per clip frame: its image is a copy that another frame shows at its capture time, and so no
/// sample of `path`'s motion. From the scene's repeats and the frames in which the path stands
/// still for a frame while it moves (tracking::AddRepeatsFromMotion), with its motion deciding
/// whether a repeated image belongs to its first or its last copy (HeldImageFromMotion).
std::vector<bool> CopiesOn(const tracking::MotionPath& path, const std::vector<bool>& repeat,
                           int frame_count);

/// The joint arc fit of positions in image px: W is x right, y up (px), times frame / fps. A
/// position equal to the one before (a repeated image) is no sample.
struct ArcStats {
  kinematics::FlightArcs fit;
  bool fitted = false;
  int on_arcs = 0, in_span = 0, arcs = 0;
  int trimmed = 0;  ///< frames left out as bent by a long contact
  /// Flights fitted one by one, each with its own parabola (PiecewiseFlights), not jointly.
  bool piecewise = false;
  double arc_fraction = 0.0, a = 0.0, a_sigmas = 0.0, down_angle_deg = 180.0, rms = core::kNaN;
  int first_arc_frame = -1, last_arc_frame = -1;  ///< clip frames
};

/// The joint arc fit of `in` (frames at `fps`); where its residual exceeds `trim_px` (> 0) and
/// it found a contact, fitted again without the frames off the arcs by more than twice that,
/// while at most 40 % of the frames are left out so (a contact that lasts several frames, on a
/// compliant surface such as a net, bends the path between arcs).
ArcStats FitArcs(const Positions& in, double fps, double trim_px = 0.0);

/// FitArcs, or the flights one by one between bounces (each with its own parabola) where they
/// explain more frames within `limit_px`: the joint fit walks from contact to contact, and
/// stops where the noise of region centroids hides one.
ArcStats Ballistic(const Positions& in, double fps, double limit_px, int min_frames);

}  // namespace hoof::pipeline::ballistic
