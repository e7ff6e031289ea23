#include "pipeline/study_format.h"

#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "core/frames.h"
#include "tracking/camera_file.h"
#include "tracking/frame_source.h"

namespace hoof::pipeline {
namespace {

/// Why `id` cannot name a trial (it names its files: figures, overlay frames), or "".
std::string IdProblem(const std::string& id) {
  if (id.empty()) return "must not be empty";
  if (id.size() > 200)
    return "is " + std::to_string(id.size()) + " characters long; at most 200 are accepted";
  if (id == "." || id == "..") return "\"" + id + "\" cannot name files";
  for (unsigned char c : id)
    if (c == '/' || c == '\\' || c < 0x20 || c == 0x7f)
      return "\"" + id + "\" holds a '/', a '\\' or a control character; it names files and tables";
  return "";
}

namespace fs = std::filesystem;
using nlohmann::json;

[[noreturn]] void Fail(const fs::path& file, const std::string& field, const std::string& why) {
  throw std::runtime_error(file.string() + ": field \"" + field + "\" " + why);
}

json ReadJson(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot open (missing file?)");
  json j;
  try {
    j = json::parse(in);
  } catch (const json::out_of_range& e) {  // a number beyond double, such as 1e999
    throw std::runtime_error(file.string() +
                             ": a number is out of range (beyond a double): " + e.what());
  } catch (const json::exception& e) {
    throw std::runtime_error(file.string() + ": not valid JSON: " + e.what());
  }
  if (!j.is_object())
    throw std::runtime_error(file.string() + ": must hold a JSON object ({...}), found " +
                             std::string(j.type_name()));
  return j;
}

/// Checks the fields of `obj` against the known ones; unknown ones become warnings.
void WarnUnknown(const json& obj, const std::set<std::string>& known, const fs::path& file,
                 const std::string& prefix, std::vector<std::string>& warnings) {
  // Found by fuzzing: a specimen, frames or camera that is a number or an array.
  if (!obj.is_object())
    Fail(file, prefix.empty() ? std::string("(top level)") : prefix.substr(0, prefix.size() - 1),
         "must be an object ({...}), found " + std::string(obj.type_name()));
  for (auto it = obj.begin(); it != obj.end(); ++it)
    if (!known.count(it.key()))
      warnings.push_back(file.string() + ": unknown field \"" + prefix + it.key() + "\" ignored");
}

const json& Require(const json& obj, const std::string& key, const fs::path& file,
                    const std::string& prefix) {
  if (!obj.is_object() || !obj.contains(key)) Fail(file, prefix + key, "is missing");
  return obj.at(key);
}

double Number(const json& obj, const std::string& key, const fs::path& file,
              const std::string& prefix, bool positive) {
  const json& v = Require(obj, key, file, prefix);
  if (!v.is_number()) Fail(file, prefix + key, "must be a number, found " + v.dump());
  const double x = v.get<double>();
  if (!std::isfinite(x)) Fail(file, prefix + key, "must be finite");
  if (positive && !(x > 0)) Fail(file, prefix + key, "must be > 0, found " + v.dump());
  return x;
}

std::string Text(const json& obj, const std::string& key, const fs::path& file,
                 const std::string& prefix) {
  const json& v = Require(obj, key, file, prefix);
  if (!v.is_string()) Fail(file, prefix + key, "must be a string, found " + v.dump());
  return v.get<std::string>();
}

Eigen::Vector2d Pair(const json& v, const fs::path& file, const std::string& field) {
  if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number())
    Fail(file, field, "must be [x, y], found " + v.dump());
  return {v[0].get<double>(), v[1].get<double>()};
}

void CheckFormat(const json& j, const std::string& expected, const fs::path& file) {
  const std::string f = Text(j, "format", file, "");
  if (f != expected) Fail(file, "format", "is \"" + f + "\", expected \"" + expected + "\"");
}

/// A ball's fields (`"shape": "ball"`): its diameter, its mass (optional: unknown without it)
/// and the rule of its inertia, "solid" (the default), "hollow" or a number in kg m^2, at most a
/// thin shell's 2/3 m R^2. The bar's fields are errors: a ball has no round end of its own.
SpecimenSpec ParseBall(const json& s, const fs::path& file, const std::string& prefix,
                       std::vector<std::string>& warnings) {
  WarnUnknown(s,
              {"shape", "diameter_m", "mass_kg", "inertia", "end_radius_m", "d_EC_m",
               "inertia_kg_m2", "markers_B_m", "length_m", "width_m", "thickness_m"},
              file, prefix, warnings);
  for (const char* key : {"end_radius_m", "d_EC_m", "inertia_kg_m2", "markers_B_m", "length_m",
                          "width_m", "thickness_m"})
    if (s.contains(key))
      Fail(file, prefix + key,
           "applies to the hoof-wall specimen; a ball (\"shape\": \"ball\") is given by "
           "diameter_m, mass_kg and inertia");
  SpecimenSpec spec;
  spec.shape = SpecimenShape::kBall;
  spec.end_radius_m = Number(s, "diameter_m", file, prefix, true) / 2;
  spec.d_EC_m = 0.0;
  spec.mass_kg = s.contains("mass_kg") ? Number(s, "mass_kg", file, prefix, true) : core::kNaN;
  spec.inertia = BallInertia::kSolid;
  if (s.contains("inertia")) {
    const json& i = s.at("inertia");
    if (i.is_number()) {
      spec.inertia = BallInertia::kGiven;
      spec.inertia_kg_m2 = Number(s, "inertia", file, prefix, true);
      if (!s.contains("mass_kg"))
        Fail(file, prefix + "inertia", "is a number, which needs the ball's mass_kg beside it");
      const double shell = BallInertiaFactor(BallInertia::kHollow) * spec.mass_kg *
                           spec.end_radius_m * spec.end_radius_m;
      if (spec.inertia_kg_m2 > shell * (1 + 1e-9))
        Fail(file, prefix + "inertia",
             "is " + i.dump() + " kg m^2, more than a thin shell's 2/3 m R^2 = " +
                 json(shell).dump() + " kg m^2: no ball of this mass and diameter has it");
    } else if (i == "solid" || i == "hollow") {
      spec.inertia = i == "solid" ? BallInertia::kSolid : BallInertia::kHollow;
    } else {
      Fail(file, prefix + "inertia",
           "must be \"solid\" (2/5 m R^2), \"hollow\" (2/3 m R^2) or a number in kg m^2, "
           "found " +
               i.dump());
    }
  }
  if (spec.inertia != BallInertia::kGiven)
    spec.inertia_kg_m2 = BallInertiaFactor(spec.inertia) * spec.mass_kg * spec.end_radius_m *
                         spec.end_radius_m;  // NaN with the mass unknown
  return spec;
}

/// A specimen's fields; `markers_B_m` may be left out where `markers_required` is false (the
/// inline specimen of a trial tracked by its silhouette). `"shape": "ball"` reads a ball.
SpecimenSpec ParseSpecimen(const json& s, const fs::path& file, const std::string& prefix,
                           std::vector<std::string>& warnings, bool markers_required = true) {
  if (s.is_object() && s.contains("shape")) {
    const std::string shape = Text(s, "shape", file, prefix);
    if (shape != "ball")
      Fail(file, prefix + "shape",
           "is \"" + shape +
               "\": must be \"ball\" (without \"shape\" the specimen is the hoof-wall "
               "specimen)");
    return ParseBall(s, file, prefix, warnings);
  }
  WarnUnknown(s,
              {"mass_kg", "inertia_kg_m2", "end_radius_m", "d_EC_m", "length_m", "width_m",
               "thickness_m", "markers_B_m"},
              file, prefix, warnings);
  SpecimenSpec spec;
  spec.mass_kg = Number(s, "mass_kg", file, prefix, true);
  spec.inertia_kg_m2 = Number(s, "inertia_kg_m2", file, prefix, true);
  spec.end_radius_m = Number(s, "end_radius_m", file, prefix, true);
  spec.d_EC_m = Number(s, "d_EC_m", file, prefix, false);
  if (spec.d_EC_m < 0)
    Fail(file, prefix + "d_EC_m", "must be >= 0, found " + s.at("d_EC_m").dump());
  if (s.contains("length_m")) spec.length_m = Number(s, "length_m", file, prefix, true);
  if (s.contains("width_m")) spec.width_m = Number(s, "width_m", file, prefix, true);
  if (s.contains("thickness_m")) spec.thickness_m = Number(s, "thickness_m", file, prefix, true);
  if (!markers_required && !s.contains("markers_B_m")) return spec;
  const json& markers = Require(s, "markers_B_m", file, prefix);
  if (!markers.is_object() || markers.size() < 2)
    Fail(file, prefix + "markers_B_m", "must name two or more markers, found " + markers.dump());
  for (auto it = markers.begin(); it != markers.end(); ++it) {
    if (const std::string why = IdProblem(it.key()); !why.empty())
      Fail(file, prefix + "markers_B_m", "marker name " + why);
    spec.markers_B_m.emplace_back(it.key(),
                                  Pair(it.value(), file, prefix + "markers_B_m." + it.key()));
  }
  return spec;
}

}  // namespace

