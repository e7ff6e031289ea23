#include "synth/options.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string_view>

namespace hoof::synth {
namespace {

[[noreturn]] void Throw(std::string_view owner, std::string_view field, double value,
                        std::string_view rule) {
  std::ostringstream os;
  os << owner << "." << field << " = " << value << ": " << rule;
  throw std::invalid_argument(os.str());
}

void RequireRange(std::string_view owner, std::string_view field, double value, double lo,
                  double hi) {
  if (!std::isfinite(value) || value < lo || value > hi) {
    std::ostringstream rule;
    rule << "must be in [" << lo << ", " << hi << "]";
    Throw(owner, field, value, rule.str());
  }
}

}  // namespace

const char* ToString(Body body) {
  switch (body) {
    case Body::kMarkers:
      return "markers";
    case Body::kUnmarked:
      return "unmarked";
    case Body::kBall:
      return "ball";
  }
  return "markers";
}

Body ParseBody(const std::string& name) {
  for (Body b : {Body::kMarkers, Body::kUnmarked, Body::kBall})
    if (name == ToString(b)) return b;
  throw std::invalid_argument("body '" + name + "' must be markers, unmarked or ball");
}

const char* ToString(Lighting lighting) {
  return lighting == Lighting::kBacklit ? "backlit" : "front";
}

Lighting ParseLighting(const std::string& name) {
  for (Lighting l : {Lighting::kFront, Lighting::kBacklit})
    if (name == ToString(l)) return l;
  throw std::invalid_argument("lighting '" + name + "' must be front or backlit");
}

const char* ToString(FrameFormat format) {
  switch (format) {
    case FrameFormat::kPng:
      return "png";
    case FrameFormat::kMraw:
      return "mraw";
    case FrameFormat::kCine:
      return "cine";
  }
  return "png";
}

FrameFormat ParseFrameFormat(const std::string& name) {
  for (FrameFormat f : {FrameFormat::kPng, FrameFormat::kMraw, FrameFormat::kCine})
    if (name == ToString(f)) return f;
  throw std::invalid_argument("frame format '" + name + "' must be png, mraw or cine");
}

const char* ToString(CalibrationTarget target) {
  switch (target) {
    case CalibrationTarget::kCheckerboard:
      return "checkerboard";
    case CalibrationTarget::kRuler:
      return "ruler";
    case CalibrationTarget::kNone:
      break;
  }
  return "none";
}

CalibrationTarget ParseCalibrationTarget(const std::string& name) {
  for (CalibrationTarget t :
       {CalibrationTarget::kNone, CalibrationTarget::kCheckerboard, CalibrationTarget::kRuler})
    if (name == ToString(t)) return t;
  throw std::invalid_argument("calibration target '" + name +
                              "' must be none, checkerboard or ruler");
}

dynamics::SpecimenParameters SpecimenGeometry::Simulated() const {
  if (body != Body::kBall) return dynamics;
  dynamics::SpecimenParameters p;
  const double r = ball_diameter_m / 2;
  p.mass_kg = ball_mass_kg;
  p.inertia_kg_m2 = 0.4 * ball_mass_kg * r * r;
  p.end_radius_m = r;
  p.d_EC_m = 0.0;
  return p;
}

void SpecimenGeometry::Validate() const {
  constexpr std::string_view kOwner = "specimen";
  dynamics.Validate();
  RequireRange(kOwner, "ball_diameter_m", ball_diameter_m, 1e-3, 0.2);
  if (!(ball_mass_kg > 0 && ball_mass_kg <= 100))
    Throw(kOwner, "ball_mass_kg", ball_mass_kg, "must be in (0, 100]");
  const double r = dynamics.end_radius_m;
  RequireRange(kOwner, "length_m", length_m, 2 * r + 1e-6, 1.0);
  RequireRange(kOwner, "width_m", width_m, 1e-4, 1.0);
  RequireRange(kOwner, "thickness_m", thickness_m, 1e-4, 1.0);
  RequireRange(kOwner, "dot_diameter_m", dot_diameter_m, 1e-5, 0.1);
  RequireRange(kOwner, "patch_size_m", patch_size_m, dot_diameter_m * 1.2, 0.1);
  if (markers.size() < 2)
    Throw(kOwner, "markers_B_m (count)", static_cast<double>(markers.size()),
          "two or more markers are needed");
  const double half = patch_size_m / 2;
  for (const Marker& m : markers) {
    const std::string field = "markers_B_m." + m.name;
    if (m.name.empty() || m.name.find_first_of("/\\\" ") != std::string::npos)
      throw std::invalid_argument("specimen.markers_B_m: marker name '" + m.name +
                                  "' must be non-empty without spaces, quotes or slashes");
    const double x = m.p_BM_m.x(), y = m.p_BM_m.y();
    if (!std::isfinite(x) || !std::isfinite(y) || x - half < 0 || x + half > length_m - r ||
        std::abs(y) + half > width_m / 2)
      Throw(kOwner, field + " x", x,
            "the patch must lie on the straight part of the bar (0 <= x -+ patch/2 <= L - R, "
            "|y| + patch/2 <= width/2); y = " +
                std::to_string(y));
  }
  for (std::size_t i = 0; i < markers.size(); ++i)
    for (std::size_t j = i + 1; j < markers.size(); ++j) {
      if (markers[i].name == markers[j].name)
        throw std::invalid_argument("specimen.markers_B_m: duplicate marker name '" +
                                    markers[i].name + "'");
      const Eigen::Vector2d d = markers[i].p_BM_m - markers[j].p_BM_m;
      if (d.cwiseAbs().maxCoeff() < patch_size_m)
        Throw(kOwner, "markers_B_m." + markers[j].name + " (distance to " + markers[i].name + ")",
              d.norm(), "patches must not overlap");
    }
}

CameraEffects CameraEffects::Clean() {
  CameraEffects c;
  c.noise = c.motion_blur = c.distortion = c.defocus = false;
  c.vignetting = c.lighting_gradient = c.subpixel_jitter = false;
  return c;
}

void CameraEffects::Validate() const {
  constexpr std::string_view kOwner = "camera";
  RequireRange(kOwner, "full_well_e", full_well_e, 1.0, 1e7);
  RequireRange(kOwner, "read_noise_e", read_noise_e, 0.0, 1e5);
  RequireRange(kOwner, "black_level", black_level, 0.0, 0.49);
  RequireRange(kOwner, "exposure_s", exposure_s, 1e-8, 1.0);
  RequireRange(kOwner, "blur_samples", blur_samples, 2, 64);
  for (double k : {k1, k2, p1, p2, k3})
    RequireRange(kOwner, "distortion (k1 k2 p1 p2 k3)", k, -1.0, 1.0);
  RequireRange(kOwner, "focal_px", focal_px, 10.0, 1e6);
  RequireRange(kOwner, "principal_offset_px x", principal_offset_px.x(), -1e3, 1e3);
  RequireRange(kOwner, "principal_offset_px y", principal_offset_px.y(), -1e3, 1e3);
  RequireRange(kOwner, "defocus_sigma_px", defocus_sigma_px, 0.0, 5.0);
  if (defocus && defocus_sigma_px <= 0) Throw(kOwner, "defocus_sigma_px", 0, "must be > 0");
  RequireRange(kOwner, "vignetting_fraction", vignetting_fraction, 0.0, 0.9);
  RequireRange(kOwner, "lighting_gradient_fraction", lighting_gradient_fraction, 0.0, 0.9);
  RequireRange(kOwner, "drop_frame_probability", drop_frame_probability, 0.0, 0.5);
  RequireRange(kOwner, "duplicate_frame_probability", duplicate_frame_probability, 0.0, 0.5);
  RequireRange(kOwner, "drop_frames", drop_frames, 0, 100000);
  RequireRange(kOwner, "duplicate_frames", duplicate_frames, 0, 100000);
  if (flicker_hz != 0) RequireRange(kOwner, "flicker_hz", flicker_hz, 1.0, 1000.0);
  if (!(flicker_depth >= 0 && flicker_depth < 1))
    Throw(kOwner, "flicker_depth", flicker_depth, "must be in [0, 1)");
}

void OutOfPlane::Validate() const {
  constexpr std::string_view kOwner = "out_of_plane";
  RequireRange(kOwner, "tilt_deg", tilt_deg, -60.0, 60.0);
  RequireRange(kOwner, "roll_deg", roll_deg, -60.0, 60.0);
  RequireRange(kOwner, "tilt_rate_deg_s", tilt_rate_deg_s, -1e4, 1e4);
  RequireRange(kOwner, "roll_rate_deg_s", roll_rate_deg_s, -1e4, 1e4);
}

void RenderOptions::Validate() const {
  constexpr std::string_view kOwner = "render";
  RequireRange(kOwner, "width_px", width_px, 64, 4096);
  RequireRange(kOwner, "height_px", height_px, 64, 4096);
  if (bit_depth != 8 && bit_depth != 12 && bit_depth != 16)
    Throw(kOwner, "bit_depth", bit_depth, "must be 8, 12 or 16");
  if (bit_depth == 12 && frame_format == FrameFormat::kPng)
    Throw(kOwner, "bit_depth", bit_depth,
          "must be 8 or 16 for PNG frames (12 needs the mraw or cine frame format)");
  if (bit_depth == 12 && frame_format == FrameFormat::kMraw && width_px % 2 != 0)
    Throw(kOwner, "width_px", width_px, "must be even for 12-bit packed MRAW");
  RequireRange(kOwner, "m_per_px", m_per_px, 2e-5, 2e-3);
  RequireRange(kOwner, "fps", fps, 1.0, 1e7);
  RequireRange(kOwner, "frames_before", frames_before, 1, 100000);
  RequireRange(kOwner, "frames_after", frames_after, 1, 100000);
  RequireRange(kOwner, "png_compression", png_compression, 0, 9);
  RequireRange(kOwner, "texture_oversampling", texture_oversampling, 3, 9);
  if (texture_oversampling % 2 == 0)
    Throw(kOwner, "texture_oversampling", texture_oversampling, "must be odd");
  camera.Validate();
  // (With frames_from_flight the counts are known only when the trial is planned; PlanTrial
  // checks them there.)
  if (!frames_from_flight &&
      camera.drop_frames + camera.duplicate_frames > frames_before + frames_after - 1)
    Throw("camera", "drop_frames + duplicate_frames", camera.drop_frames + camera.duplicate_frames,
          "must leave the first frame: at most frames_before + frames_after - 1");
  if (camera.motion_blur && camera.exposure_s > 1.0 / fps * (1 + 1e-12))
    Throw("camera", "exposure_s", camera.exposure_s,
          "must not exceed the frame period (one over the frame rate)");
}

void TrialSpec::Validate() const {
  constexpr std::string_view kOwner = "trial";
  if (id.empty() || id.find_first_of("/\\") != std::string::npos || id == "." || id == "..")
    throw std::invalid_argument("trial.id '" + id + "' must be a non-empty folder name");
  RequireRange(kOwner, "angle_deg", angle_deg, 0.0, 60.0);
  if (!std::isfinite(speed_m_s) || speed_m_s <= 0 || speed_m_s > 20)
    Throw(kOwner, "speed_m_s", speed_m_s, "must be in (0, 20]");
  if (e && !(*e > 0 && *e < 1)) Throw(kOwner, "e", *e, "must be in (0, 1)");
  if (mu && !(*mu >= 0 && std::isfinite(*mu))) Throw(kOwner, "mu", *mu, "must be >= 0");
  RequireRange(kOwner, "scatter_scale", scatter_scale, 0.0, 4.0);
  RequireRange(kOwner, "bounces", bounces, 1, 20);
  hidden.contact.Validate();
  hidden.out_of_plane.Validate();
}

double RestitutionSpread(dynamics::Surface surface) {
  switch (surface) {
    case dynamics::Surface::kSteel:
      return 0.041;
    case dynamics::Surface::kConcrete:
      return 0.039;
    case dynamics::Surface::kAsphalt:
      return 0.071;
  }
  return 0.05;
}

}  // namespace hoof::synth
