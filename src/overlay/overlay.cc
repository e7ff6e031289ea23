#include "overlay/overlay.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "compare/comparison_tables.h"
#include "core/frames.h"
#include "io/atomic_file.h"
#include "io/interrupt.h"
#include "studyfile/study_file.h"
#include "tracking/frame_source.h"

namespace hoof::overlay {
namespace {

namespace fs = std::filesystem;
using core::kNaN;
constexpr double kPi = std::numbers::pi;

Eigen::Vector2d Dir(double a) { return {std::cos(a), std::sin(a)}; }

/// Appends the segment a -> b (without b) in steps of at most `step`.
void AddSegment(std::vector<Eigen::Vector2d>& out, const Eigen::Vector2d& a,
                const Eigen::Vector2d& b, double step) {
  const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / step)));
  for (int i = 0; i < n; ++i) out.push_back(a + (b - a) * (static_cast<double>(i) / n));
}

/// Appends the arc of radius r about the origin from angle a0 to a1 (a1 > a0; without a1).
void AddArc(std::vector<Eigen::Vector2d>& out, double r, double a0, double a1, double step) {
  const int n = std::max(1, static_cast<int>(std::ceil(r * (a1 - a0) / step)));
  for (int i = 0; i < n; ++i) out.push_back(r * Dir(a0 + (a1 - a0) * i / n));
}

/// The trial folder recorded in the study file: as written, or, when the study was run from
/// another working directory, the folder of that name in the study folder.
fs::path FindTrialDir(const studyfile::TrialResult& r, const fs::path& study_dir,
                      const fs::path& h5) {
  const fs::path dir = r.dir;
  if (fs::exists(dir / "trial.json")) return dir;
  if (!study_dir.empty() && fs::exists(study_dir / dir.filename() / "trial.json"))
    return study_dir / dir.filename();
  throw std::runtime_error(h5.string() + ": trial " + r.id + ": its folder " + dir.string() +
                           " (recorded in the study file) has no trial.json");
}

std::unique_ptr<tracking::FrameSource> OpenFrames(const pipeline::TrialSpec& spec) {
  if (spec.frames.is_video())
    return std::make_unique<tracking::VideoSource>(spec.dir / spec.frames.video);
  return std::make_unique<tracking::ImageSequenceSource>(spec.dir, spec.frames.pattern,
                                                         spec.frames.first, spec.frames.count);
}

/// Everything RenderTrialOverlay needs from the study file and the trial folder.
struct TrialData {
  studyfile::TrialResult result;
  pipeline::TrialSpec spec;
  tracking::ImageToWorld camera;
  std::vector<compare::FrameComparison> frames;  ///< the simulation against the measurement
  double t_touch_s = kNaN;
};

TrialData LoadTrial(const fs::path& h5, const std::string& id) {
  TrialData d;
  const studyfile::StudyResults results = studyfile::ReadStudyResults(h5);
  const auto it = std::find_if(results.trials.begin(), results.trials.end(),
                               [&](const auto& t) { return t.id == id; });
  if (it == results.trials.end()) {
    std::string ids;
    for (const auto& t : results.trials) ids += (ids.empty() ? "" : ", ") + t.id;
    throw std::runtime_error(h5.string() + ": no trial with id '" + id + "' (trials: " + ids + ")");
  }
  d.result = *it;
  if (!compare::HasComparison(h5))
    throw std::runtime_error(h5.string() +
                             " has no /comparison (the simulation against the "
                             "measurement): run `hoofimpact run` first");
  const std::vector<compare::ComparedTrial> compared = compare::ReadComparedTrials(h5);
  const auto row = std::find_if(compared.begin(), compared.end(),
                                [&](const compare::ComparedTrial& t) { return t.id == id; });
  if (row == compared.end() || !row->comparison.success) {
    const std::string why = row == compared.end() ? "" : row->comparison.message;
    throw std::runtime_error(h5.string() + ": trial '" + id +
                             "' was not simulated against its "
                             "measurement" +
                             (why.empty() ? "" : ": " + why));
  }
  d.t_touch_s = row->comparison.t_touch_s;
  const fs::path trial_dir = FindTrialDir(d.result, results.study_dir, h5);
  const fs::path study_json = fs::path(results.study_dir) / "study.json";
  d.spec = pipeline::ReadTrial(
      trial_dir, fs::exists(study_json) ? std::optional<fs::path>(study_json) : std::nullopt);
  std::vector<std::string> markers;
  for (const auto& [name, p_B] : d.spec.specimen.markers_B_m) markers.push_back(name);
  d.frames = compare::ReadComparedFrames(h5, id, markers);
  d.camera.m_per_px = d.result.m_per_px_used;  // the scale the comparison used
  d.camera.gravity_I = d.spec.camera.gravity_image;
  d.camera.camera_matrix = d.spec.camera.camera_matrix;
  d.camera.distortion = d.spec.camera.distortion;
  return d;
}

