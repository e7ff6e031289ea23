#include "pipeline/trial_setup.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "format/number_format.h"
#include "pipeline/round_end.h"
#include "pipeline/study_format.h"
#include "pipeline/trial_analysis.h"
#include "tracking/camera_file.h"
#include "tracking/dot_detector.h"
#include "tracking/frame_source.h"

namespace hoof::pipeline {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

double Median(std::vector<double> v) {
  if (v.empty()) return core::kNaN;
  auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

bool IsImageFile(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp" || ext == ".pgm" ||
         ext == ".tif" || ext == ".tiff";
}

/// A folder of numbered images: the printf pattern (relative to the folder), first and count
/// of the largest group of names alike but for their number. Throws naming the folder.
void FramesOfFolder(const fs::path& dir, std::string& pattern, int& first, int& count) {
  struct Group {
    std::vector<long long> numbers;
    bool padded = true;
  };
  std::map<std::string, Group> groups;  // key: prefix \t width \t extension
  const std::regex numbered(R"(^(.*?)(\d+)$)");
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (!it->is_regular_file() || !IsImageFile(it->path())) continue;
    const std::string stem = it->path().stem().string();
    std::smatch m;
    if (!std::regex_match(stem, m, numbered) || m[2].length() > 9) continue;
    const std::string digits = m[2].str();
    const std::string key =
        m[1].str() + "\t" + std::to_string(digits.size()) + "\t" + it->path().extension().string();
    groups[key].numbers.push_back(std::stoll(digits));
  }
  if (ec) throw std::runtime_error(dir.string() + ": cannot list the folder: " + ec.message());
  const Group* best = nullptr;
  std::string best_key;
  for (const auto& [key, g] : groups)
    if (!best || g.numbers.size() > best->numbers.size()) {
      best = &g;
      best_key = key;
    }
  if (!best || best->numbers.size() < 3)
    throw std::runtime_error(dir.string() +
                             ": no numbered image frames (such as 000000.png, 000001.png, ...)");
  std::vector<long long> n = best->numbers;
  std::sort(n.begin(), n.end());
  for (std::size_t i = 1; i < n.size(); ++i)
    if (n[i] != n[i - 1] + 1)
      throw std::runtime_error(
          dir.string() + ": the numbered frames are not contiguous: " + std::to_string(n[i - 1]) +
          " is followed by " + std::to_string(n[i]));
  const auto t1 = best_key.find('\t'), t2 = best_key.find('\t', t1 + 1);
  std::string prefix = best_key.substr(0, t1);
  const std::string width = best_key.substr(t1 + 1, t2 - t1 - 1);
  std::string escaped;
  for (char c : prefix) escaped += c == '%' ? std::string("%%") : std::string(1, c);
  pattern = escaped + "%0" + width + "d" + best_key.substr(t2 + 1);
  first = static_cast<int>(n.front());
  count = static_cast<int>(n.size());
}

/// The surface angle (trial convention: descending toward +x for phi > 0) of an image line
/// with gravity along +y of the image.
double SurfaceAngleDeg(const tracking::ImageLine& line) {
  double phi = std::atan2(line.direction_I.y(), line.direction_I.x()) * 180 / M_PI;
  if (phi > 90) phi -= 180;
  if (phi <= -90) phi += 180;
  return phi;
}

/// The white dots of a marked body in `grey`: the most significant dot and the dots alike in
/// size (radii within a factor 1.5) and contrast (at least a quarter of its significance)
/// within 30 of its radii. Empty unless there are two or more: a lone bright disc (a front-lit
/// ball) is a body, not a marker.
std::vector<tracking::Dot> MarkerDots(const cv::Mat& grey) {
  const auto found = tracking::FindDots(grey, 12);
  if (found.size() < 2) return {};
  const tracking::Dot& top = found.front();
  std::vector<tracking::Dot> alike;
  for (const auto& d : found)
    if (d.radius_px < 1.5 * top.radius_px && d.radius_px > top.radius_px / 1.5 &&
        d.significance > 0.25 * top.significance && (d.p_I - top.p_I).norm() < 30 * top.radius_px)
      alike.push_back(d);
  if (alike.size() < 2) return {};
  return alike;
}

/// The study.json that defines `options.specimen`: the one beside the trial folder unless
/// `options.study_json`.
fs::path StudyFileOf(const TrialSetupOptions& options, const fs::path& trial_abs) {
  return options.study_json.empty() ? trial_abs.parent_path() / "study.json"
                                    : fs::path(options.study_json);
}

/// study.json's specimen `options.specimen` (StudyFileOf). Throws naming the file for an
/// unreadable study or an unknown id.
json SpecimenOfStudy(const TrialSetupOptions& options, const fs::path& trial_abs) {
  const fs::path study_file = StudyFileOf(options, trial_abs);
  std::ifstream in(study_file);
  if (!in) throw std::runtime_error(study_file.string() + ": cannot be read");
  json study;
  try {
    study = json::parse(in);
  } catch (const std::exception& e) {
    throw std::runtime_error(study_file.string() + ": not JSON: " + e.what());
  }
  if (!study.contains("specimens") || !study["specimens"].contains(options.specimen))
    throw std::runtime_error(study_file.string() + ": defines no specimen \"" + options.specimen +
                             "\" (--specimen)");
  return study["specimens"][options.specimen];
}

/// The scale (m/px) a marker layout gives the dots seen: the median ratio of the layout's
/// pairwise distances to the dots' (both sorted, so no identities are needed). Throws naming
/// `what` when fewer dots are seen than the layout has, or when the ratios disagree by more
/// than 15 % (a layout that is not the one seen).
double ScaleOfLayout(const json& markers_B_m, const std::vector<Eigen::Vector2d>& dots,
                     const std::string& what) {
  std::vector<Eigen::Vector2d> layout;
  if (!markers_B_m.is_object() || markers_B_m.size() < 2)
    throw std::runtime_error(what + ": markers_B_m must name at least two markers");
  for (const auto& [name, p] : markers_B_m.items()) {
    if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number())
      throw std::runtime_error(what + ": markers_B_m." + name + " must be [x, y] in metres");
    layout.emplace_back(p[0].get<double>(), p[1].get<double>());
  }
  if (dots.size() < layout.size())
    throw std::runtime_error(what + ": its layout has " + std::to_string(layout.size()) +
                             " markers, but the first frame shows " + std::to_string(dots.size()) +
                             " dots");
  auto pairwise = [](const std::vector<Eigen::Vector2d>& p) {
    std::vector<double> d;
    for (std::size_t i = 0; i < p.size(); ++i)
      for (std::size_t j = i + 1; j < p.size(); ++j) d.push_back((p[i] - p[j]).norm());
    std::sort(d.begin(), d.end());
    return d;
  };
  std::vector<Eigen::Vector2d> seen;
  for (std::size_t i = 0; i < layout.size(); ++i) seen.push_back(dots[i]);
  const auto L = pairwise(layout), D = pairwise(seen);
  std::vector<double> ratio;
  for (std::size_t k = 0; k < L.size(); ++k) ratio.push_back(L[k] / std::max(1e-9, D[k]));
  const double m = Median(ratio);
  for (double r : ratio)
    if (!(std::abs(r / m - 1) < 0.15))
      throw std::runtime_error(what +
                               ": its markers_B_m do not match the dots seen in the "
                               "first frame (their distances disagree by more than 15 %)");
  return m;
}