std::string BallInertiaName(BallInertia inertia) {
  switch (inertia) {
    case BallInertia::kSolid:
      return "solid";
    case BallInertia::kHollow:
      return "hollow";
    case BallInertia::kGiven:
      return "given";
    case BallInertia::kUnknown:
      return "unknown";
  }
  return "unknown";
}

double BallInertiaFactor(BallInertia inertia) {
  switch (inertia) {
    case BallInertia::kSolid:
      return 2.0 / 5.0;
    case BallInertia::kHollow:
      return 2.0 / 3.0;
    default:
      return core::kNaN;
  }
}

StudySpec ReadStudy(const fs::path& dir) {
  const fs::path file = dir / "study.json";
  const json j = ReadJson(file);
  StudySpec study;
  study.dir = dir;
  WarnUnknown(j, {"format", "name", "specimens", "trials"}, file, "", study.warnings);
  CheckFormat(j, "hoofimpact-study/1", file);
  if (j.contains("name")) study.name = Text(j, "name", file, "");
  const json& specimens = Require(j, "specimens", file, "");
  if (!specimens.is_object() || specimens.empty())
    Fail(file, "specimens", "must hold at least one specimen");
  for (auto it = specimens.begin(); it != specimens.end(); ++it) {
    if (const std::string why = IdProblem(it.key()); !why.empty())
      Fail(file, "specimens", "specimen id " + why);
    study.specimens[it.key()] =
        ParseSpecimen(it.value(), file, "specimens." + it.key() + ".", study.warnings);
  }
  if (j.contains("trials")) {
    const json& trials = j.at("trials");
    if (!trials.is_array()) Fail(file, "trials", "must be an array of folder names");
    for (const auto& t : trials) {
      if (!t.is_string()) Fail(file, "trials", "must hold folder names, found " + t.dump());
      // A trial folder lies inside the study folder: no absolute path, no "..".
      const fs::path rel = fs::path(t.get<std::string>()).lexically_normal();
      if (rel.empty() || rel.is_absolute() || rel.has_root_name() || *rel.begin() == ".." ||
          rel == ".")
        Fail(file, "trials",
             "\"" + t.get<std::string>() + "\" is not a folder inside the study folder");
      study.trial_dirs.push_back(dir / rel);
    }
  } else {
    // Every sub-folder holding a trial.json; one that cannot be looked into (a symlink loop,
    // no permission) is a warning, not the end of the study.
    std::vector<fs::path> found;
    std::error_code ec;
    fs::directory_iterator it(dir, ec), end;
    if (ec)
      throw std::runtime_error(dir.string() + ": cannot list the study folder: " + ec.message());
    for (; it != end; it.increment(ec)) {
      if (ec) {
        study.warnings.push_back(dir.string() + ": listing stopped: " + ec.message());
        break;
      }
      std::error_code e1, e2;
      const bool folder = it->is_directory(e1);
      const bool trial = folder && fs::exists(it->path() / "trial.json", e2);
      if (e1 || e2)
        study.warnings.push_back(it->path().string() +
                                 ": skipped, cannot be read: " + (e1 ? e1 : e2).message());
      else if (trial)
        found.push_back(it->path());
    }
    std::sort(found.begin(), found.end());
    study.trial_dirs = found;
  }
  return study;
}

