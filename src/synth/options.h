#pragma once
/// @file
/// Settings of the synthetic high-speed trial renderer (docs/synthetic-trials.md): the specimen
/// as drawn, the camera and its nuisances, the hidden effects and the trial itself. Plain
/// option structs with documented SI defaults and a Validate() that names the field.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "dynamics/parameters.h"

namespace hoof::synth {

/// What body the camera sees (docs/synthetic-trials.md, "Bodies").
enum class Body {
  kMarkers,   ///< The hoof-wall specimen with its dot markers (the default).
  kUnmarked,  ///< The same specimen without markers: hoof-wall texture and outline only.
  kBall,      ///< A shaded sphere; its rotation is not visible.
};
/// "markers", "unmarked" or "ball".
const char* ToString(Body body);
/// Parses ToString's names; std::invalid_argument naming the value otherwise.
Body ParseBody(const std::string& name);

/// How the scene is lit.
enum class Lighting {
  kFront,    ///< Lights in front, upper left: a lit body on a dark studio (the default).
  kBacklit,  ///< A bright, near-saturated background; body and surface block dark silhouettes.
};
const char* ToString(Lighting lighting);
Lighting ParseLighting(const std::string& name);

/// How a trial's frames are stored (docs/synthetic-trials.md, "Frame files").
enum class FrameFormat {
  kPng,   ///< frames/%06d.png, one grey PNG per frame (the default).
  kMraw,  ///< One Photron clip.mraw with its clip.cihx header.
  kCine,  ///< One Phantom clip.cine with per-frame time stamps.
};
/// "png", "mraw" or "cine".
const char* ToString(FrameFormat format);
/// Parses ToString's names; std::invalid_argument naming the value otherwise.
FrameFormat ParseFrameFormat(const std::string& name);

/// A calibration image written beside the trial (docs/synthetic-trials.md, "Calibration
/// images"), which trial.json then names as its scale (camera.scale_from).
enum class CalibrationTarget {
  kNone,          ///< No calibration image; trial.json states camera.m_per_px (the default).
  kCheckerboard,  ///< A checkerboard card.
  kRuler,         ///< A ruler with regular ticks.
};
/// "none", "checkerboard" or "ruler".
const char* ToString(CalibrationTarget target);
/// Parses ToString's names; std::invalid_argument naming the value otherwise.
CalibrationTarget ParseCalibrationTarget(const std::string& name);

/// One white dot on its black square patch, at p_BM in the body frame B (origin E, x_B toward
/// C), on the face of the specimen that looks at the camera.
struct Marker {
  std::string name;                  ///< "M1", "M2", ...
  Eigen::Vector2d p_BM_m{0.0, 0.0};  ///< Centre of the dot in B (m).
};

/// The specimen as the camera sees it, and as the model sees it (`dynamics`).
/// The outline is a 45 x 16 mm bar whose end x_B < 0 is rounded with radius R about E.
struct SpecimenGeometry {
  dynamics::SpecimenParameters dynamics;  ///< m, I_C, R and d used by the simulator.
  double length_m = 0.045;                ///< Bar length from the tip of the round end (m); > 2 R.
  double width_m = 0.016;                 ///< Bar width, in the image plane (m); > 0.
  double thickness_m = 0.008;             ///< Bar thickness, toward the camera (m); > 0.
  double dot_diameter_m = 0.003;          ///< Diameter of each white dot (m); > 0.
  double patch_size_m = 0.006;            ///< Side of the black square under each dot (m); > dot.
  /// Marker centres in B; two or more, each patch inside the bar outline.
  std::vector<Marker> markers = {{"M1", {0.006, 0.0}}, {"M2", {0.024, 0.0}}};

  Body body = Body::kMarkers;  ///< What is drawn and simulated.
  /// Ball diameter (m); in [1e-3, 0.2]. Used when body is kBall.
  double ball_diameter_m = 0.02;
  /// Ball mass (kg); in (0, 100]. The default equals the specimen's 8 g, so the paper's (k, b)
  /// give the paper's e (the e draw's mean depends on the mass, synth/contact_draw.h).
  double ball_mass_kg = 0.008;