/// An unmarked specimen's scale from its known end radius (`end_radius_m`) over the median
/// radius of its round end's arc fitted in up to 40 frames (pipeline/round_end.h), as `track`
/// measures it with camera.scale_from "end_radius". False (with a warning) when the round end
/// is not found.
bool ScaleFromEndRadius(tracking::FrameSource& source, double end_radius_m,
                        const std::string& named, TrialSetup& s) {
  const RoundEndOffset end = MeasureRoundEnd(
      source, s.track, 0.0, TrialAnalysisOptions{}.round_end_frames, tracking::ImageToWorld{});
  if (!end.measured || !(end.radius_px > 0)) {
    s.warnings.push_back(named + ": the round end's radius was not measured (" + end.message +
                         "), so the specimen's end_radius_m gives no scale");
    return false;
  }
  s.scale_from = "end_radius";
  const EndRadiusScale scale = ScaleOfEndRadius(end_radius_m, end);
  s.m_per_px = scale.m_per_px;
  s.m_per_px_se = scale.m_per_px_se;
  return true;
}

/// A marked body's specimen: study.json's `--specimen` into `specimen` (null without one) and
/// the scale its markers_B_m give the dots of the first frame into `layout_m_per_px`. Without
/// a specimen or a layout, a warning says what trial.json still needs; nothing is invented.
void MarkedSpecimen(const TrialSetupOptions& options, const fs::path& trial_abs, TrialSetup& s,
                    json& specimen, double& layout_m_per_px) {
  const std::string dots = std::to_string(s.marker_dots_px.size()) + " white dots";
  if (options.specimen.empty()) {
    s.warnings.push_back(
        "a marked body (" + dots +
        " in the first frame) needs its specimen: the marker layout (markers_B_m) and its mass, "
        "inertia, end radius and |EC|; give --specimen ID (and --study study.json), or add "
        "\"specimen\" (an id of study.json) or \"specimen_parameters\" to trial.json before "
        "track");
    return;
  }
  specimen = SpecimenOfStudy(options, trial_abs);
  const std::string what = "specimen \"" + options.specimen + "\" (--specimen)";
  if (!specimen.contains("markers_B_m")) {
    s.warnings.push_back(what + " has no markers_B_m: add the layout of the " + dots +
                         " before track");
    return;
  }
  layout_m_per_px = ScaleOfLayout(specimen["markers_B_m"], s.marker_dots_px, what);
  s.marker_layout_known = true;
}

