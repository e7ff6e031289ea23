#include "pipeline/calibration_scale.h"

#include <cmath>
#include <memory>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "pipeline/trial_analysis.h"

namespace hoof::pipeline {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

/// An image file (PNG, TIFF, any format OpenCV reads; 8- or 16-bit, grey or colour), as grey.
cv::Mat ReadImage(const fs::path& path, const std::string& field) {
  if (!fs::is_regular_file(path))
    throw std::runtime_error(path.string() + ": the calibration image (" + field +
                             ") does not exist");
  const cv::Mat image = cv::imread(path.string(), cv::IMREAD_ANYDEPTH | cv::IMREAD_GRAYSCALE);
  if (image.empty())
    throw std::runtime_error(path.string() + ": the calibration image (" + field +
                             ") cannot be read as an image");
  return image;
}

tracking::CalibrationScale Measure(const std::string& kind, const CalibrationImageSpec& c,
                                   const cv::Mat& image, const tracking::ImageToWorld& lens,
                                   const std::string& name) {
  if (kind == "checkerboard")
    return tracking::MeasureCheckerboard(image, c.cols, c.rows, c.square_m, lens, name);
  return tracking::MeasureRuler(image, c.from_px, c.to_px, c.tick_m, lens, name);
}

}  // namespace

bool UsesCalibrationImage(const TrialSpec& spec) {
  return spec.camera.scale_from == "checkerboard" || spec.camera.scale_from == "ruler";
}

tracking::CalibrationScale MeasureCalibrationScale(const TrialSpec& spec) {
  const std::string& kind = spec.camera.scale_from;
  const auto& c = kind == "checkerboard" ? spec.camera.checkerboard : spec.camera.ruler;
  const std::string field = "camera." + kind;
  const fs::path trial_json = spec.dir / "trial.json";
  if (!c) throw std::runtime_error(trial_json.string() + ": field \"" + field + "\" is missing");
  cv::Mat image;
  std::string name;
  if (!c->image.empty()) {
    const fs::path path = spec.dir / c->image;
    image = ReadImage(path, field + ".image");
    name = path.string() + " (" + field + ".image)";
  } else {
    auto source = OpenFrames(spec);
    if (c->frame >= source->count())
      throw std::runtime_error(trial_json.string() + ": field \"" + field + ".frame\" is " +
                               std::to_string(c->frame) + ", but the clip has " +
                               std::to_string(source->count()) + " frames");
    image = source->Read(c->frame);
    name = source->Describe(c->frame) + " (" + field + ".frame)";
  }
  return Measure(kind, *c, image, TrialCamera(spec, 1.0), name);
}

void UseCalibrationScale(const InitCalibration& c, const fs::path& trial_dir, TrialSetup& s) {
  if (c.kind.empty()) return;
  const std::string option = c.kind == "checkerboard" ? "--checkerboard" : "--ruler";
  const cv::Mat image = ReadImage(c.image, option);
  CalibrationImageSpec spec;
  spec.cols = c.cols;
  spec.rows = c.rows;
  spec.square_m = c.square_m;
  spec.from_px = c.from_px;
  spec.to_px = c.to_px;
  spec.tick_m = c.tick_m;
  // init writes no lens model: the image is taken as it is.
  const tracking::CalibrationScale m = Measure(c.kind, spec, image, tracking::ImageToWorld{},
                                               c.image.string() + " (" + option + ")");
  s.scale_from = c.kind;
  s.m_per_px = m.m_per_px;
  s.m_per_px_se = m.m_per_px_se;
  // What the gravity fit said of the scale no longer applies.
  std::vector<std::string> kept;
  for (const auto& w : s.warnings)
    if (s.gravity.message.empty() || w.rfind(s.gravity.message, 0) != 0) kept.push_back(w);
  s.warnings = kept;
  json t = json::parse(s.trial_json);
  const fs::path trial_abs = fs::absolute(trial_dir).lexically_normal();
  const std::string image_ref =
      fs::relative(fs::absolute(c.image).lexically_normal(), trial_abs).generic_string();
  json& camera = t["camera"];
  camera.erase("m_per_px");
  camera["scale_from"] = c.kind;
  if (c.kind == "checkerboard")
    camera["checkerboard"] = {
        {"image", image_ref}, {"inner_corners", {c.cols, c.rows}}, {"square_m", c.square_m}};
  else
    camera["ruler"] = {{"image", image_ref},
                       {"from_px", {c.from_px.x(), c.from_px.y()}},
                       {"to_px", {c.to_px.x(), c.to_px.y()}},
                       {"tick_m", c.tick_m}};
  std::ostringstream notes;
  notes << (t.contains("notes") && t["notes"].is_string() ? t["notes"].get<std::string>() : "")
        << "; the scale used is " << m.m_per_px << " +- " << m.m_per_px_se << " m/px from the "
        << c.kind << " in " << c.image.string() << " (" << m.points
        << (c.kind == "checkerboard" ? " corners" : " ticks") << ")";
  t["notes"] = notes.str();
  s.trial_json = t.dump(2) + "\n";
}

}  // namespace hoof::pipeline