  /// What the simulator sees: `dynamics` for the specimen; for the ball a solid sphere, its
  /// round end the whole ball (R = diameter / 2, d = 0: E is the centre C, so the contact
  /// point is R below C) and I_C = 2/5 m R^2.
  dynamics::SpecimenParameters Simulated() const;

  /// Throws std::invalid_argument naming the field (e.g. "markers_B_m.M2") and its value.
  void Validate() const;
};

/// Camera nuisances. Each is on by default at a realistic level; `Clean()` turns all off.
struct CameraEffects {
  bool noise = true;            ///< Shot (Poisson-like) plus read noise.
  double full_well_e = 6000.0;  ///< Electrons at full scale; sets the shot noise; > 0.
  double read_noise_e = 25.0;   ///< Read noise, standard deviation in electrons; >= 0.
  double black_level = 0.015;   ///< Pedestal as a fraction of full scale; in [0, 0.5).

  bool motion_blur = true;          ///< Integrate the exposure over sub-frame poses.
  double exposure_s = 1.0 / 16000;  ///< Exposure time (s); in (0, 1/fps].
  int blur_samples = 8;             ///< Sub-frame poses across the exposure; in [2, 64].

  bool distortion = true;  ///< OpenCV lens distortion (k1 k2 p1 p2 k3) about the image centre.
  double k1 = -0.06, k2 = 0.02, p1 = 2e-4, p2 = -1e-4, k3 = 0.0;  ///< Dimensionless.
  double focal_px = 1500.0;  ///< Focal length in pixels for the distortion model; > 0.
  /// Principal point offset from the image centre (px).
  Eigen::Vector2d principal_offset_px{3.2, -2.1};

  bool defocus = true;            ///< Gaussian point-spread function.
  double defocus_sigma_px = 0.6;  ///< Its standard deviation (px); in (0, 5].

  bool vignetting = true;             ///< Radial light fall-off toward the corners.
  double vignetting_fraction = 0.25;  ///< Fall-off at the corners, in [0, 0.9].
  bool lighting_gradient = true;      ///< Light from the upper left: a linear ramp over the frame.
  double lighting_gradient_fraction = 0.15;  ///< Peak-to-peak across the frame, in [0, 0.9].

  bool subpixel_jitter = true;  ///< Random placement of the scene (sub-pixel and a few px).

  double drop_frame_probability = 0.0;       ///< Per frame, a capture skipped; in [0, 0.5].
  double duplicate_frame_probability = 0.0;  ///< Per frame, the previous image repeated.
  /// Exactly this many captures dropped / images repeated, at seeded frame indices (>= 1,
  /// distinct, never both at one frame); besides the probabilities above. >= 0.
  int drop_frames = 0;
  int duplicate_frames = 0;

  /// Mains-powered lights: brightness 1 + D sin(2 pi F t + psi), psi seeded, integrated over
  /// the exposure (docs/synthetic-trials.md, "Flicker"). 0 Hz is off; else F in [1, 1000] Hz
  /// and D in [0, 1).
  double flicker_hz = 0.0;
  double flicker_depth = 0.0;