/// A ball's specimen: study.json's `--specimen`, which must be a ball with a positive
/// diameter_m; that diameter into `diameter_m`, where --diameter-m (`diameter_m` > 0 on entry)
/// must agree with it. Throws naming study.json and the specimen otherwise.
json BallSpecimen(const TrialSetupOptions& options, const fs::path& trial_abs,
                  const std::string& named, double& diameter_m) {
  json specimen = SpecimenOfStudy(options, trial_abs);
  const std::string what = StudyFileOf(options, trial_abs).string() + ": specimen \"" +
                           options.specimen + "\" (--specimen)";
  if (!specimen.is_object() || !specimen.contains("shape") || specimen["shape"] != "ball")
    throw std::runtime_error(what +
                             " is not a ball (it has no \"shape\": \"ball\"), but the "
                             "body found in " +
                             named + " is one");
  if (!specimen.contains("diameter_m") || !specimen["diameter_m"].is_number() ||
      !(specimen["diameter_m"].get<double>() > 0))
    throw std::runtime_error(what + " gives no positive diameter_m");
  const double d = specimen["diameter_m"].get<double>();
  if (diameter_m > 0 && std::abs(diameter_m - d) > 1e-9 * d) {
    std::ostringstream os;
    os << "--diameter-m " << diameter_m << " disagrees with " << what << ", whose diameter_m is "
       << d;
    throw std::runtime_error(os.str());
  }
  diameter_m = d;
  return specimen;
}

/// A two-marker layout's spacing cannot be checked against the dots (one distance only): where
/// gravity gives a scale, a layout scale off by more than 10 % and three of gravity's standard
/// errors is a warning (a wrong markers_B_m or frame rate).
void CheckLayoutAgainstGravity(TrialSetup& s) {
  if (!s.gravity.measured || !(s.gravity.m_per_px > 0)) return;
  const double off = s.m_per_px - s.gravity.m_per_px;
  if (std::abs(off) > 0.1 * s.gravity.m_per_px && std::abs(off) > 3 * s.gravity.m_per_px_se) {
    std::ostringstream os;
    os << "the markers' spacing gives " << s.m_per_px << " m/px, but gravity's parabola "
       << s.gravity.m_per_px << " +- " << s.gravity.m_per_px_se
       << " m/px: check the specimen's markers_B_m and the frame rate";
    s.warnings.push_back(os.str());
  }
}

/// A marked body: white dots on black patches in the first frame (or as --body markers says).
/// Follows each dot through the clip (a predicted search window, as the marker tracker) and
/// puts the dots' mean in `c_px` where all are seen: the impacts and gravity's scale come from
/// it. Returns false (and changes nothing) when the body is not a marked one.
bool SetUpMarkers(tracking::FrameSource& source, const TrialSetupOptions& options, TrialSetup& s,
                  std::vector<std::optional<Eigen::Vector2d>>& c_px, double& travel) {
  if (options.body != "auto" && options.body != "markers") return false;
  const cv::Mat first = tracking::ToGrey(source.Read(0), source.Describe(0));
  const std::vector<tracking::Dot> dots = MarkerDots(first);
  if (dots.size() < 2) {
    if (options.body == "markers")
      throw std::runtime_error(source.Describe(0) +
                               ": --body markers, but fewer than two white dots alike are seen "
                               "in the first frame");
    return false;
  }
  s.shape = "markers";
  s.marker_dot_radius_px = Median([&] {
    std::vector<double> r;
    for (const auto& d : dots) r.push_back(d.radius_px);
    return r;
  }());
  std::vector<Eigen::Vector2d> p, v(dots.size(), Eigen::Vector2d::Zero());
  for (const auto& d : dots) p.push_back(d.p_I);
  s.marker_dots_px = p;
  const Eigen::Vector2d start = [&] {
    Eigen::Vector2d c = Eigen::Vector2d::Zero();
    for (const auto& q : p) c += q;
    return Eigen::Vector2d(c / static_cast<double>(p.size()));
  }();
  travel = 0;
  for (int f = 0; f < source.count(); ++f) {
    const cv::Mat grey = f == 0 ? first : tracking::ToGrey(source.Read(f), source.Describe(f));
    std::vector<Eigen::Vector2d> seen;
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    for (std::size_t i = 0; i < p.size(); ++i) {
      const Eigen::Vector2d predicted = p[i] + v[i];
      const double search = std::max(6.0, 0.5 * s.marker_dot_radius_px + 3 * v[i].norm());
      const auto d = f == 0
                         ? std::optional<tracking::Dot>(dots[i])
                         : tracking::FindDotNear(grey, predicted, search, s.marker_dot_radius_px);
      if (d) {
        if (f > 0) v[i] = d->p_I - p[i];
        p[i] = d->p_I;
        seen.push_back(d->p_I);
        sum += d->p_I;
      } else {
        p[i] = predicted;
      }
    }
    if (seen.size() == p.size()) {
      const Eigen::Vector2d c = sum / static_cast<double>(seen.size());
      c_px.emplace_back(c);
      travel = std::max(travel, (c - start).norm());
      s.marker_frames_px.push_back(seen);
    } else {
      c_px.emplace_back(std::nullopt);
      s.marker_frames_px.emplace_back();
      s.warnings.push_back(source.Describe(f) + ": " + std::to_string(p.size() - seen.size()) +
                           " of the " + std::to_string(p.size()) + " markers not found");
    }
  }
  return true;
}

