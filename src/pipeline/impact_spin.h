#pragma once
/// @file
/// A ball's spin before and after an impact, from its own texture (tracking/ball_spin.h): the
/// faces its tracker sampled on the frames of the two flights the impact was measured from, one
/// constant spin fitted to each flight.

#include <vector>

#include "kinematics/impact_kinematics.h"
#include "kinematics/pose_sample.h"
#include "tracking/ball_spin.h"
#include "tracking/silhouette_tracker.h"

namespace hoof::pipeline {

/// Measures `im`'s spin before and after from `track`'s faces (one observation per frame, as
/// `samples`, whose times it takes). The frames fitted are those of im.before and im.after that
/// hold a position, less the frames the impact's limits name as off the arcs or repeated.
/// `sense_W` is +1 or -1: the sign that carries a turn in the image (x toward y) into W (the
/// determinant's sign of the image-to-world mapping; -1 for a camera whose image y points
/// down). Where a side is measured, its w and s.e. (and the flight fit's) are set and its
/// rotational energy (1/2 I w^2, with `inertia_kg_m2` when finite) added to the kinetic energy;
/// where not, w stays as it was (NaN for a ball). im.limits.spin_before and spin_after say how
/// each side was measured, or why not. An impact that was not measured is left alone.
void MeasureImpactSpin(const tracking::SilhouetteTrack& track,
                       const std::vector<kinematics::PoseSample>& samples, double sense_W,
                       double inertia_kg_m2, const tracking::BallSpinOptions& options,
                       kinematics::ImpactKinematics& im);

}  // namespace hoof::pipeline