  /// Everything off: an ideal pinhole camera, no noise, point-in-time exposure.
  static CameraEffects Clean();
  /// Throws std::invalid_argument naming the field.
  void Validate() const;
};

/// Out-of-plane rotation of the specimen (the paper's named error source; docs/tracking.md,
/// "5. Out-of-plane rotation"). The body is rotated about C by roll about its long axis x_B and
/// then by tilt about its transverse axis y_B (which turns the long axis out of the image
/// plane); the camera projects orthographically. Angles at first touch plus constant rates.
struct OutOfPlane {
  double tilt_deg = 0.0;         ///< Tilt at first touch (deg); |tilt| < 60.
  double roll_deg = 0.0;         ///< Roll at first touch (deg); |roll| < 60.
  double tilt_rate_deg_s = 0.0;  ///< d tilt / dt (deg/s).
  double roll_rate_deg_s = 0.0;  ///< d roll / dt (deg/s).
  bool Any() const {
    return tilt_deg != 0 || roll_deg != 0 || tilt_rate_deg_s != 0 || roll_rate_deg_s != 0;
  }
  void Validate() const;
};

/// Effects that the baseline model lacks and that a synthetic trial may hide.
struct HiddenEffects {
  dynamics::ContactExtensions contact;  ///< Passed to the simulator; recorded in truth.
  OutOfPlane out_of_plane;              ///< Drawn by the renderer; recorded in truth.
};

/// Image geometry, timing and file settings.
struct RenderOptions {
  int width_px = 512;   ///< Frame width (px); in [64, 4096].
  int height_px = 384;  ///< Frame height (px); in [64, 4096].
  /// Bits per pixel: 8 or 16 (grey PNG); 12 (values 0..4095) with an MRAW (12-bit packed, even
  /// width) or CINE (16-bit storage recording 12 bits) frame format only.
  int bit_depth = 8;
  double m_per_px = 2e-4;   ///< Scale in the plane of motion (m/px); in [2e-5, 2e-3].
  double fps = 8000.0;      ///< Frame rate (1/s); > 0.
  int frames_before = 30;   ///< Frames before first touch; >= 1.
  int frames_after = 30;    ///< Frames from first touch on; >= 1.
  int png_compression = 1;  ///< zlib level 0-9 for the PNG files (1 is fastest).
  /// zlib's Huffman-only strategy: sensor noise defeats string matching, so this is both
  /// faster and smaller than the default strategy for these frames.
  bool png_huffman_only = true;
  /// Texels per image pixel of the specimen texture; odd, in [3, 9]. A box prefilter one
  /// pixel wide turns bilinear sampling into area coverage.
  int texture_oversampling = 5;
  Lighting lighting = Lighting::kFront;
  FrameFormat frame_format = FrameFormat::kPng;  ///< How the frames are stored.
  /// A calibration image of the scale, written as calibration.png and named by trial.json.
  CalibrationTarget calibration = CalibrationTarget::kNone;
  /// Choose frames_before from the fall since release at rest (speed / g) and frames_after to
  /// end at the apex of the rebound after the last impact, instead of the fixed counts.
  bool frames_from_flight = false;
  CameraEffects camera;

  /// Throws std::invalid_argument naming the field.
  void Validate() const;
};

/// One trial: what hits what, how fast, and the seed of all its random draws.
struct TrialSpec {
  std::string id = "trial";  ///< Folder name and trial.json id; no '/'.
  dynamics::Surface surface = dynamics::Surface::kSteel;
  double angle_deg = 0.0;  ///< Surface angle phi (deg); in [0, 60].
  double speed_m_s = 3.0;  ///< Vertical speed at first touch (m/s); in (0, 20].
  std::uint64_t seed = 1;  ///< Seeds every draw of the trial (std::mt19937_64).
  /// Draw e and mu per trial with the paper's spread (docs/synthetic-trials.md, "What is
  /// drawn"). When false, the paper's model coefficients are used as they are.
  bool scatter_parameters = true;
  /// Multiplies both spreads of those draws (RestitutionSpread and kFrictionSpread): 1 is the
  /// paper's, 0.5 half of it, 0 the same as no scatter. Dimensionless; in [0, 4].
  double scatter_scale = 1.0;
  std::optional<double> e;   ///< Fixes the drawn normal restitution; in (0, 1).
  std::optional<double> mu;  ///< Fixes the friction coefficient; >= 0.
  /// Impacts in the clip; in [1, 20]. After each separation the body flies until its round
  /// end touches the surface again and the simulator is restarted from that flight state.
  int bounces = 1;
  HiddenEffects hidden;

  /// Throws std::invalid_argument naming the field.
  void Validate() const;
};

/// Spread of the per-trial coefficient draws (the paper's s.d.; docs/synthetic-trials.md,
/// "What is drawn").
double RestitutionSpread(dynamics::Surface surface);
/// Standard deviation of the per-trial friction draw (about 0.04 on every surface).
inline constexpr double kFrictionSpread = 0.04;

}  // namespace hoof::synth