/// Simulated pose of C at time t (s since frame 0), linear between frames.
std::pair<Eigen::Vector2d, double> SimPoseAt(const TrialData& d, double t) {
  const auto& fr = d.frames;
  const double f = std::clamp(t * d.spec.fps, 0.0, static_cast<double>(fr.size() - 1));
  const auto i = std::min(static_cast<std::size_t>(f), fr.size() - (fr.size() > 1 ? 2 : 1));
  const double a = fr.size() > 1 ? f - static_cast<double>(i) : 0.0;
  const std::size_t j = std::min(i + 1, fr.size() - 1);
  return {fr[i].p_WC_sim + a * (fr[j].p_WC_sim - fr[i].p_WC_sim),
          fr[i].theta_W_sim_rad + a * (fr[j].theta_W_sim_rad - fr[i].theta_W_sim_rad)};
}

FrameOverlay BuildFrame(const TrialData& d, std::size_t f) {
  FrameOverlay o;
  o.frame = static_cast<int>(f);
  o.title = d.spec.id;
  o.t_since_impact_s = static_cast<double>(f) / d.spec.fps - d.result.impact_time_s;
  const auto& sp = d.spec.specimen;
  if (f >= d.frames.size()) return o;
  const compare::FrameComparison& fc = d.frames[f];
  o.markers_sim_px = fc.markers_px_sim;
  o.markers_meas_px = fc.markers_px_meas;
  o.outline_sim_px = OutlineToImage(sp, fc.p_WC_sim, fc.theta_W_sim_rad, d.camera);
  // Contact point T at first touch: the round end's lowest point along the surface normal y_S.
  if (std::isfinite(d.t_touch_s)) {
    const auto [p_WC_touch, theta_touch] = SimPoseAt(d, d.t_touch_s);
    const auto R_WS = core::SurfaceRotation::FromDegrees(d.spec.surface_angle_deg);
    const Eigen::Vector2d& x_S = R_WS.x_S();
    const Eigen::Vector2d& y_S = R_WS.y_S();
    const Eigen::Vector2d p_WT = p_WC_touch - sp.d_EC_m * Dir(theta_touch) - sp.end_radius_m * y_S;
    const double half = std::max(sp.length_m, 4 * sp.end_radius_m);
    o.has_contact = true;
    o.contact_px = d.camera.ToImage(p_WT);
    o.surface_a_px = d.camera.ToImage(p_WT - half * x_S);
    o.surface_b_px = d.camera.ToImage(p_WT + half * x_S);
  }
  o.marker_radius_px = std::max(4.0, 0.6 * 1e-3 / d.camera.m_per_px);
  return o;
}

cv::Point2d Pt(const Eigen::Vector2d& p) { return {p.x(), p.y()}; }
bool Finite(const Eigen::Vector2d& p) { return std::isfinite(p.x()) && std::isfinite(p.y()); }

cv::Mat ToColour8(const cv::Mat& frame) {
  cv::Mat grey = frame.channels() == 1 ? frame : tracking::ToGrey(frame, "overlay frame");
  cv::Mat u8;
  if (grey.depth() == CV_8U)
    u8 = grey;
  else
    tracking::ToUnitFloat(grey).convertTo(u8, CV_8U, 255.0);
  cv::Mat bgr;
  cv::cvtColor(u8, bgr, cv::COLOR_GRAY2BGR);
  return bgr;
}

std::string Stamp(const FrameOverlay& o) {
  char buf[128];
  if (std::isfinite(o.t_since_impact_s))
    std::snprintf(buf, sizeof buf, "frame %d   t = %+.3f ms from impact", o.frame,
                  o.t_since_impact_s * 1e3);
  else
    std::snprintf(buf, sizeof buf, "frame %d", o.frame);
  return buf;
}

/// Writes `frames` into a video at `path` with `fourcc`; false when the encoder is missing.
bool TryVideo(const fs::path& path, int fourcc, const std::vector<fs::path>& frames,
              const OverlayOptions& opt) {
  const cv::Mat first = cv::imread(frames.front().string(), cv::IMREAD_COLOR);
  cv::VideoWriter w(path.string(), cv::CAP_FFMPEG, fourcc, opt.video_fps, first.size(), true);
  if (!w.isOpened()) w.open(path.string(), fourcc, opt.video_fps, first.size(), true);
  if (!w.isOpened()) {
    std::error_code ec;
    fs::remove(path, ec);  // a failed attempt's leftovers
    return false;
  }
  for (const auto& f : frames) {
    const cv::Mat img = cv::imread(f.string(), cv::IMREAD_COLOR);
    for (int k = 0; k < opt.slow; ++k) w.write(img);
  }
  w.release();
  return fs::exists(path) && fs::file_size(path) > 0;
}

}  // namespace