/// An integer of trial.json in [low, INT_MAX], compared as 64-bit before narrowing, so
/// 4294967297 is refused, not read as 1.
int FrameNumber(const json& v, std::int64_t low, const fs::path& file, const std::string& field) {
  constexpr std::int64_t kMaxInt = std::numeric_limits<int>::max();
  bool ok = v.is_number_integer();
  if (ok && v.is_number_unsigned())
    ok = v.get<std::uint64_t>() <= static_cast<std::uint64_t>(kMaxInt) &&
         static_cast<std::int64_t>(v.get<std::uint64_t>()) >= low;
  else if (ok)
    ok = v.get<std::int64_t>() >= low && v.get<std::int64_t>() <= kMaxInt;
  if (!ok)
    Fail(file, field,
         "must be an integer in [" + std::to_string(low) + ", " + std::to_string(kMaxInt) +
             "], found " + v.dump());
  return v.get<int>();
}

/// trial.json's "frames": a camera file (with an optional range), a video, or a pattern with
/// the first frame and the count.
FramesSpec ParseFrames(const json& frames, const fs::path& file,
                       std::vector<std::string>& warnings) {
  FramesSpec out;
  WarnUnknown(frames, {"pattern", "first", "count", "video", "camera_file"}, file, "frames.",
              warnings);
  if (frames.contains("camera_file")) {
    out.camera_file = Text(frames, "camera_file", file, "frames.");
    if (out.camera_file.empty() || !tracking::IsCameraFile(out.camera_file))
      Fail(file, "frames.camera_file",
           "\"" + out.camera_file +
               "\" must name a camera file: .mraw (or its .cihx/.cih), .cine, .tif or .tiff");
    if (frames.contains("pattern") || frames.contains("video"))
      Fail(file, "frames.camera_file", "cannot be given with frames.pattern or frames.video");
    // The range within the clip; the clip's own length is checked when it is opened.
    if (frames.contains("first"))
      out.first = FrameNumber(frames.at("first"), 0, file, "frames.first");
    if (frames.contains("count"))
      out.count = FrameNumber(frames.at("count"), 1, file, "frames.count");
  } else if (frames.contains("video")) {
    out.video = Text(frames, "video", file, "frames.");
  } else {
    out.pattern = Text(frames, "pattern", file, "frames.");
    if (out.pattern.size() > tracking::kMaxFramePatternLength)
      Fail(file, "frames.pattern",
           "is " + std::to_string(out.pattern.size()) + " characters long; at most " +
               std::to_string(tracking::kMaxFramePatternLength) + " are accepted");
    if (!tracking::IsFramePattern(out.pattern))
      Fail(file, "frames.pattern",
           "\"" + out.pattern +
               "\" must hold exactly one integer conversion such as %06d (and %% for a "
               "percent sign)");
    out.first = FrameNumber(Require(frames, "first", file, "frames."), 0, file, "frames.first");
    out.count = FrameNumber(Require(frames, "count", file, "frames."), 1, file, "frames.count");
  }
  return out;
}