/// A body without markers, by its silhouette: a ball or an outline by its shape in the first
/// frame that shows it (or as `shape` says: "ball", "outline", or "" to decide), tracked
/// through the clip. Fills the track, the shape and a ball's diameter; `c_px` gets its centre
/// per frame. Returns how far it moves (px).
double SetUpSilhouette(tracking::FrameSource& source, const std::string& shape,
                       const std::string& named, TrialSetup& s,
                       std::vector<std::optional<Eigen::Vector2d>>& c_px) {
  // The body: a silhouette, ball or outline by its shape in the first frame that shows it.
  tracking::SilhouetteOptions so;
  s.found_by = "shape";
  if (!shape.empty()) {
    s.shape = shape;
  } else {
    so.shape = tracking::SilhouetteShape::kOutline;
    for (int f = 0; f < source.count() && s.shape.empty(); ++f) {
      tracking::Polarity p;
      const auto o =
          tracking::FindSilhouette(tracking::ToGrey(source.Read(f), source.Describe(f)), so, &p);
      if (!o.found) continue;
      // A disc's extents agree; the specimen is about three times as long as wide.
      s.shape = o.length_px < 1.3 * o.width_px ? "ball" : "outline";
    }
    if (s.shape.empty()) throw std::runtime_error(named + ": no body found in any frame");
  }
  so.shape =
      s.shape == "ball" ? tracking::SilhouetteShape::kBall : tracking::SilhouetteShape::kOutline;
  s.track = tracking::TrackSilhouette(source, so);
  for (const auto& w : s.track.warnings) s.warnings.push_back(w);
  std::vector<double> diameters;
  Eigen::Vector2d first_seen{0, 0};
  bool any = false;
  double travel = 0;
  c_px.clear();
  for (const auto& o : s.track.frames) {
    c_px.push_back(o.found ? std::optional<Eigen::Vector2d>(o.p_I) : std::nullopt);
    if (!o.found) continue;
    if (!any) first_seen = o.p_I;
    any = true;
    travel = std::max(travel, (o.p_I - first_seen).norm());
    if (o.diameter_px > 0) diameters.push_back(o.diameter_px);
  }
  s.body_diameter_px = Median(diameters);
  return travel;
}

/// A shape-found silhouette is trusted where the motion finder found no ballistic path only
/// when it is a lab clip's: the body found in at least 90 % of the frames.
bool ShapeTrackHolds(const TrialSetup& s) {
  int found = 0;
  for (const auto& o : s.track.frames) found += o.found ? 1 : 0;
  return !s.track.frames.empty() && found >= 0.9 * static_cast<double>(s.track.frames.size());
}

/// A body without markers found by its motion (pipeline/moving_body.h): the clip's median
/// background, what moves against it, and the path that is ballistic. Fills the setup for a
/// ball found so (found_by "motion", its track, colour, diameter and gravity's direction) and
/// returns true; returns false with `s.moving` set when no ball was found that way (an outline,
/// or nothing ballistic), for the caller to try the body's shape.
bool SetUpByMotion(tracking::FrameSource& source, const TrialSetupOptions& options,
                   const std::string& named, TrialSetup& s,
                   std::vector<std::optional<Eigen::Vector2d>>& c_px, double& travel) {
  MovingBodyOptions mo;
  if (!options.color.empty()) {
    try {
      mo.rgb = ParseColour(options.color);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(std::string("--color: ") + e.what());
    }
  }
  mo.motion.thumbnail_px = kContactSheetTilePx;  // the contact sheet's frames, kept
  const cv::Mat background = tracking::MedianBackground(source, mo.motion);
  auto moving = std::make_shared<MovingBody>(
      FindMovingBody(tracking::FindMotion(source, background, mo.motion), s.fps, named, mo));
  s.moving = moving;
  if (!moving->found || !moving->round) return false;
  s.shape = "ball";
  s.found_by = "motion";
  s.track = moving->track;
  s.body_diameter_px = moving->diameter_px;
  for (const auto& w : moving->warnings) s.warnings.push_back(w);
  if (moving->down_measured) {
    s.gravity_image = moving->down_I;
    s.gravity_from_arcs = true;
  }
  c_px.clear();
  travel = 0;
  std::optional<Eigen::Vector2d> first_seen;
  for (std::size_t f = 0; f < s.track.frames.size(); ++f) {
    const auto& o = s.track.frames[f];
    // A frame whose image another frame shows at its capture time is no sample of the motion.
    const bool sample = o.found && !(f < moving->copies.size() && moving->copies[f]);
    c_px.push_back(sample ? std::optional<Eigen::Vector2d>(o.p_I) : std::nullopt);
    if (!sample) continue;
    if (!first_seen) first_seen = o.p_I;
    travel = std::max(travel, (o.p_I - *first_seen).norm());
  }
  return true;
}