std::vector<Eigen::Vector2d> OutlineInBody(const pipeline::SpecimenSpec& s, double max_step_m) {
  if (!(max_step_m > 0)) throw std::invalid_argument("OutlineInBody: max_step_m must be > 0");
  const double r = s.end_radius_m, h = s.width_m / 2, far = s.length_m - r;
  std::vector<Eigen::Vector2d> out;
  if (!(s.length_m > 0 && s.width_m > 0 && far > 0)) {
    AddArc(out, r, 0, 2 * kPi, max_step_m);
    return out;
  }
  // Far end, then the upper edge back to where it meets the round end, the arc around the
  // back, and the lower edge.
  const bool narrow = h < r;
  const double x_meet = narrow ? std::sqrt(r * r - h * h) : 0.0;
  const double a0 = narrow ? std::atan2(h, x_meet) : kPi / 2;
  AddSegment(out, {far, -h}, {far, h}, max_step_m);
  AddSegment(out, {far, h}, {x_meet, h}, max_step_m);
  if (!narrow) AddSegment(out, {0, h}, {0, r}, max_step_m);
  AddArc(out, r, a0, 2 * kPi - a0, max_step_m);
  if (!narrow) AddSegment(out, {0, -r}, {0, -h}, max_step_m);
  AddSegment(out, {x_meet, -h}, {far, -h}, max_step_m);
  return out;
}

Eigen::Vector2d BodyPointToImage(const Eigen::Vector2d& p_B, const Eigen::Vector2d& p_WC,
                                 double theta_W_rad, double d_EC_m,
                                 const tracking::ImageToWorld& camera) {
  const core::BodyRotation R_WB(theta_W_rad);
  const Eigen::Vector2d p_WE = p_WC - d_EC_m * R_WB.x_B();
  return camera.ToImage(p_WE + R_WB.ToW(p_B));
}

std::vector<Eigen::Vector2d> OutlineToImage(const pipeline::SpecimenSpec& specimen,
                                            const Eigen::Vector2d& p_WC, double theta_W_rad,
                                            const tracking::ImageToWorld& camera) {
  std::vector<Eigen::Vector2d> out;
  for (const auto& p : OutlineInBody(specimen, 2e-4))
    out.push_back(BodyPointToImage(p, p_WC, theta_W_rad, specimen.d_EC_m, camera));
  return out;
}

cv::Mat DrawOverlay(const cv::Mat& frame, const FrameOverlay& o) {
  cv::Mat img = ToColour8(frame);
  const double size = std::min(img.cols, img.rows);
  const int thick = std::max(1, static_cast<int>(std::lround(size / 400)));
  const double font = std::max(0.4, size / 900);
  const cv::Scalar red(40, 40, 255), green(0, 220, 0), yellow(0, 230, 255), white(255, 255, 255);
  const int shift = 4;  // sub-pixel drawing: coordinates * 16
  auto fx = [&](const Eigen::Vector2d& p) {
    return cv::Point(static_cast<int>(std::lround(p.x() * 16)),
                     static_cast<int>(std::lround(p.y() * 16)));
  };
  if (o.has_contact) {
    cv::line(img, fx(o.surface_a_px), fx(o.surface_b_px), yellow, thick, cv::LINE_AA, shift);
  }
  if (!o.outline_sim_px.empty()) {
    std::vector<cv::Point> poly;
    for (const auto& p : o.outline_sim_px)
      if (Finite(p)) poly.push_back(fx(p));
    cv::polylines(img, std::vector<std::vector<cv::Point>>{poly}, true, red, thick, cv::LINE_AA,
                  shift);
  }
  for (const auto& p : o.markers_sim_px)
    if (Finite(p))
      cv::circle(img, fx(p), static_cast<int>(o.marker_radius_px * 16), red, thick, cv::LINE_AA,
                 shift);
  const double arm = std::max(3.0, 0.6 * o.marker_radius_px);
  for (const auto& p : o.markers_meas_px) {
    if (!Finite(p)) continue;
    cv::line(img, fx(p + Eigen::Vector2d(-arm, 0)), fx(p + Eigen::Vector2d(arm, 0)), green, thick,
             cv::LINE_AA, shift);
    cv::line(img, fx(p + Eigen::Vector2d(0, -arm)), fx(p + Eigen::Vector2d(0, arm)), green, thick,
             cv::LINE_AA, shift);
  }
  if (o.has_contact) {
    cv::drawMarker(img, Pt(o.contact_px), yellow, cv::MARKER_DIAMOND, static_cast<int>(2 * arm),
                   thick, cv::LINE_AA);
  }
  // Text: title and time stamp at the top left, the legend below.
  const int line = static_cast<int>(std::lround(28 * font)) + 4;
  int y = line;
  auto text = [&](const std::string& s, const cv::Scalar& c) {
    cv::putText(img, s, {8, y}, cv::FONT_HERSHEY_SIMPLEX, font, cv::Scalar(0, 0, 0), thick + 2,
                cv::LINE_AA);
    cv::putText(img, s, {8, y}, cv::FONT_HERSHEY_SIMPLEX, font, c, thick, cv::LINE_AA);
    y += line;
  };
  std::vector<std::pair<std::string, cv::Scalar>> lines;
  if (!o.title.empty()) lines.emplace_back(o.title, white);
  lines.emplace_back(Stamp(o), white);
  lines.emplace_back("+ measured markers", green);
  lines.emplace_back("o simulated markers and outline", red);
  if (o.has_contact)
    lines.emplace_back("<> contact point T at first touch (sim.), surface", yellow);
  // A darkened box behind the text keeps it legible over the specimen.
  int width = 0, base = 0;
  for (const auto& l : lines)
    width = std::max(width,
                     cv::getTextSize(l.first, cv::FONT_HERSHEY_SIMPLEX, font, thick, &base).width);
  const cv::Rect box =
      cv::Rect(0, 0, width + 16, line * static_cast<int>(lines.size()) + line / 2) &
      cv::Rect(0, 0, img.cols, img.rows);
  img(box) *= 0.35;
  for (const auto& l : lines) text(l.first, l.second);
  return img;
}

