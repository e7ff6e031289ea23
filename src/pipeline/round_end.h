#pragma once
/// @file
/// The round end of an unmarked specimen's outline (docs/tracking.md, "Where E and C are on an
/// outline"): the circle through the edge of the end x_B < 0, whose centre is E. An outline's
/// area centroid is not its centre of mass C in general (the rounded corners alone put it
/// 0.68 mm ahead of C on the paper's 45 x 16 mm bar with R = 9 mm), and on a spinning body
/// that offset moves the centroid's velocity by w x r. The round end is the body's defined
/// geometry: E from its arc, and C = E + |EC| x_B, as for markers.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "tracking/pose.h"
#include "tracking/silhouette_tracker.h"

namespace hoof::pipeline {

/// One frame's round end.
struct RoundEndFit {
  bool ok = false;
  std::string status;                  ///< "ok" or why not
  Eigen::Vector2d centre_I{0.0, 0.0};  ///< E in the image (px, as the frame is: distorted)
  double radius_px = 0.0;
  double rms_px = 0.0;  ///< of the edge points used about the circle
  int points = 0, rejected = 0;
};

/// Fits the round end of the outline `o` (found, with its orientation: x_B from the round end
/// toward C) in `grey` (single channel, any depth), the body of polarity `polarity`. Edge points
/// come from rays about E's first guess over the end's arc (within the outline's half width of
/// the axis), each where the profile crosses the level midway between inside and outside; the
/// circle (centre and radius free) is fitted geometrically with outliers rejected (a surface or
/// shadow joining the end), twice. `radius_guess_px` (<= 0: half the outline's width) seeds it.
RoundEndFit FitRoundEnd(const cv::Mat& grey, const tracking::SilhouetteObservation& o,
                        tracking::Polarity polarity, double radius_guess_px);

/// Where E lies relative to an outline's area centroid, in the body frame, from many frames.
struct RoundEndOffset {
  bool measured = false;
  std::string message;  ///< why it was not measured
  /// E minus the area centroid in B (x_B toward C), in px of the undistorted image: the median
  /// over the frames whose round end was fitted, and its robust standard error.
  Eigen::Vector2d p_BE_px{0.0, 0.0};
  Eigen::Vector2d p_BE_se_px{0.0, 0.0};
  double radius_px = 0.0;  ///< median fitted radius
  int frames_used = 0, frames_tried = 0;
};

/// The body-frame offset of E from the centroid over the frames of `fits` (one per
/// observation; nullopt where none was tried) with the observations `obs`; `unit` maps the
/// image to W at 1 m per px (undistorts and rotates).
RoundEndOffset EstimateRoundEndOffset(const std::vector<tracking::SilhouetteObservation>& obs,
                                      const std::vector<std::optional<RoundEndFit>>& fits,
                                      const tracking::ImageToWorld& unit);

}  // namespace hoof::pipeline