/// A trial's camera file: its frame range is checked against the clip (and completed when
/// trial.json gives no count), and its frame rate taken where trial.json gives none or
/// compared where it does.
void CheckCameraFile(TrialSpec& t, const fs::path& file, const std::optional<double>& fps) {
  const fs::path clip = t.dir / t.frames.camera_file;
  std::unique_ptr<tracking::CameraFileSource> source;
  try {
    source = tracking::OpenCameraFile(clip);
  } catch (const std::exception& e) {  // the clip's own message, with the trial that names it
    Fail(file, "frames.camera_file", "names a clip that cannot be read: " + std::string(e.what()));
  }
  const tracking::CameraFileInfo& info = source->info();
  FramesSpec& f = t.frames;
  if (f.first >= info.frame_count)
    Fail(file, "frames.first",
         "is " + std::to_string(f.first) + " but " + clip.string() + " holds " +
             std::to_string(info.frame_count) + " frames");
  if (f.count == 0) f.count = info.frame_count - f.first;
  if (f.count > info.frame_count - f.first)
    Fail(file, "frames.count",
         "asks for frames " + std::to_string(f.first) + " to " +
             std::to_string(static_cast<std::int64_t>(f.first) + f.count - 1) + " but " +
             clip.string() + " holds " + std::to_string(info.frame_count) + " frames");
  const bool recorded = std::isfinite(info.fps) && info.fps > 0;
  if (!fps && !recorded)
    Fail(file, "fps", "is missing, and " + clip.string() + " does not record its frame rate");
  if (fps && recorded && std::abs(*fps - info.fps) > 1e-6 * info.fps)
    Fail(file, "fps",
         "is " + json(*fps).dump() + " but " + clip.string() + " records " + json(info.fps).dump() +
             " frames per second");
  t.fps = fps ? *fps : info.fps;
}

/// A video's frame rate where trial.json gives none: the container's (the rate it plays at; a
/// slow-motion file's capture rate differs and must be stated as fps).
double ContainerRate(const TrialSpec& t, const fs::path& file) {
  const fs::path clip = t.dir / t.frames.video;
  double fps = std::numeric_limits<double>::quiet_NaN();
  try {
    fps = tracking::VideoSource(clip).info().fps;
  } catch (const std::exception& e) {
    Fail(file, "frames.video", "names a clip that cannot be read: " + std::string(e.what()));
  }
  if (!(fps > 0))
    Fail(file, "fps", "is missing, and " + clip.string() + " does not record its frame rate");
  return fps;
}

/// camera.distortion: OpenCV's [k1, k2, p1, p2, k3].
std::array<double, 5> ParseDistortion(const json& d, const fs::path& file) {
  if (!d.is_array() || d.size() != 5)
    Fail(file, "camera.distortion", "must be [k1, k2, p1, p2, k3], found " + d.dump());
  std::array<double, 5> k{};
  for (std::size_t i = 0; i < 5; ++i) {
    if (!d[i].is_number()) Fail(file, "camera.distortion", "must hold numbers");
    k[i] = d[i].get<double>();
  }
  return k;
}