/// The angle (deg) of the image direction `down_I` from the image's down, positive leaning
/// toward +x: the camera's roll.
double RollDeg(const Eigen::Vector2d& down_I) {
  return std::atan2(down_I.x(), down_I.y()) * 180 / M_PI;
}

/// Where a ball found by its motion touches the surface: at each contact of its arcs, the
/// lowest point (along gravity) of the ball at the arcs' meeting, in image px.
std::vector<Eigen::Vector2d> ContactPoints(const TrialSetup& s) {
  std::vector<Eigen::Vector2d> out;
  if (!s.moving || !s.moving->found) return out;
  const auto& arcs = s.moving->arcs;
  const int first = s.moving->path.first_frame();
  for (const auto& c : arcs.contacts) {
    Eigen::Vector2d lowest{0, 0};
    double depth = -1e300;
    for (int f : {c.last_frame_before, c.first_frame_after}) {
      const int frame = first + f;
      if (frame < 0 || frame >= static_cast<int>(s.track.frames.size())) continue;
      const auto& o = s.track.frames[static_cast<std::size_t>(frame)];
      if (!o.found) continue;
      const double along = o.p_I.dot(s.gravity_image);
      if (along > depth) {
        depth = along;
        lowest = o.p_I + 0.5 * o.diameter_px * s.gravity_image;
      }
    }
    if (depth > -1e300) out.push_back(lowest);
  }
  return out;
}

/// The capture rate gravity implies where the scale is known apart from it (`m_per_px` from a
/// stated scale or a ball's diameter) and the arcs measured |a|; a warning when it disagrees
/// with the rate used.
void CheckCaptureRate(TrialSetup& s, double m_per_px, double scale_rel_se) {
  if (!s.moving || !s.moving->found || !(m_per_px > 0)) return;
  const auto& arcs = s.moving->arcs;
  if (arcs.status != kinematics::ArcFitStatus::kFitted || !(arcs.a_norm > 0)) return;
  s.capture_rate = kinematics::CaptureRateFromGravity(
      arcs.a_norm * m_per_px, arcs.a_norm_se * m_per_px, s.fps, scale_rel_se);
  const auto& r = s.capture_rate;
  if (!r.measured) return;
  const double off = std::abs(r.ratio - 1);
  if (off > 0.1 && off > 3 * r.ratio_se) {
    std::ostringstream os;
    os.precision(3);
    os << "gravity's parabola and the scale say the frames were captured at " << r.capture_fps
       << " +- " << r.capture_fps_se << " fps, " << r.ratio << " x the " << s.fps
       << " fps used (a slow-motion file records the rate it plays at, not its capture rate, or "
          "the scale is off); give --fps "
       << std::lround(r.capture_fps) << " if it was captured so (--fps decides)";
    s.warnings.push_back(os.str());
  }
}

}  // namespace

std::string BodyText(const TrialSetup& s) {
  if (s.shape == "markers")
    return "markers (" + std::to_string(s.marker_dots_px.size()) + " white dots)";
  return s.shape + " (" + tracking::PolarityName(s.track.polarity) + ")";
}