void OverlayOptions::Validate() const {
  if (slow < 1)
    throw std::invalid_argument("overlay: slow must be >= 1, got " + std::to_string(slow));
  if (!(video_fps > 0)) throw std::invalid_argument("overlay: video_fps must be > 0");
  if (!write_frames && !write_video)
    throw std::invalid_argument("overlay: nothing to write (no frames, no video)");
}

OverlaySummary RenderTrialOverlay(const fs::path& h5, const std::string& id,
                                  const OverlayOptions& opt) {
  opt.Validate();
  const TrialData d = LoadTrial(h5, id);
  auto source = OpenFrames(d.spec);
  OverlaySummary sum;
  const std::string group = fs::path(d.result.group).filename().string();
  sum.dir = opt.output_dir / group;
  fs::create_directories(opt.output_dir);
  // ".<group>.tmp-<pid>-<n>": removed by an interrupt, and by a later run if this one is killed.
  const fs::path tmp = io::TemporaryPathFor(opt.output_dir / ("." + group));
  {
    const io::CreatingTemporary creating;
    fs::create_directories(tmp);
  }
  try {
    std::vector<fs::path> tmp_frames;
    for (int f = 0; f < source->count(); ++f) {
      const cv::Mat img = DrawOverlay(source->Read(f), BuildFrame(d, static_cast<std::size_t>(f)));
      char name[32];
      std::snprintf(name, sizeof name, "frame_%06d.png", f);
      tmp_frames.push_back(tmp / name);
      if (!cv::imwrite(tmp_frames.back().string(), img))
        throw std::runtime_error("cannot write " + tmp_frames.back().string());
      sum.frame_files.push_back(sum.dir / name);
    }
    sum.frames = source->count();
    if (opt.write_video && !tmp_frames.empty()) {
      if (TryVideo(tmp / "overlay.webm", cv::VideoWriter::fourcc('V', 'P', '8', '0'), tmp_frames,
                   opt)) {
        sum.video = sum.dir / "overlay.webm";
        sum.video_format = "WebM (VP8)";
      } else if (TryVideo(tmp / "overlay.avi", cv::VideoWriter::fourcc('M', 'J', 'P', 'G'),
                          tmp_frames, opt)) {
        sum.video = sum.dir / "overlay.avi";
        sum.video_format = "AVI (MJPG)";
      } else {
        sum.warnings.push_back("no video encoder (VP8 or MJPG) available: video not written");
      }
    }
    if (!opt.write_frames) {
      for (const auto& f : tmp_frames) fs::remove(f);
      sum.frame_files.clear();
    }
    fs::remove_all(sum.dir);
    fs::rename(tmp, sum.dir);
    io::UntrackTemporary(tmp);
  } catch (...) {
    std::error_code ec;
    fs::remove_all(tmp, ec);
    io::UntrackTemporary(tmp);
    throw;
  }
  return sum;
}

}  // namespace hoof::overlay