/// camera.camera_matrix: 3x3, as nested rows or nine numbers, row by row.
std::array<double, 9> ParseCameraMatrix(const json& m, const fs::path& file) {
  std::array<double, 9> k{};
  std::vector<double> flat;
  if (m.is_array())
    for (const auto& row : m) {
      if (row.is_array())
        for (const auto& v : row) flat.push_back(v.is_number() ? v.get<double>() : NAN);
      else
        flat.push_back(row.is_number() ? row.get<double>() : NAN);
    }
  if (flat.size() != 9)
    Fail(file, "camera.camera_matrix", "must be a 3x3 matrix, found " + m.dump());
  for (std::size_t i = 0; i < 9; ++i) {
    if (!std::isfinite(flat[i])) Fail(file, "camera.camera_matrix", "must hold numbers");
    k[i] = flat[i];
  }
  return k;
}

/// camera.checkerboard or camera.ruler (`kind`): the image (a file or a frame of the clip) and
/// the target's geometry.
CalibrationImageSpec ParseCalibrationImage(const json& c, const std::string& kind,
                                           const fs::path& file,
                                           std::vector<std::string>& warnings) {
  const std::string prefix = "camera." + kind + ".";
  const bool board = kind == "checkerboard";
  WarnUnknown(c,
              board ? std::set<std::string>{"image", "frame", "inner_corners", "square_m"}
                    : std::set<std::string>{"image", "frame", "from_px", "to_px", "tick_m"},
              file, prefix, warnings);
  CalibrationImageSpec out;
  if (c.contains("image") == c.contains("frame"))
    Fail(file, "camera." + kind,
         "must name its \"image\" (a file relative to the trial folder) or a \"frame\" of the "
         "clip, one of the two");
  if (c.contains("image")) {
    out.image = Text(c, "image", file, prefix);
    if (out.image.empty()) Fail(file, prefix + "image", "must not be empty");
  } else {
    const json& f = c.at("frame");
    if (!f.is_number_integer() || f.get<std::int64_t>() < 0 ||
        f.get<std::int64_t>() > std::numeric_limits<int>::max())
      Fail(file, prefix + "frame", "must be a frame index >= 0, found " + f.dump());
    out.frame = f.get<int>();
  }
  if (board) {
    const json& n = Require(c, "inner_corners", file, prefix);
    if (!n.is_array() || n.size() != 2 || !n[0].is_number_integer() || !n[1].is_number_integer() ||
        n[0].get<std::int64_t>() < 3 || n[1].get<std::int64_t>() < 3 ||
        n[0].get<std::int64_t>() > 1000 || n[1].get<std::int64_t>() > 1000)
      Fail(file, prefix + "inner_corners",
           "must be [columns, rows] of inner corners, each 3 to 1000, found " + n.dump());
    out.cols = n[0].get<int>();
    out.rows = n[1].get<int>();
    out.square_m = Number(c, "square_m", file, prefix, true);
  } else {
    out.from_px = Pair(Require(c, "from_px", file, prefix), file, prefix + "from_px");
    out.to_px = Pair(Require(c, "to_px", file, prefix), file, prefix + "to_px");
    if (!((out.to_px - out.from_px).norm() > 0))
      Fail(file, prefix + "to_px", "must differ from " + prefix + "from_px");
    out.tick_m = Number(c, "tick_m", file, prefix, true);
  }
  return out;
}

/// trial.json's "camera": the scale, and gravity's direction and the lens where given.
CameraSpec ParseCamera(const json& camera, const fs::path& file,
                       std::vector<std::string>& warnings) {
  CameraSpec out;
  WarnUnknown(camera,
              {"m_per_px", "scale_from", "gravity_image", "distortion", "camera_matrix",
               "checkerboard", "ruler"},
              file, "camera.", warnings);
  if (camera.contains("scale_from")) {
    out.scale_from = Text(camera, "scale_from", file, "camera.");
    if (out.scale_from != "m_per_px" && out.scale_from != "body_diameter" &&
        out.scale_from != "markers" && out.scale_from != "gravity" &&
        out.scale_from != "end_radius" && out.scale_from != "checkerboard" &&
        out.scale_from != "ruler")
      Fail(file, "camera.scale_from",
           "is \"" + out.scale_from +
               "\": must be \"m_per_px\", \"body_diameter\", \"markers\", \"gravity\", "
               "\"end_radius\", \"checkerboard\" or \"ruler\"");
  }
  for (const char* kind : {"checkerboard", "ruler"}) {
    if (!camera.contains(kind)) {
      if (out.scale_from == kind)
        Fail(file, std::string("camera.") + kind,
             std::string("is missing: camera.scale_from \"") + kind + "\" needs it");
      continue;
    }
    (std::string(kind) == "ruler" ? out.ruler : out.checkerboard) =
        ParseCalibrationImage(camera.at(kind), kind, file, warnings);
    if (out.scale_from != kind)
      warnings.push_back(file.string() + ": camera." + kind +
                         " is not used: camera.scale_from is not \"" + kind + "\"");
  }
  // Required unless a ball's known diameter gives the scale (checked by ReadTrial).
  if (camera.contains("m_per_px")) out.m_per_px = Number(camera, "m_per_px", file, "camera.", true);
  if (camera.contains("gravity_image")) {
    const Eigen::Vector2d g = Pair(camera.at("gravity_image"), file, "camera.gravity_image");
    if (!(g.norm() > 0)) Fail(file, "camera.gravity_image", "must not be zero");
    out.gravity_image = g.normalized();
  }
  if (camera.contains("distortion"))
    out.distortion = ParseDistortion(camera.at("distortion"), file);
  if (camera.contains("camera_matrix"))
    out.camera_matrix = ParseCameraMatrix(camera.at("camera_matrix"), file);
  if (out.distortion && !out.camera_matrix)
    Fail(file, "camera.camera_matrix", "is needed when camera.distortion is given");
  return out;
}

