#pragma once
/// @file
/// Plans an everyday clip: its camera, the ball's path, the hand, the frame schedule and the
/// light, and from them the clip's truth (everything but the pixels).

#include "synth/ball_flight.h"
#include "synth/footage_options.h"
#include "synth/footage_timing.h"
#include "synth/footage_truth.h"
#include "synth/hand_model.h"
#include "synth/pinhole_camera.h"
#include "synth/room_scene.h"

namespace hoof::synth {

/// A planned clip.
struct FootagePlan {
  FootageSpec spec;
  PinholeCamera camera;
  BallPath path;
  FrameSchedule schedule;
  RoomLight light;
  HandModel hand;
  FootageTruth truth;
};

/// Validates `spec` and plans the clip. Throws std::invalid_argument naming the field for a bad
/// spec, and for a clip that cannot be drawn as asked: the ball in view inside the back wall, a
/// side wall or the camera, a table bounce off the table, or a kNeverLands ball that lands in
/// view (each names launch.v_W_m_s or the field at fault).
FootagePlan PlanFootage(const FootageSpec& spec);

/// Sub-frame samples the exposure of `capture` is integrated over (1 without motion blur):
/// enough that the ball's and the hand's images move at most 0.4 px between samples, from 2 up
/// to sensor.max_blur_samples.
int ExposureSamples(const FootagePlan& plan, int capture);

/// The fractions of the sphere image `image` inside a w x h frame and under `hand` (sampled on
/// a grid of about 1300 points over the ellipse; exact 0 or 1 when the ellipse's bounding box
/// is wholly out of or inside the frame, or misses the hand's).
void VisibleFractions(const SphereImage& image, const HandShape& hand, int width_px, int height_px,
                      double& in_view, double& occluded);

}  // namespace hoof::synth
