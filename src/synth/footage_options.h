#pragma once
/// @file
/// Settings of the everyday-footage renderer (docs/synthetic-trials.md, "Everyday footage"): a
/// coloured ball bouncing in an ordinary room, filmed by a phone or a slow-motion camera. Plain
/// option structs with documented SI defaults (a realistic clip) and a Validate() that names the
/// field. World W: x right, y up (the contact surface is y = 0), z toward the camera (m).

#include <cstdint>
#include <limits>
#include <string>

#include <Eigen/Core>

#include "core/frames.h"

namespace hoof::synth {

/// What happens in the clip.
enum class FootageScenario {
  kBounce,      ///< A hand releases the ball, which bounces on the surface (the default).
  kNeverLands,  ///< The ball is thrown and leaves the view before it lands: no impact in view.
  kStill,       ///< Nothing moves: the ball lies on the surface, no hand.
  kHandOnly,    ///< No ball: a hand comes into view and leaves.
};
/// "bounce", "never-lands", "still" or "hand-only".
const char* ToString(FootageScenario scenario);
/// Parses ToString's names; std::invalid_argument naming the value otherwise.
FootageScenario ParseFootageScenario(const std::string& name);

/// How the ball's mass is spread: I = k m r^2.
enum class BallInertia {
  kSolid,   ///< A solid sphere, k = 2/5 (a rubber or plastic ball; the default).
  kHollow,  ///< A thin hollow sphere, k = 2/3 (a table-tennis or inflated ball).
};
const char* ToString(BallInertia inertia);
BallInertia ParseBallInertia(const std::string& name);
/// k of I = k m r^2.
double InertiaFactor(BallInertia inertia);

/// The ball's paint.
enum class BallColor { kRed, kYellow, kOrange, kWhite, kGreen, kBlue };
const char* ToString(BallColor color);
BallColor ParseBallColor(const std::string& name);
/// The paint's reflectance, linear RGB in [0, 1].
Eigen::Vector3d BallAlbedoRgb(BallColor color);

/// What is drawn on the ball (it shows the spin).
enum class BallTexture {
  kPlain,    ///< One colour (the default).
  kStripes,  ///< Two black great circles at right angles.
  kCross,    ///< A black cross drawn on one side.
};
const char* ToString(BallTexture texture);
BallTexture ParseBallTexture(const std::string& name);

/// What the ball lands on.
enum class ContactSurface {
  kFloor,  ///< A wooden floor that meets the back wall (the default).
  kTable,  ///< A table top whose front edge is nearer the camera than the ball.
};
const char* ToString(ContactSurface surface);
ContactSurface ParseContactSurface(const std::string& name);

/// How captures become the frames of the file.
enum class FrameDelivery {
  /// One frame per capture, in order, at the container rate (a phone; a slow-motion file when
  /// the container rate is below the capture rate). The default.
  kEachCapture,
  /// The file samples a live picture: frame j, at j / container_fps, shows the latest capture
  /// taken by then (a screen recording: each capture held for one or more frames).
  kLatestCapture,
};
const char* ToString(FrameDelivery delivery);
FrameDelivery ParseFrameDelivery(const std::string& name);

/// How the frames are stored.
enum class FootageCodec {
  kH264,  ///< clip.mp4, H.264 in yuv420p through OpenCV's FFmpeg writer (the default).
  kPng,   ///< frames/%06d.png, lossless colour PNGs as delivered (upright).
};
const char* ToString(FootageCodec codec);
FootageCodec ParseFootageCodec(const std::string& name);

/// The ball's look and build.
struct BallOptions {
  double radius_m = 0.025;                    ///< (m), in [0.005, 0.2].
  BallInertia inertia = BallInertia::kSolid;  ///< I = k m r^2 (InertiaFactor).
  BallColor color = BallColor::kRed;
  BallTexture texture = BallTexture::kPlain;
  double specular = 0.35;   ///< Strength of the light's highlight, in [0, 2] (0 = matt).
  double shininess = 60.0;  ///< Blinn-Phong exponent of the highlight, in [1, 2000].
  void Validate() const;
};

/// Where and how the ball is let go. With a non-zero velocity the hand carries the ball along
/// the straight line of that velocity during throw_duration_s before the release (a throw).
struct LaunchOptions {
  double x_m = 0.0;             ///< Sideways position of the release (m), in [-3, 3].
  double z_m = 0.0;             ///< Depth of the release, + toward the camera (m), in [-3, 3].
  double drop_height_m = 0.45;  ///< Lowest point of the ball above the surface (m), [0, 3].
  Eigen::Vector3d v_W_m_s{0.0, 0.0, 0.0};    ///< Velocity at release (m/s), each in [-20, 20].
  Eigen::Vector3d w_W_rad_s{0.0, 0.0, 0.0};  ///< Spin at release (rad/s), each in [-500, 500].
  double release_time_s = 0.3;               ///< Since capture 0 (s), in [0, 60].
  double throw_duration_s = 0.1;             ///< Hand carry before a throw (s), in [0, 2].
  void Validate() const;
};

/// The impacts: instantaneous rigid-sphere impacts with Newton restitution along the normal and
/// Coulomb friction with rolling (docs/synthetic-trials.md, "Everyday footage").
struct BounceOptions {
  double e_mean = 0.75;  ///< Mean normal restitution, in [0.05, 0.98].
  /// S.d. of the per-bounce draw of e (a normal, redrawn outside [0.05, 0.98]); 0 = every
  /// bounce e_mean. In [0, 0.2].
  double e_sd = 0.02;
  double mu = 0.5;                              ///< Coulomb friction, in [0, 2].
  double g_m_s2 = core::kStandardGravity_m_s2;  ///< Gravity (m/s^2), in [0.1, 100].
  /// A bounce whose rebound would rise less than this ends the bouncing (m), in [1e-5, 1]: the
  /// ball then stays on the surface (an impact without rebound), slides and rolls.
  double min_rebound_height_m = 0.002;
  void Validate() const;
};

/// A pinhole camera, described in the image as delivered (upright, after the rotation tag).
/// Camera axes: x right, y down, z forward. From looking along -z_W it is panned about y_W,
/// tilted down about its x axis, then rolled about its optical axis.
struct FootageCameraOptions {
  int width_px = 1280;  ///< Delivered width (px), in [16, 4096]; even for H.264.
  int height_px = 720;  ///< Delivered height (px), in [16, 4096]; even for H.264.
  double focal_px = 0;  ///< Focal length (px); 0 = from horizontal_fov_deg. In [0, 1e5].
  double horizontal_fov_deg = 62.0;  ///< Used when focal_px is 0, in [5, 150].
  /// Principal point (px, delivered image); NaN = the image centre ((w - 1) / 2, (h - 1) / 2).
  double cx_px = std::numeric_limits<double>::quiet_NaN();
  double cy_px = std::numeric_limits<double>::quiet_NaN();
  Eigen::Vector3d p_W_m{0.05, 0.30, 1.30};  ///< Centre of projection in W (m).
  double pan_deg = 0.0;                     ///< > 0 turns the camera toward +x_W, in [-60, 60].
  double tilt_deg = 4.0;                    ///< > 0 looks down, in [-60, 80].
  double roll_deg = 1.5;  ///< > 0 turns the scene clockwise in the image, in [-45, 45].
  /// The file's rotation tag (0, 90, 180, 270): the frames are stored turned by it
  /// counter-clockwise, as a phone stores them, so a player that turns them clockwise by the
  /// tag shows them upright. Needs the H.264 codec.
  int rotation_tag_deg = 0;
  void Validate() const;
};

/// The room. Everything in it is static.
struct RoomOptions {
  ContactSurface surface = ContactSurface::kFloor;
  /// Shelves with objects, a side wall (a corner), a picture, a plant pot, a ruler and a
  /// skirting board. false: a plain wall over a plain floor (clean backgrounds for tests).
  bool clutter = true;
  double wall_z_m = -0.6;           ///< The back wall's plane (m), in [-20, -0.05].
  double side_wall_x_m = -1.0;      ///< The left wall's plane (with clutter) (m), in [-20, -0.1].
  double table_height_m = 0.75;     ///< kTable: the room's floor lies this far below (m), [0.2, 2].
  double table_front_z_m = 0.35;    ///< kTable: the front edge (m), in (release z, 5].
  double table_half_width_m = 0.8;  ///< kTable: half its width about x = 0 (m), in [0.1, 10].
  Eigen::Vector3d light_p_W_m{0.3, 2.2, 0.5};  ///< The ceiling light (m); above the surface.
  double light_radius_m = 0.15;  ///< Radius of the light (sets the shadow's softness), [0, 2].
  double ambient = 0.35;         ///< Share of the light that comes from everywhere, in [0, 1].
  double brightness = 1.0;       ///< Exposure factor on every colour, in [0.05, 4].
  void Validate() const;
};

/// The hand that holds the ball at the start and lets go at the release time.
struct HandOptions {
  bool enabled = true;
  double skin_tone = 0.35;  ///< 0 light to 1 dark skin, in [0, 1].
  /// How fast the hand withdraws after the release (m/s), in [0.05, 20]; it also accelerates
  /// away at 4 m/s^2.
  double leave_speed_m_s = 1.2;
  /// Direction of withdrawal in the hand's plane (x_W sideways, y_W up); normalised; not zero.
  Eigen::Vector2d leave_direction{-0.3, 1.0};
  void Validate() const;
};

/// When frames are captured and how they are stored.
struct FootageTimingOptions {
  double capture_fps = 30.0;  ///< Captures per second, in [1, 2000].
  double container_fps = 0;   ///< The file's frame rate; 0 = capture_fps. In [0, 2000].
  FrameDelivery delivery = FrameDelivery::kEachCapture;
  double duration_s = 2.0;  ///< Scene time the clip covers (s), in (0, 120].
  /// Exposure per capture (s); 0 = half the capture period (a phone's in room light). At most
  /// one capture period.
  double exposure_s = 0;
  /// kLatestCapture: s.d. of each capture's time about k / capture_fps, as a fraction of the
  /// capture period (clamped to +-0.45 periods), in [0, 0.3].
  double capture_jitter_fraction = 0.15;
  int repeat_frames = 0;  ///< Frames that repeat the previous one, at seeded places, >= 0.
  int drop_frames = 0;    ///< kEachCapture: captures left out, at seeded places, >= 0.
  void Validate() const;
};

/// The sensor and lens.
struct SensorOptions {
  bool motion_blur = true;    ///< Integrate the image over the exposure.
  int max_blur_samples = 64;  ///< Most sub-frame samples per exposure, in [1, 1024].
  bool noise = true;          ///< Read and shot noise.
  double read_noise = 1.2;    ///< S.d. of read noise (8-bit levels), in [0, 50].
  double shot_noise = 0.04;   ///< Shot noise variance per level of signal, in [0, 5].
  double vignetting = 0.2;    ///< Brightness lost in the corners, in [0, 0.9].
  void Validate() const;
};

/// Everything that defines a clip of everyday footage. The defaults are a phone's 2 s clip at
/// 30 fps, 1280 x 720, of a red 50 mm ball dropped from 0.45 m onto a wooden floor.
struct FootageSpec {
  FootageScenario scenario = FootageScenario::kBounce;
  std::uint64_t seed = 1;  ///< Seeds every draw (e per bounce, textures, clutter, noise).
  BallOptions ball;
  LaunchOptions launch;
  BounceOptions bounce;
  FootageCameraOptions camera;
  RoomOptions room;
  HandOptions hand;
  FootageTimingOptions timing;
  SensorOptions sensor;
  FootageCodec codec = FootageCodec::kH264;
  int png_compression = 1;  ///< kPng: zlib level, in [0, 9].
  /// Checks every field; std::invalid_argument names it ("FootageSpec.ball.radius_m = 0.5:
  /// must be in [0.005, 0.2]").
  void Validate() const;
};

/// The spec a scenario starts from: the defaults, with kNeverLands thrown sideways and up from
/// the left so that it leaves the view before it lands, kStill without a hand and kHandOnly
/// without a ball.
FootageSpec DefaultFootageSpec(FootageScenario scenario);

/// Ready-made timings.
enum class TimingPreset {
  kPhone,            ///< 30 captures a second, one frame each, at 30 fps.
  kSlowMotion,       ///< 240 captures a second stored at 30 fps.
  kScreenRecording,  ///< About 30 irregular captures a second sampled by a 60 fps file.
};
/// "phone", "slow-motion" or "screen-recording".
const char* ToString(TimingPreset preset);
TimingPreset ParseTimingPreset(const std::string& name);
/// The timing of a preset (the other fields at their defaults).
FootageTimingOptions TimingOf(TimingPreset preset);

/// The container rate in effect: container_fps, or capture_fps when it is 0.
double ContainerFps(const FootageTimingOptions& timing);
/// The exposure in effect: exposure_s, or half the capture period when it is 0.
double ExposureSeconds(const FootageTimingOptions& timing);

}  // namespace hoof::synth