/// trial.json's "body": the body model, and for a silhouette its shape, polarity and (a ball)
/// known diameter.
BodySpec ParseBody(const json& body, const fs::path& file, std::vector<std::string>& warnings) {
  BodySpec out;
  WarnUnknown(
      body,
      {"model", "shape", "polarity", "diameter_m", "find", "background", "rgb", "diameter_px"},
      file, "body.", warnings);
  out.model = Text(body, "model", file, "body.");
  if (out.model == "markers") {
    for (const char* key :
         {"shape", "polarity", "diameter_m", "find", "background", "rgb", "diameter_px"})
      if (body.contains(key))
        Fail(file, std::string("body.") + key, "applies to the \"silhouette\" model only");
    return out;
  }
  if (out.model != "silhouette")
    Fail(file, "body.model", "is \"" + out.model + "\": must be \"markers\" or \"silhouette\"");
  out.shape = Text(body, "shape", file, "body.");
  if (out.shape != "ball" && out.shape != "outline")
    Fail(file, "body.shape", "is \"" + out.shape + "\": must be \"ball\" or \"outline\"");
  if (body.contains("polarity")) {
    out.polarity = Text(body, "polarity", file, "body.");
    if (out.polarity != "auto" && out.polarity != "dark_on_bright" &&
        out.polarity != "bright_on_dark")
      Fail(file, "body.polarity",
           "is \"" + out.polarity +
               "\": must be \"auto\", \"dark_on_bright\" (back-lit) or \"bright_on_dark\"");
  }
  if (body.contains("diameter_m")) {
    if (out.shape != "ball") Fail(file, "body.diameter_m", "applies to a ball only");
    out.diameter_m = Number(body, "diameter_m", file, "body.", true);
  }
  if (body.contains("find")) {
    out.find = Text(body, "find", file, "body.");
    if (out.find != "shape" && out.find != "motion")
      Fail(file, "body.find", "is \"" + out.find + "\": must be \"shape\" or \"motion\"");
    if (out.find == "motion" && out.shape != "ball")
      Fail(file, "body.find", "\"motion\" applies to a ball only");
  }
  for (const char* key : {"background", "rgb", "diameter_px"})
    if (body.contains(key) && out.find != "motion")
      Fail(file, std::string("body.") + key, "applies to body.find \"motion\" only");
  if (body.contains("background")) {
    out.background = Text(body, "background", file, "body.");
    if (out.background.empty()) Fail(file, "body.background", "must name an image file");
  }
  if (body.contains("rgb")) {
    const json& c = body.at("rgb");
    if (!c.is_array() || c.size() != 3)
      Fail(file, "body.rgb", "must be [red, green, blue], each 0 to 255");
    Eigen::Vector3d rgb;
    for (int i = 0; i < 3; ++i) {
      if (!c[static_cast<std::size_t>(i)].is_number() ||
          !(c[static_cast<std::size_t>(i)].get<double>() >= 0 &&
            c[static_cast<std::size_t>(i)].get<double>() <= 255))
        Fail(file, "body.rgb", "must be [red, green, blue], each 0 to 255");
      rgb[i] = c[static_cast<std::size_t>(i)].get<double>();
    }
    out.rgb = rgb;
  }
  if (body.contains("diameter_px"))
    out.diameter_px = Number(body, "diameter_px", file, "body.", true);
  return out;
}

/// A trial whose specimen is a ball (`"shape": "ball"`): it must be tracked as one, and its
/// body.diameter_m, when given, must be the specimen's (else it is taken from it, so the
/// diameter can give the scale).
void TakeBallSpecimen(TrialSpec& t, const fs::path& file) {
  const std::string where =
      "names the ball specimen \"" + t.specimen_id + "\" (" + t.specimen_origin + ")";
  if (!t.body.is_ball())
    Fail(file, "specimen",
         where + ", but the trial tracks " +
             (t.body.is_silhouette() ? std::string("an outline") : std::string("markers")) +
             ": a ball is tracked by its silhouette, \"body\": {\"model\": \"silhouette\", "
             "\"shape\": \"ball\"}");
  const double diameter = 2 * t.specimen.end_radius_m;
  if (t.body.diameter_m > 0 && std::abs(t.body.diameter_m - diameter) > 1e-6 * diameter)
    Fail(file, "body.diameter_m",
         "is " + json(t.body.diameter_m).dump() + " m, but the trial " + where +
             " whose diameter_m is " + json(diameter).dump() + " m");
  t.body.diameter_m = diameter;
}