TrialSetup SetUpTrial(const fs::path& clip, const fs::path& trial_dir,
                      const TrialSetupOptions& options) {
  TrialSetup s;
  s.clip = clip;
  std::error_code ec;
  if (!fs::exists(clip, ec)) throw std::runtime_error(clip.string() + ": no such file or folder");
  const fs::path trial_abs = fs::absolute(trial_dir).lexically_normal();
  const fs::path clip_abs = fs::absolute(clip).lexically_normal();
  std::unique_ptr<tracking::FrameSource> source;
  if (fs::is_directory(clip_abs)) {
    s.clip_kind = "frames";
    std::string pattern;
    FramesOfFolder(clip_abs, pattern, s.first, s.count);
    s.frames_reference = (fs::relative(clip_abs, trial_abs) / pattern).generic_string();
    source = std::make_unique<tracking::ImageSequenceSource>(clip_abs, pattern, s.first, s.count);
  } else if (tracking::IsCameraFile(clip_abs)) {
    s.clip_kind = "camera_file";
    auto camera = tracking::OpenCameraFile(clip_abs);
    const auto& info = camera->info();
    if (std::isfinite(info.fps) && info.fps > 0) {
      s.fps = info.fps;
      s.fps_recorded = true;
    }
    s.count = camera->count();
    s.frames_reference = fs::relative(clip_abs, trial_abs).generic_string();
    source = std::move(camera);
  } else {
    s.clip_kind = "video";
    s.frames_reference = fs::relative(clip_abs, trial_abs).generic_string();
    auto video = std::make_unique<tracking::VideoSource>(clip_abs);
    s.container_fps = video->info().fps;
    s.rotation_deg = video->info().rotation_deg;
    s.fps = s.container_fps;
    s.count = video->count();
    source = std::move(video);
  }
  if (options.fps > 0) {
    if (s.fps_recorded && std::abs(options.fps - s.fps) > 1e-6 * s.fps)
      throw std::runtime_error(clip.string() + ": --fps " + json(options.fps).dump() +
                               " disagrees with the clip's recorded " + json(s.fps).dump());
    // A video's container records the rate it plays at: a slow-motion file's capture rate is
    // another, which --fps states.
    if (s.container_fps > 0 && std::abs(options.fps - s.container_fps) > 1e-6 * s.container_fps) {
      std::ostringstream os;
      os << "--fps " << options.fps << " is used: the container plays at " << s.container_fps
         << " fps (" << options.fps / s.container_fps << " x slower than captured)";
      s.warnings.push_back(os.str());
    }
    s.fps = options.fps;
  }
  if (!(s.fps > 0))
    throw std::runtime_error(clip.string() +
                             ": the clip does not record its frame rate: give it with --fps");
  if (s.rotation_deg != 0)
    s.warnings.push_back("the container's rotation tag turns the stored frames by " +
                         std::to_string(s.rotation_deg) +
                         " deg clockwise: they are measured turned upright, as a player shows "
                         "them");
  const std::string named = source->Describe(0) + " .. " + source->Describe(source->count() - 1);

  // The body: white dots on black patches (a marked specimen), else a silhouette.
  std::vector<std::optional<Eigen::Vector2d>> c_px;
  double travel = 0;
  // A high-speed camera's clip: the body moves little between frames against a plain
  // background. A clip shorter than kMinMotionClip_s may be too short in time for gravity to
  // bend its path measurably, which finding it by its motion needs: its body is looked for by
  // its motion first (a slow-motion phone clip of a throw), and by its shape where that fails.
  const bool high_speed = s.clip_kind == "camera_file" || s.fps >= kHighSpeedFps;
  const bool short_clip = s.count / s.fps < kMinMotionClip_s;
  bool marked = false;
  {
    const TrialSetup before = s;
    if (SetUpMarkers(*source, options, s, c_px, travel)) {
      marked = true;
      // White dots that stay where they are (on a frame or the surface) are not the body when
      // it was not said to be marked, in a clip where what moves can be found by its motion.
      if (options.body == "auto" && !high_speed && !(travel > 4 * s.marker_dot_radius_px)) {
        std::ostringstream os;
        os << s.marker_dots_px.size() << " white dots in the first frame move at most "
           << std::lround(travel) << " px: they are not the body (--body markers if they are)";
        s = before;
        s.warnings.push_back(os.str());
        c_px.clear();
        travel = 0;
        marked = false;
      }
    }
  }
  if (marked) {
    s.found_by = "markers";
  } else if (options.body == "outline") {
    travel = SetUpSilhouette(*source, "outline", named, s, c_px);
  } else if (high_speed) {
    travel = SetUpSilhouette(*source, options.body == "ball" ? "ball" : "", named, s, c_px);
  } else if (!SetUpByMotion(*source, options, named, s, c_px, travel)) {
    // Nothing ballistic moves against the clip's background, or what does is elongated: the
    // body by its shape, where that holds through the clip (a lab clip: a back-lit body, a
    // high frame rate at which the body moves less than its size).
    const MovingBody& m = *s.moving;
    const bool outline = m.found && !m.round;
    // Only where nothing moved that could be tested (every path still or too short): a path
    // that moves and was refused must not be replaced by a silhouette that does not move.
    bool untested = true;
    for (const auto& c : m.candidates)
      untested &= c.verdict == CandidateVerdict::kStill || c.verdict == CandidateVerdict::kTooShort;
    if (!outline && !untested && !short_clip)
      throw SetupRefused(m.message, std::make_shared<TrialSetup>(s));
    bool shape_found = true;
    try {
      travel = SetUpSilhouette(*source,
                               outline                  ? "outline"
                               : options.body == "ball" ? "ball"
                                                        : "",
                               named, s, c_px);
    } catch (const std::runtime_error&) {
      if (outline || short_clip) throw;
      shape_found = false;
    }
    if (!outline && !short_clip && (!shape_found || !ShapeTrackHolds(s) || travel < 0.5)) {
      // What the silhouette found is not a body that moves: the motion's verdicts say why.
      s.shape.clear();
      s.track = tracking::SilhouetteTrack{};
      throw SetupRefused(m.message, std::make_shared<TrialSetup>(s));
    }
    if (!outline)
      s.warnings.push_back("the body was found by its shape in the frames, not by its motion (" +
                           m.message + ")");
  }
  if (travel < 0.5) {
    std::ostringstream os;
    os << named << ": no moving body: the "
       << (s.shape == "markers" ? std::string("marked body") : s.shape) << " never moves more than "
       << travel << " px from where it is first seen";
    throw std::runtime_error(os.str());
  }

  // The surface: the straight edge in the first frame, measured from gravity's perpendicular.
  s.surface_line =
      tracking::FindSurfaceLine(tracking::ToGrey(source->Read(0), source->Describe(0)));
  const double roll_deg = RollDeg(s.gravity_image);
  const std::vector<Eigen::Vector2d> contacts = ContactPoints(s);
  bool edge_refused = false;
  if (s.surface_line && !contacts.empty()) {
    // The edge found must be where the ball turns: within a diameter of every contact.
    const tracking::ImageLine& l = *s.surface_line;
    const Eigen::Vector2d n(-l.direction_I.y(), l.direction_I.x());
    double worst = 0;
    for (const auto& c : contacts) worst = std::max(worst, std::abs((c - l.point_I).dot(n)));
    if (!(worst < std::max(4.0, s.body_diameter_px))) {
      std::ostringstream os;
      os << "the straight edge found in the first frame lies " << std::lround(worst)
         << " px from where the ball turns: it is not the surface; the contact level is taken "
            "from where the arcs meet, level with gravity";
      s.warnings.push_back(os.str());
      s.surface_line.reset();
      s.contact_level_from_arcs = true;
      edge_refused = true;
    }
  }
  if (s.surface_line) {
    double phi = SurfaceAngleDeg(*s.surface_line) - roll_deg;
    if (phi > 90) phi -= 180;
    if (phi <= -90) phi += 180;
    s.surface_angle_deg = std::round(phi * 100) / 100;
  } else if (!contacts.empty()) {
    s.contact_level_from_arcs = true;
    if (!edge_refused)
      s.warnings.push_back(
          "no surface line found in the first frame: the contact level is taken from where the "
          "arcs meet, and the surface as level with gravity (surface_angle_deg 0); check it");
  } else {
    s.warnings.push_back(
        "no surface line found in the first frame: surface_angle_deg 0 is assumed; "
        "check it");
  }
  if (s.gravity_from_arcs && std::abs(roll_deg) > 0.5) {
    std::ostringstream os;
    os.precision(3);
    os << "gravity's direction is taken from the arcs' shared acceleration: " << roll_deg << " +- "
       << s.moving->down_se_deg << " deg from the image's down (the camera's roll)";
    s.warnings.push_back(os.str());
  }

  // A marked body's specimen and layout (study.json), and the scale its spacing gives.
  json marked_specimen;
  double layout_m_per_px = core::kNaN;
  if (s.shape == "markers") MarkedSpecimen(options, trial_abs, s, marked_specimen, layout_m_per_px);

  // An outline's specimen (study.json), whose end radius gives a scale.
  json outline_specimen;
  double outline_end_radius_m = 0.0;
  if (s.shape == "outline" && !options.specimen.empty()) {
    outline_specimen = SpecimenOfStudy(options, trial_abs);
    if (outline_specimen.contains("end_radius_m") && outline_specimen["end_radius_m"].is_number())
      outline_end_radius_m = outline_specimen["end_radius_m"].get<double>();
  }

  // A ball's specimen, whose diameter gives the scale as --diameter-m does.
  double diameter_m = options.diameter_m;
  const json ball_specimen = s.shape == "ball" && !options.specimen.empty()
                                 ? BallSpecimen(options, trial_abs, named, diameter_m)
                                 : json();

  // Impacts and the scale from gravity: one fit.
  kinematics::GravityScaleOptions go;
  go.gravity_m_s2 = options.gravity_m_s2;
  s.gravity = kinematics::EstimateGravityScale(c_px, s.fps, s.gravity_image, go);
  if (!s.gravity.measured) {
    // As track does: the joint flight arcs where the parabolas between contacts do not hold.
    kinematics::GravityScale arcs = kinematics::GravityScaleFromArcs(c_px, s.fps, go);
    if (arcs.measured) s.gravity = std::move(arcs);
  }
  if (s.found_by == "motion") {
    // The impacts of the arcs that found the body.
    const int first = s.moving->path.first_frame();
    for (const auto& c : s.moving->arcs.contacts)
      s.impact_frames.push_back(first + c.first_frame_after);
  } else {
    for (std::size_t i = 0; i < s.gravity.contact_frames.size(); ++i)
      if (i == 0 || s.gravity.contact_frames[i] > s.gravity.contact_frames[i - 1] + 1)
        s.impact_frames.push_back(s.gravity.contact_frames[i]);
  }
  if (options.m_per_px > 0) {
    s.scale_from = "m_per_px";
    s.m_per_px = options.m_per_px;
    s.m_per_px_se = 0;
    CheckCaptureRate(s, s.m_per_px, 0.0);
  } else if (diameter_m > 0) {
    if (s.shape != "ball")
      throw std::runtime_error("--diameter-m: the body found in " + named + " is not a ball");
    s.scale_from = "body_diameter";
    s.m_per_px = diameter_m / s.body_diameter_px;
    CheckCaptureRate(s, s.m_per_px, 0.01);
  } else if (s.shape == "markers" && layout_m_per_px > 0) {
    s.scale_from = "markers";
    s.m_per_px = layout_m_per_px;
    CheckLayoutAgainstGravity(s);
  } else if (outline_end_radius_m > 0 &&
             ScaleFromEndRadius(*source, outline_end_radius_m, named, s)) {
    // An unmarked specimen's known end radius over its round end's fitted radius.
  } else {
    s.scale_from = "gravity";
    if (s.gravity.measured) {
      s.m_per_px = s.gravity.m_per_px;
      s.m_per_px_se = s.gravity.m_per_px_se;
      if (s.shape == "outline")
        s.warnings.push_back(
            "an outline's scale from gravity is doubtful: on rendered clips it passed its test "
            "biased by 11-26 % (docs/init.md); give --m-per-px, or --specimen with its "
            "end_radius_m");
    } else {
      s.warnings.push_back(s.gravity.message + "; give the scale with --m-per-px" +
                           (s.shape == "markers" ? std::string(" or the specimen's layout")
                                                 : std::string(" or a ball's --diameter-m")));
    }
  }

  // trial.json.
  json t;
  t["format"] = "hoofimpact-trial/1";
  std::string id = trial_abs.filename().string();
  if (id.empty() || id == "." || id == ".." || id.size() > 200) id = "trial";
  t["id"] = id;
  t["surface"] = options.surface;
  t["surface_angle_deg"] = s.surface_angle_deg;
  if (!s.fps_recorded) t["fps"] = s.fps;
  if (s.clip_kind == "camera_file")
    t["frames"] = {{"camera_file", s.frames_reference}};
  else if (s.clip_kind == "video")
    t["frames"] = {{"video", s.frames_reference}};
  else
    t["frames"] = {{"pattern", s.frames_reference}, {"first", s.first}, {"count", s.count}};
  json camera = {
      {"gravity_image",
       {std::round(s.gravity_image.x() * 1e6) / 1e6, std::round(s.gravity_image.y() * 1e6) / 1e6}},
      {"scale_from", s.scale_from}};
  if (s.scale_from == "m_per_px") camera["m_per_px"] = s.m_per_px;
  // The marker tracker matches the dots to the layout at an approximate scale, also when the
  // scale used comes from the markers' spacing or gravity.
  if (s.shape == "markers" && s.scale_from != "m_per_px" && std::isfinite(s.m_per_px))
    camera["m_per_px"] = s.m_per_px;
  t["camera"] = camera;
  if (s.shape == "markers") {
    t["body"] = {{"model", "markers"}};
    if (!marked_specimen.is_null()) {
      t["specimen"] = options.specimen;
      t["specimen_parameters"] = marked_specimen;
    }
  } else {
    json body = {{"model", "silhouette"},
                 {"shape", s.shape},
                 {"polarity", tracking::PolarityName(s.track.polarity)}};
    if (s.shape == "ball" && diameter_m > 0) body["diameter_m"] = diameter_m;
    if (s.found_by == "motion") {
      body["find"] = "motion";
      body["background"] = kBackgroundFile;
      const Eigen::Vector3d& c = s.moving->rgb;
      body["rgb"] = {std::lround(c[0]), std::lround(c[1]), std::lround(c[2])};
      body["diameter_px"] = std::round(s.body_diameter_px * 100) / 100;
    }
    t["body"] = body;
  }
  if (!ball_specimen.is_null()) {
    t["specimen"] = options.specimen;
    t["specimen_parameters"] = ball_specimen;
  }
  if (s.shape == "outline") {
    if (!options.specimen.empty()) {
      t["specimen"] = options.specimen;
      t["specimen_parameters"] = outline_specimen;
    } else {
      s.warnings.push_back(
          "an outline needs its specimen (mass, inertia, end radius, |EC|): give --specimen "
          "(and --study), or add \"specimen\" to trial.json before track");
    }
  }
  std::ostringstream notes;
  notes << "written by hoofimpact init from " << clip.string() << ": " << BodyText(s) << ", "
        << (s.surface_line ? "surface at " + json(s.surface_angle_deg).dump() + " deg"
                           : std::string("no surface line found"))
        << ", " << s.impact_frames.size() << " impact(s)";
  if (std::isfinite(s.m_per_px)) notes << ", scale " << s.m_per_px << " m/px from " << s.scale_from;
  notes << "; review before track";
  t["notes"] = notes.str();
  s.trial_json = t.dump(2) + "\n";
  return s;
}

}  // namespace hoof::pipeline
