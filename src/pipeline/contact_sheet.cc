#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "format/number_format.h"
#include "pipeline/trial_setup.h"
#include "tracking/camera_file.h"
#include "tracking/frame_source.h"
#include "tracking/motion_blobs.h"

// init's contact sheet (docs/init.md, "Output"): what SetUpTrial found, drawn on the frames.
namespace hoof::pipeline {

namespace fs = std::filesystem;
using json = nlohmann::json;

std::string EncodePng(const cv::Mat& image) {
  std::vector<unsigned char> bytes;
  if (!cv::imencode(".png", image, bytes)) throw std::runtime_error("cannot encode a PNG image");
  return std::string(bytes.begin(), bytes.end());
}

namespace {

/// BGR of a verdict's drawing: green for the body, amber for a joined piece, red for the rest.
cv::Scalar VerdictColour(CandidateVerdict v) {
  switch (v) {
    case CandidateVerdict::kBody:
      return {0, 220, 0};
    case CandidateVerdict::kJoined:
      return {0, 200, 255};
    default:
      return {60, 60, 255};
  }
}

/// `text` cut to about `chars` characters at a word, with "..." where cut.
std::string Shortened(const std::string& text, std::size_t chars) {
  if (text.size() <= chars) return text;
  std::size_t cut = text.rfind(' ', chars - 3);
  if (cut == std::string::npos || cut < chars / 2) cut = chars - 3;
  return text.substr(0, cut) + "...";
}

/// What moved (s.moving): the clip's background with every moving path drawn, numbered, the
/// body's measured centre on every frame it was measured (green dots), and a list of the
/// numbered paths with what each was judged to be and why. `width` px wide.
cv::Mat MotionPanel(const TrialSetup& s, int width) {
  const MovingBody& m = *s.moving;
  const cv::Mat& bg = m.scene.background;
  const int max_h = 420;
  const double zoom =
      std::min(static_cast<double>(width) / bg.cols, static_cast<double>(max_h) / bg.rows);
  cv::Mat view;
  cv::resize(bg, view,
             cv::Size(std::max(1, static_cast<int>(bg.cols * zoom)),
                      std::max(1, static_cast<int>(bg.rows * zoom))),
             0, 0, cv::INTER_AREA);
  view *= 0.6;  // dimmed, so the paths stand out
  auto P = [&](const Eigen::Vector2d& p) { return cv::Point2d(p.x() * zoom, p.y() * zoom); };
  const std::size_t listed = std::min<std::size_t>(m.candidates.size(), 10);
  for (std::size_t i = 0; i < listed; ++i) {
    const MovingCandidate& c = m.candidates[i];
    const auto& path = m.scene.paths[static_cast<std::size_t>(c.path)];
    const cv::Scalar colour = VerdictColour(c.verdict);
    for (std::size_t k = 1; k < path.regions.size(); ++k)
      cv::line(view, P(path.regions[k - 1].p_I), P(path.regions[k].p_I), colour, 1, cv::LINE_AA);
    cv::putText(view, std::to_string(i + 1), P(c.p_first_I) + cv::Point2d(4, -4),
                cv::FONT_HERSHEY_SIMPLEX, 0.45, colour, 1, cv::LINE_AA);
  }
  for (const auto& o : s.track.frames)
    if (o.found) cv::circle(view, P(o.p_I), 2, cv::Scalar(0, 255, 0), cv::FILLED, cv::LINE_AA);
  const int line_h = 16;
  std::vector<std::string> lines;
  lines.push_back(m.found ? "what moved (numbered), the body's centre on every frame (green dots):"
                          : "what moved (numbered); no body: " + Shortened(m.message, 200));
  const std::size_t chars = static_cast<std::size_t>(width / 7);
  for (std::size_t i = 0; i < listed; ++i) {
    const MovingCandidate& c = m.candidates[i];
    std::ostringstream os;
    os << i + 1 << ". frames " << c.first_frame << "-" << c.last_frame << ", "
       << std::lround(c.diameter_px) << " px, " << ColourHex(c.rgb) << ": "
       << CandidateVerdictName(c.verdict) << ": " << c.reason;
    lines.push_back(Shortened(os.str(), chars));
  }
  if (m.candidates.size() > listed)
    lines.push_back(std::to_string(m.candidates.size() - listed) + " more paths not drawn");
  cv::Mat panel(view.rows + line_h * static_cast<int>(lines.size()) + 8, width, CV_8UC3,
                cv::Scalar(32, 32, 32));
  view.copyTo(panel(cv::Rect((width - view.cols) / 2, 0, view.cols, view.rows)));
  for (std::size_t k = 0; k < lines.size(); ++k) {
    const cv::Scalar colour = k == 0        ? cv::Scalar(240, 240, 240)
                              : k <= listed ? VerdictColour(m.candidates[k - 1].verdict)
                                            : cv::Scalar(200, 200, 200);
    cv::putText(panel, lines[k], cv::Point(6, view.rows + 14 + line_h * static_cast<int>(k)),
                cv::FONT_HERSHEY_SIMPLEX, 0.4, colour, 1, cv::LINE_AA);
  }
  return panel;
}

/// The setup's clip, opened again.
std::unique_ptr<tracking::FrameSource> OpenClip(const TrialSetup& s) {
  const fs::path clip_abs = fs::absolute(s.clip).lexically_normal();
  if (s.clip_kind == "frames")
    return std::make_unique<tracking::ImageSequenceSource>(
        clip_abs, fs::path(s.frames_reference).filename().string(), s.first, s.count);
  if (s.clip_kind == "camera_file") return tracking::OpenCameraFile(clip_abs);
  return std::make_unique<tracking::VideoSource>(clip_abs);
}

}  // namespace

std::vector<std::pair<std::string, std::string>> TrialFiles(const TrialSetup& s) {
  std::vector<std::pair<std::string, std::string>> out = {{"trial.json", s.trial_json}};
  if (s.found_by == "motion" && s.moving)
    out.emplace_back(kBackgroundFile, EncodePng(s.moving->scene.background));
  return out;
}

cv::Mat ContactSheet(const TrialSetup& s) {
  // The frames as the motion finder kept them in init's pass over the clip, else read again.
  const std::vector<cv::Mat>* kept = nullptr;
  if (s.moving && static_cast<int>(s.moving->scene.thumbnails.size()) == s.count && s.count > 0) {
    const cv::Size full(s.moving->scene.width, s.moving->scene.height);
    if (s.moving->scene.thumbnails.front().size() ==
        tracking::ThumbnailSize(full, kContactSheetTilePx))
      kept = &s.moving->scene.thumbnails;
  }
  const std::unique_ptr<tracking::FrameSource> source = kept ? nullptr : OpenClip(s);
  const int n = kept ? s.count : source->count();
  // The frames shown: each impact with the frames before and after it, then spread evenly.
  std::vector<int> shown;
  for (int f : s.impact_frames)
    for (int g : {f - 1, f, f + 1})
      if (g >= 0 && g < n && std::find(shown.begin(), shown.end(), g) == shown.end() &&
          shown.size() < 9)
        shown.push_back(g);
  for (int k = 0; shown.size() < 12 && k < 12; ++k) {
    const int g = static_cast<int>(std::lround(k * (n - 1) / 11.0));
    if (std::find(shown.begin(), shown.end(), g) == shown.end()) shown.push_back(g);
  }
  std::sort(shown.begin(), shown.end());
  const cv::Size full =
      kept ? cv::Size(s.moving->scene.width, s.moving->scene.height) : source->Read(0).size();
  const cv::Size tile_size = tracking::ThumbnailSize(full, kContactSheetTilePx);
  const double zoom = static_cast<double>(tile_size.width) / full.width;
  const int tw = tile_size.width, th = tile_size.height;
  const int cols = 4, label_h = 18;
  const int rows = static_cast<int>((shown.size() + cols - 1) / cols);
  std::vector<std::string> caption;
  {
    std::ostringstream a, b, c;
    a << "body: " << BodyText(s);
    if (s.shape == "ball") a << ", diameter " << std::lround(s.body_diameter_px) << " px";
    a << "; " << s.count << " frames at " << s.fps << " fps";
    b << "surface: "
      << (s.surface_line ? json(s.surface_angle_deg).dump() + " deg (red line)"
                         : std::string("not found"))
      << "; impacts at frames:";
    if (s.impact_frames.empty()) b << " none";
    for (int f : s.impact_frames) b << " " << f;
    // In um per px through the number policy (the drawing font has no micro or plus-minus sign).
    c << "scale from " << s.scale_from << ": ";
    if (std::isfinite(s.m_per_px))
      c << format::WithError(s.m_per_px * 1e6, s.m_per_px_se * 1e6, format::Kind::kMeasured,
                             " +/- ")
        << " um/px";
    else
      c << "not measured";
    caption = {a.str(), b.str(), c.str()};
  }
  const int caption_h = 20 * static_cast<int>(caption.size()) + 8;
  const int sheet_w = std::max(cols * tw, 640);
  cv::Mat sheet(rows * (th + label_h) + caption_h, sheet_w, CV_8UC3, cv::Scalar(32, 32, 32));
  for (std::size_t i = 0; i < shown.size(); ++i) {
    const int f = shown[i];
    cv::Mat grey = kept ? (*kept)[static_cast<std::size_t>(f)]
                        : tracking::ToGrey(source->Read(f), source->Describe(f));
    const auto [lo, hi] = tracking::FrameLevels(grey);
    cv::Mat g8;
    grey.convertTo(g8, CV_8U, 255.0 / std::max(1e-9, hi - lo),
                   -lo * 255.0 / std::max(1e-9, hi - lo));
    cv::Mat tile;
    cv::cvtColor(g8, tile, cv::COLOR_GRAY2BGR);
    cv::resize(tile, tile, cv::Size(tw, th), 0, 0, cv::INTER_AREA);
    auto P = [&](const Eigen::Vector2d& p) { return cv::Point2d(p.x() * zoom, p.y() * zoom); };
    if (s.surface_line) {
      const auto& l = *s.surface_line;
      const double reach = 2.0 * (full.width + full.height);
      cv::line(tile, P(l.point_I - reach * l.direction_I), P(l.point_I + reach * l.direction_I),
               cv::Scalar(0, 0, 255), 1, cv::LINE_AA);
    }
    const auto fi = static_cast<std::size_t>(f);
    const tracking::SilhouetteObservation o =
        fi < s.track.frames.size() ? s.track.frames[fi] : tracking::SilhouetteObservation{};
    if (fi < s.marker_frames_px.size())
      for (const auto& d : s.marker_frames_px[fi])
        cv::circle(tile, P(d), std::max(2, static_cast<int>(1.5 * s.marker_dot_radius_px * zoom)),
                   cv::Scalar(0, 255, 0), 1, cv::LINE_AA);
    if (o.found) {
      if (s.shape == "ball") {
        cv::circle(tile, P(o.p_I), std::max(1, static_cast<int>(0.5 * o.diameter_px * zoom)),
                   cv::Scalar(0, 255, 0), 1, cv::LINE_AA);
      } else {
        const Eigen::Vector2d ax(std::cos(o.angle_I_rad), std::sin(o.angle_I_rad));
        cv::ellipse(tile,
                    cv::RotatedRect(P(o.p_I),
                                    cv::Size2f(static_cast<float>(o.length_px * zoom),
                                               static_cast<float>(o.width_px * zoom)),
                                    static_cast<float>(o.angle_I_rad * 180 / M_PI)),
                    cv::Scalar(0, 255, 0), 1, cv::LINE_AA);
        cv::line(tile, P(o.p_I), P(o.p_I + 0.5 * o.length_px * ax), cv::Scalar(0, 255, 0), 1,
                 cv::LINE_AA);
      }
      cv::drawMarker(tile, P(o.p_I), cv::Scalar(0, 255, 0), cv::MARKER_CROSS, 7);
    }
    const bool impact =
        std::find(s.impact_frames.begin(), s.impact_frames.end(), f) != s.impact_frames.end();
    if (impact) cv::rectangle(tile, cv::Rect(0, 0, tw, th), cv::Scalar(0, 0, 255), 3);
    const int x0 = static_cast<int>(i % cols) * tw,
              y0 = static_cast<int>(i / cols) * (th + label_h);
    tile.copyTo(sheet(cv::Rect(x0, y0, tw, th)));
    cv::putText(sheet,
                "frame " + std::to_string(f) + (impact ? "  IMPACT" : "") +
                    (o.found || (fi < s.marker_frames_px.size() && !s.marker_frames_px[fi].empty())
                         ? ""
                         : "  (no body)"),
                cv::Point(x0 + 3, y0 + th + 13), cv::FONT_HERSHEY_SIMPLEX, 0.4,
                impact ? cv::Scalar(80, 80, 255) : cv::Scalar(220, 220, 220), 1, cv::LINE_AA);
  }
  for (std::size_t k = 0; k < caption.size(); ++k)
    cv::putText(sheet, caption[k],
                cv::Point(6, rows * (th + label_h) + 18 + 20 * static_cast<int>(k)),
                cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(240, 240, 240), 1, cv::LINE_AA);
  if (!s.moving || s.moving->scene.background.empty()) return sheet;
  cv::Mat with_motion;
  cv::vconcat(MotionPanel(s, sheet.cols), sheet, with_motion);
  return with_motion;
}

}  // namespace hoof::pipeline