TrialSpec ReadTrial(const fs::path& trial_dir, const StudySpec& study) {
  const fs::path file = trial_dir / "trial.json";
  const json j = ReadJson(file);
  TrialSpec t;
  t.dir = trial_dir;
  WarnUnknown(j,
              {"format", "id", "specimen", "specimen_parameters", "surface", "surface_angle_deg",
               "fps", "frames", "camera", "surface_line_px", "nominal_speed_m_s", "notes", "body"},
              file, "", t.warnings);
  CheckFormat(j, "hoofimpact-trial/1", file);
  t.id = Text(j, "id", file, "");
  if (const std::string why = IdProblem(t.id); !why.empty()) Fail(file, "id", why);
  if (j.contains("body")) t.body = ParseBody(j.at("body"), file, t.warnings);
  if (t.body.is_ball() && !j.contains("specimen") && !j.contains("specimen_parameters")) {
    // A ball is its own specimen: its radius from its diameter (when given; else from the
    // fitted diameter at the trial's scale), its centre of mass at its centre, its mass and
    // inertia unknown.
    t.specimen_id = "ball";
    t.specimen_origin = file.string() + " (a ball without a specimen: mass and inertia unknown)";
    t.specimen.shape = SpecimenShape::kBall;
    t.specimen.inertia = BallInertia::kUnknown;
    t.specimen.mass_kg = t.specimen.inertia_kg_m2 = core::kNaN;
    t.specimen.end_radius_m = t.body.diameter_m / 2;
    t.specimen.d_EC_m = 0.0;
  } else if (j.contains("specimen_parameters")) {
    t.specimen_id = t.body.is_ball() && !j.contains("specimen") ? std::string("ball")
                                                                : Text(j, "specimen", file, "");
    // Extension: a trial may carry its specimen inline (same fields as in study.json), so a
    // single trial folder can be measured without a study around it. A silhouette needs no
    // marker layout.
    t.specimen = ParseSpecimen(j.at("specimen_parameters"), file, "specimen_parameters.",
                               t.warnings, !t.body.is_silhouette());
    t.specimen_origin = file.string() + ", specimen_parameters";
  } else {
    t.specimen_id = Text(j, "specimen", file, "");
    const auto sp = study.specimens.find(t.specimen_id);
    if (sp == study.specimens.end())
      Fail(file, "specimen",
           "names \"" + t.specimen_id + "\", which " + (study.dir / "study.json").string() +
               " does not define");
    t.specimen = sp->second;
    t.specimen_origin = (study.dir / "study.json").string() + ", specimens." + t.specimen_id;
  }
  if (t.specimen.is_ball()) TakeBallSpecimen(t, file);
  t.surface = Text(j, "surface", file, "");
  t.surface_angle_deg = Number(j, "surface_angle_deg", file, "", false);
  if (std::abs(t.surface_angle_deg) >= 90)
    Fail(file, "surface_angle_deg", "must be within (-90, 90)");
  t.frames = ParseFrames(Require(j, "frames", file, ""), file, t.warnings);
  // The frame rate: required, unless a camera file records it (then both must agree).
  if (t.frames.is_camera_file()) {
    std::optional<double> fps;
    if (j.contains("fps")) fps = Number(j, "fps", file, "", true);
    CheckCameraFile(t, file, fps);
  } else if (t.frames.is_video() && !j.contains("fps") && !tracking::IsCameraFile(t.frames.video)) {
    t.fps = ContainerRate(t, file);
  } else {
    t.fps = Number(j, "fps", file, "", true);
  }
  if (const auto why = tracking::FpsOutOfRange(t.fps)) Fail(file, "fps", *why);
  t.camera = ParseCamera(Require(j, "camera", file, ""), file, t.warnings);
  const std::string& from = t.camera.scale_from;
  if ((from.empty() || from == "m_per_px") && !(t.camera.m_per_px > 0) &&
      !(from.empty() && t.body.is_ball() && t.body.diameter_m > 0))
    Fail(file, "camera.m_per_px",
         "is missing (a ball's body.diameter_m, or camera.scale_from \"gravity\", can give the "
         "scale instead)");
  if (from == "body_diameter" && !(t.body.is_ball() && t.body.diameter_m > 0))
    Fail(file, "camera.scale_from",
         "is \"body_diameter\" but the body is not a ball with a diameter_m");
  if ((from == "gravity" || from == "markers") && !t.body.is_silhouette() &&
      !(t.camera.m_per_px > 0))
    Fail(file, "camera.m_per_px",
         "is missing: the marker tracker needs an approximate scale to match the markers to the "
         "layout, even when camera.scale_from \"" +
             from + "\" gives the scale used");
  for (const auto& [kind, c] : {std::pair<const char*, const std::optional<CalibrationImageSpec>*>{
                                    "checkerboard", &t.camera.checkerboard},
                                {"ruler", &t.camera.ruler}})
    if (*c && !(*c)->image.empty() && from == kind && !fs::is_regular_file(trial_dir / (*c)->image))
      Fail(file, std::string("camera.") + kind + ".image",
           "names " + (trial_dir / (*c)->image).string() + ", which is not a file");
  if (from == "markers" && t.body.is_silhouette())
    Fail(file, "camera.scale_from", "is \"markers\" but the body is tracked by its silhouette");
  if (from == "end_radius" && !(t.body.is_silhouette() && !t.body.is_ball()))
    Fail(file, "camera.scale_from",
         "is \"end_radius\" but the body is not an unmarked outline (a ball's scale is "
         "\"body_diameter\")");
  if (t.body.is_ball()) {
    if (t.body.diameter_m > 0) t.specimen.end_radius_m = t.body.diameter_m / 2;
    t.specimen.d_EC_m = 0.0;  // a ball's centre is its round end's centre and its mass centre
  }

  if (j.contains("surface_line_px")) {
    const json& l = j.at("surface_line_px");
    if (!l.is_array() || l.size() != 2) Fail(file, "surface_line_px", "must be [[x, y], [x, y]]");
    t.surface_line_px = std::array<Eigen::Vector2d, 2>{Pair(l[0], file, "surface_line_px[0]"),
                                                       Pair(l[1], file, "surface_line_px[1]")};
  }
  if (j.contains("nominal_speed_m_s"))
    t.nominal_speed_m_s = Number(j, "nominal_speed_m_s", file, "", true);
  if (j.contains("notes") && j.at("notes").is_string()) t.notes = j.at("notes").get<std::string>();
  return t;
}

