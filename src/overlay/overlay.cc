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
#include "compare/replay_convention.h"
#include "core/frames.h"
#include "format/number_format.h"
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

/// The trial's folder: where the study file recorded it, else under the study folder's new
/// place (`moved_study_dir`), else by its name in the recorded study folder.
fs::path FindTrialDir(const studyfile::TrialResult& r, const fs::path& study_dir,
                      const fs::path& moved_study_dir, const fs::path& h5) {
  const compare::replay::TrialFolderSearch s =
      compare::replay::LocateTrialFolder(r.dir, study_dir, moved_study_dir);
  if (s.found) return *s.found;
  throw std::runtime_error(h5.string() + ": trial " + r.id + ": " +
                           compare::replay::NotFoundMessage(s, !moved_study_dir.empty()));
}

/// Everything RenderTrialOverlay needs from the study file and the trial folder.
struct TrialData {
  studyfile::TrialResult result;
  pipeline::TrialSpec spec;
  tracking::ImageToWorld camera;
  std::vector<compare::FrameComparison> frames;  ///< the simulation against the measurement
  double t_touch_s = kNaN;
  fs::path dir;  ///< the trial folder the frames are read from
};

TrialData LoadTrial(const fs::path& h5, const std::string& id, const fs::path& moved_study_dir) {
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
  d.dir = FindTrialDir(d.result, results.study_dir, moved_study_dir, h5);
  const fs::path& trial_dir = d.dir;
  // study.json of the study folder the trial was found in (its specimens).
  fs::path study_json = fs::path(results.study_dir) / "study.json";
  if (!moved_study_dir.empty() && fs::exists(moved_study_dir / "study.json"))
    study_json = moved_study_dir / "study.json";
  d.spec = pipeline::ReadTrial(
      trial_dir, fs::exists(study_json) ? std::optional<fs::path>(study_json) : std::nullopt);
  std::vector<std::string> markers;
  if (!d.spec.body.is_silhouette())  // the comparison carries markers only where they were tracked
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

FrameOverlay BuildFrame(const TrialData& d, std::size_t f, const OverlayOptions& opt,
                        const std::string& pace) {
  FrameOverlay o;
  o.frame = static_cast<int>(f);
  o.title = d.spec.id;
  o.residual_scale = opt.residual_scale;
  o.pace = pace;
  o.t_since_impact_s = static_cast<double>(f) / d.spec.fps - d.result.impact_time_s;
  const auto& sp = d.spec.specimen;
  if (f >= d.frames.size()) return o;
  const compare::FrameComparison& fc = d.frames[f];
  o.markers_sim_px = fc.markers_px_sim;
  o.markers_meas_px = fc.markers_px_meas;
  if (sp.markers_B_m.empty() || d.spec.body.is_silhouette()) {
    // No markers (a ball, an unmarked outline): the centre of mass is the point compared.
    o.centre_of_mass = true;
    o.markers_sim_px = {fc.centre_px_sim};
    o.markers_meas_px = {fc.centre_px_meas};
  }
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
  std::string s = "frame " + std::to_string(o.frame);
  if (std::isfinite(o.t_since_impact_s))
    s += "   t = " + std::string(o.t_since_impact_s >= 0 ? "+" : "") +
         format::Number(o.t_since_impact_s * 1e3) + " ms from impact";
  return s;
}

/// A glyph's colour as OpenCV's BGR.
cv::Scalar Bgr(const compare::replay::Glyph& g) { return {double(g.b), double(g.g), double(g.r)}; }

/// Writes `frames` into a video at `path` with `fourcc`; false when the encoder is missing.
bool TryVideo(const fs::path& path, int fourcc, const std::vector<fs::path>& frames,
              const VideoPace& pace) {
  const cv::Mat first = cv::imread(frames.front().string(), cv::IMREAD_COLOR);
  cv::VideoWriter w(path.string(), cv::CAP_FFMPEG, fourcc, pace.video_fps, first.size(), true);
  if (!w.isOpened()) w.open(path.string(), fourcc, pace.video_fps, first.size(), true);
  if (!w.isOpened()) {
    std::error_code ec;
    fs::remove(path, ec);  // a failed attempt's leftovers
    return false;
  }
  for (const auto& f : frames) {
    const cv::Mat img = cv::imread(f.string(), cv::IMREAD_COLOR);
    for (int k = 0; k < pace.repeats; ++k) w.write(img);
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

std::vector<std::pair<std::string, cv::Scalar>> OverlayLegend(const FrameOverlay& o) {
  using namespace compare::replay;
  const cv::Scalar yellow(0, 230, 255), white(255, 255, 255);
  std::vector<std::pair<std::string, cv::Scalar>> lines;
  if (!o.title.empty()) lines.emplace_back(o.title, white);
  lines.emplace_back(Stamp(o), white);
  if (o.centre_of_mass) {
    lines.emplace_back(std::string(kMeasured.symbol) + "  " + kMeasuredCentre.label,
                       Bgr(kMeasured));
    lines.emplace_back(std::string(kSimulated.symbol) + "  " + kSimulatedCentre.label + ", outline",
                       Bgr(kSimulated));
  } else {
    lines.emplace_back(std::string(kMeasured.symbol) + "  " + kMeasured.label, Bgr(kMeasured));
    lines.emplace_back(std::string(kSimulated.symbol) + "  " + kSimulated.label + ", outline",
                       Bgr(kSimulated));
  }
  if (o.residual_scale > 0)
    lines.emplace_back(std::string(kResidual.symbol) + " " + kResidual.label + " x " +
                           std::to_string(o.residual_scale) + " (sim. - meas.)",
                       Bgr(kResidual));
  if (o.has_contact) lines.emplace_back("<> contact T, surface (sim.)", yellow);
  if (!o.pace.empty()) lines.emplace_back("video " + o.pace, white);
  return lines;
}

namespace {
/// Text metrics of the legend for an image of `size`.
struct LegendMetrics {
  int thick;
  double font;
  int line;  ///< line height (px)
};
LegendMetrics MetricsFor(const cv::Size& size) {
  const double s = std::min(size.width, size.height);
  LegendMetrics m;
  m.thick = std::max(1, static_cast<int>(std::lround(s / 400)));
  m.font = std::max(0.4, s / 900);
  m.line = static_cast<int>(std::lround(28 * m.font)) + 4;
  return m;
}
}  // namespace

cv::Rect LegendRect(const cv::Size& size, const FrameOverlay& o) {
  const LegendMetrics m = MetricsFor(size);
  int width = 0, base = 0;
  const auto lines = OverlayLegend(o);
  for (const auto& l : lines)
    width = std::max(
        width, cv::getTextSize(l.first, cv::FONT_HERSHEY_SIMPLEX, m.font, m.thick, &base).width);
  const int w = std::min(size.width, width + 16);
  const int h = std::min(size.height, m.line * static_cast<int>(lines.size()) + m.line / 2);
  const bool right = o.legend_corner == 1 || o.legend_corner == 3;
  const bool bottom = o.legend_corner >= 2;
  return {right ? size.width - w : 0, bottom ? size.height - h : 0, w, h};
}

int LegendCorner(const cv::Size& size, const std::vector<FrameOverlay>& frames) {
  int best = 0;
  long fewest = -1;
  for (int corner = 0; corner < 4; ++corner) {
    long covered = 0;
    for (FrameOverlay o : frames) {
      o.legend_corner = corner;
      const cv::Rect r = LegendRect(size, o);
      // A point counts when its glyph would reach into the box.
      const double pad = 1.5 * o.marker_radius_px;
      auto count = [&](const Eigen::Vector2d& p) {
        if (Finite(p) && p.x() >= r.x - pad && p.x() <= r.x + r.width + pad && p.y() >= r.y - pad &&
            p.y() <= r.y + r.height + pad)
          ++covered;
      };
      for (std::size_t k = 0; k < o.markers_meas_px.size(); ++k) {
        count(o.markers_meas_px[k]);
        if (k < o.markers_sim_px.size() && o.residual_scale > 0)
          count(o.markers_meas_px[k] +
                o.residual_scale * (o.markers_sim_px[k] - o.markers_meas_px[k]));
      }
      for (const auto& p : o.markers_sim_px) count(p);
      for (const auto& p : o.outline_sim_px) count(p);
    }
    if (fewest < 0 || covered < fewest) fewest = covered, best = corner;
  }
  return best;
}

cv::Mat DrawOverlay(const cv::Mat& frame, const FrameOverlay& o) {
  using namespace compare::replay;
  cv::Mat img = ToColour8(frame);
  const LegendMetrics metrics = MetricsFor(img.size());
  const int thick = metrics.thick;
  const double font = metrics.font;
  const cv::Scalar yellow(0, 230, 255);
  const cv::Scalar measured = Bgr(kMeasured), simulated = Bgr(kSimulated),
                   residual = Bgr(kResidual);
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
    cv::polylines(img, std::vector<std::vector<cv::Point>>{poly}, true, simulated, thick,
                  cv::LINE_AA, shift);
  }
  const double arm = kSimulated.size * o.marker_radius_px;
  for (const auto& p : o.markers_sim_px) {
    if (!Finite(p)) continue;
    cv::line(img, fx(p + Eigen::Vector2d(-arm, 0)), fx(p + Eigen::Vector2d(arm, 0)), simulated,
             thick, cv::LINE_AA, shift);
    cv::line(img, fx(p + Eigen::Vector2d(0, -arm)), fx(p + Eigen::Vector2d(0, arm)), simulated,
             thick, cv::LINE_AA, shift);
  }
  for (const auto& p : o.markers_meas_px)
    if (Finite(p))
      cv::circle(img, fx(p),
                 static_cast<int>(std::lround(kMeasured.size * o.marker_radius_px * 16)), measured,
                 thick, cv::LINE_AA, shift);
  // The residual arrows last, over the markers: measured -> measured + F (simulated - measured).
  if (o.residual_scale > 0) {
    const double head = kResidual.size * o.marker_radius_px;
    for (std::size_t m = 0; m < std::min(o.markers_meas_px.size(), o.markers_sim_px.size()); ++m) {
      const Eigen::Vector2d& a = o.markers_meas_px[m];
      const Eigen::Vector2d b = a + o.residual_scale * (o.markers_sim_px[m] - a);
      if (!Finite(a) || !Finite(b)) continue;
      const double length = (b - a).norm();
      if (length < 0.5) continue;  // nothing to draw
      cv::arrowedLine(img, fx(a), fx(b), residual, thick, cv::LINE_AA, shift,
                      std::min(0.5, head / length));
    }
  }
  if (o.has_contact) {
    cv::drawMarker(img, Pt(o.contact_px), yellow, cv::MARKER_DIAMOND,
                   static_cast<int>(std::lround(2 * arm)), thick, cv::LINE_AA);
  }
  // Text: title and time stamp, then the legend, on a darkened box (which keeps it legible
  // over the specimen) in the legend's corner.
  const cv::Rect box = LegendRect(img.size(), o);
  img(box) *= 0.35;
  const int line = MetricsFor(img.size()).line;
  int y = box.y + line;
  for (const auto& [s, c] : OverlayLegend(o)) {
    cv::putText(img, s, {box.x + 8, y}, cv::FONT_HERSHEY_SIMPLEX, font, cv::Scalar(0, 0, 0),
                thick + 2, cv::LINE_AA);
    cv::putText(img, s, {box.x + 8, y}, cv::FONT_HERSHEY_SIMPLEX, font, c, thick, cv::LINE_AA);
    y += line;
  }
  return img;
}

namespace {
/// A ratio for the legend: a whole number as such ("1000"), else to 3 significant digits.
std::string Ratio(double x) {
  const double whole = std::round(x);
  if (std::abs(x - whole) <= 1e-9 * std::abs(x) && std::abs(whole) < 1e15)
    return std::to_string(static_cast<long long>(whole));
  return format::Significant(x, 3);
}
}  // namespace

std::string VideoPace::Legend() const {
  return "1/" + Ratio(slowdown) + " of real time, " + Ratio(video_fps / repeats) + " frames/s";
}

VideoPace PlanVideo(double capture_fps, int slowdown) {
  if (!(capture_fps > 0) || !std::isfinite(capture_fps))
    throw std::invalid_argument("overlay: the capture's frame rate (fps) must be > 0, got " +
                                format::Number(capture_fps));
  if (slowdown < 1)
    throw std::invalid_argument("overlay: slowdown must be >= 1, got " + std::to_string(slowdown));
  VideoPace p;
  const double r = capture_fps / slowdown;
  if (r > kMaxVideoFps) {
    p.video_fps = kMaxVideoFps;
    p.repeats = 1;
    p.limited = true;
  } else {
    p.repeats = std::max(1, static_cast<int>(std::ceil(kMinVideoFps / r - 1e-9)));
    p.video_fps = r * p.repeats;
  }
  p.slowdown = capture_fps * p.repeats / p.video_fps;
  return p;
}

void OverlayOptions::Validate() const {
  if (slowdown < 1 || slowdown > 1000000)
    throw std::invalid_argument("OverlayOptions.slowdown = " + std::to_string(slowdown) +
                                ": must be in 1..1000000");
  compare::replay::ValidateResidualScale(residual_scale, "OverlayOptions.residual_scale");
  if (!write_frames && !write_video)
    throw std::invalid_argument("overlay: nothing to write (no frames, no video)");
}

OverlaySummary RenderTrialOverlay(const fs::path& h5, const std::string& id,
                                  const OverlayOptions& opt) {
  opt.Validate();
  const TrialData d = LoadTrial(h5, id, opt.study_dir);
  auto source = pipeline::OpenFrames(d.spec);  // image sequence, video or camera file
  OverlaySummary sum;
  sum.trial_dir = d.dir;
  sum.pace = PlanVideo(d.spec.fps, opt.slowdown);
  const std::string pace = opt.write_video ? sum.pace.Legend() : std::string();
  if (opt.write_video && sum.pace.limited)
    sum.warnings.push_back("a capture at " + Ratio(d.spec.fps) + " fps shown 1/" +
                           std::to_string(opt.slowdown) + " of real time would need a video at " +
                           Ratio(d.spec.fps / opt.slowdown) + " fps; it plays at " +
                           Ratio(kMaxVideoFps) + " fps, " + pace);
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
    // One legend corner for the whole trial, the one that hides the fewest marks.
    std::vector<FrameOverlay> overlays;
    for (int f = 0; f < source->count(); ++f)
      overlays.push_back(BuildFrame(d, static_cast<std::size_t>(f), opt, pace));
    const int corner = overlays.empty() ? 0 : LegendCorner(source->Read(0).size(), overlays);
    for (int f = 0; f < source->count(); ++f) {
      FrameOverlay& o = overlays[static_cast<std::size_t>(f)];
      o.legend_corner = corner;
      const cv::Mat img = DrawOverlay(source->Read(f), o);
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
                   sum.pace)) {
        sum.video = sum.dir / "overlay.webm";
        sum.video_format = "WebM (VP8)";
      } else if (TryVideo(tmp / "overlay.avi", cv::VideoWriter::fourcc('M', 'J', 'P', 'G'),
                          tmp_frames, sum.pace)) {
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