TrialSpec ReadTrial(const fs::path& trial_dir, const std::optional<fs::path>& study_json) {
  fs::path trial_abs = fs::absolute(trial_dir).lexically_normal();
  if (!trial_abs.has_filename()) trial_abs = trial_abs.parent_path();  // trailing separator
  const fs::path study_dir = study_json ? study_json->parent_path() : trial_abs.parent_path();
  if (study_json && study_json->filename() != "study.json")
    throw std::runtime_error(study_json->string() + ": a study file must be named study.json");
  if (!fs::exists(study_dir / "study.json")) {
    // Only a trial that carries its specimen inline can be read without a study.
    StudySpec none;
    none.dir = study_dir;
    try {
      return ReadTrial(trial_dir, none);
    } catch (const std::runtime_error& e) {
      if (std::string(e.what()).find("does not define") == std::string::npos) throw;
      throw std::runtime_error((trial_dir / "trial.json").string() +
                               ": no study.json beside the trial folder defines its specimen, "
                               "and the trial has no specimen_parameters (give one with --study)");
    }
  }
  return ReadTrial(trial_dir, ReadStudy(study_dir));
}

std::unique_ptr<tracking::FrameSource> OpenFrames(const TrialSpec& spec) {
  const fs::path trial_json = spec.dir / "trial.json";
  if (spec.frames.is_camera_file()) {
    auto clip = tracking::OpenCameraFile(spec.dir / spec.frames.camera_file);
    if (spec.frames.first == 0 && spec.frames.count == clip->count()) return clip;
    try {
      return std::make_unique<tracking::FrameRangeSource>(std::move(clip), spec.frames.first,
                                                          spec.frames.count);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(trial_json.string() + ": frames of " +
                               (spec.dir / spec.frames.camera_file).string() + ": " + e.what());
    }
  }
  if (spec.frames.is_video()) {
    // A camera file (.mraw, .cine, .tif) named as a video is read by its own reader.
    if (tracking::IsCameraFile(spec.frames.video))
      return tracking::OpenCameraFile(spec.dir / spec.frames.video);
    return std::make_unique<tracking::VideoSource>(spec.dir / spec.frames.video);
  }
  try {
    return std::make_unique<tracking::ImageSequenceSource>(spec.dir, spec.frames.pattern,
                                                           spec.frames.first, spec.frames.count);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(trial_json.string() + ": " + e.what());
  }
}

}  // namespace hoof::pipeline
