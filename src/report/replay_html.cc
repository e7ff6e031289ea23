// The report's Replay section (report/html_parts.h): a few trials' frames around the impact,
// read again from their trial folders, with the measured and simulated markers and the
// magnified residuals drawn over them in the browser by assets/replay.js, in the glyphs of
// compare/replay_convention.h (which this file writes into the page's replay JSON).
#include <algorithm>
#include <cmath>
#include <memory>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "compare/comparison_tables.h"
#include "compare/replay_convention.h"
#include "core/frames.h"
#include "format/number_format.h"
#include "pipeline/study_format.h"
#include "report/html_parts.h"
#include "report/html_report.h"
#include "studyfile/study_file.h"
#include "tracking/frame_source.h"

namespace hoof::report::internal {
namespace {

namespace fs = std::filesystem;
namespace rp = compare::replay;

/// The glyphs' size unit on the page's canvas (px): the measured ring's radius.
constexpr double kMarkerRadiusCanvasPx = 6.0;

/// The trials to replay: successful ones, one per surface first, then in file order.
std::vector<const studyfile::TrialResult*> PickReplays(const studyfile::StudyResults& study,
                                                       int n) {
  std::vector<const studyfile::TrialResult*> candidates, picked;
  for (const auto& t : study.trials)
    if (t.success) candidates.push_back(&t);
  std::set<std::string> surfaces;
  for (const auto* t : candidates)
    if (static_cast<int>(picked.size()) < n && surfaces.insert(t->surface).second)
      picked.push_back(t);
  for (const auto* t : candidates)
    if (static_cast<int>(picked.size()) < n &&
        std::find(picked.begin(), picked.end(), t) == picked.end())
      picked.push_back(t);
  return picked;
}

/// The trial's folder (compare::replay::LocateTrialFolder); throws saying where it looked.
fs::path TrialFolder(const studyfile::TrialResult& t, const std::string& study_dir,
                     const fs::path& moved_study_dir) {
  const rp::TrialFolderSearch s = rp::LocateTrialFolder(t.dir, study_dir, moved_study_dir);
  if (s.found) return *s.found;
  throw std::runtime_error(rp::NotFoundMessage(s, !moved_study_dir.empty()));
}

/// Frames [first, last) of the trial as JPEG data URIs, grey levels stretched over the range
/// of those frames, downscaled to max_width. Sets `scale` (shown px per image px).
std::vector<std::string> EncodeFrames(const pipeline::TrialSpec& spec, int first, int last,
                                      const HtmlReportOptions& o, double& scale) {
  const std::unique_ptr<tracking::FrameSource> source = pipeline::OpenFrames(spec);
  std::vector<cv::Mat> frames;
  double lo = 1e300, hi = -1e300;
  for (int f = first; f < last && f < source->count(); ++f) {
    cv::Mat grey;
    source->Read(f).convertTo(grey, CV_32F);
    double a = 0, b = 0;
    cv::minMaxLoc(grey, &a, &b);
    lo = std::min(lo, a);
    hi = std::max(hi, b);
    frames.push_back(grey);
  }
  std::vector<std::string> uris;
  if (frames.empty()) return uris;
  scale = std::min(1.0, o.replay_max_width_px / static_cast<double>(frames[0].cols));
  const double gain = hi > lo ? 255.0 / (hi - lo) : 1.0;
  for (const cv::Mat& f : frames) {
    cv::Mat small, bytes;
    cv::resize(f, small, cv::Size(), scale, scale, cv::INTER_AREA);
    small.convertTo(bytes, CV_8U, gain, -lo * gain);
    std::vector<uchar> jpeg;
    cv::imencode(".jpg", bytes, jpeg, {cv::IMWRITE_JPEG_QUALITY, o.jpeg_quality});
    uris.push_back(
        "data:image/jpeg;base64," +
        Base64(std::string_view(reinterpret_cast<const char*>(jpeg.data()), jpeg.size())));
  }
  return uris;
}

/// The largest |simulated - measured| over the markers of a frame (image px); NaN when no
/// marker has both.
double LargestResidualPx(const compare::FrameComparison& f) {
  double largest = core::kNaN;
  for (std::size_t m = 0; m < std::min(f.markers_px_sim.size(), f.markers_px_meas.size()); ++m) {
    const double d = (f.markers_px_sim[m] - f.markers_px_meas[m]).norm();
    if (std::isfinite(d) && !(d <= largest)) largest = d;
  }
  return largest;
}

/// The points a replay compares: the markers, or for a body without markers (a ball, an
/// unmarked outline) its centre of mass C as the one point "C".
compare::ComparedFrames ReplayedPoints(compare::ComparedFrames compared) {
  if (!compared.markers.empty()) return compared;
  compared.markers = {"C"};
  for (auto& f : compared.frames) {
    f.markers_px_sim = {f.centre_px_sim};
    f.markers_px_meas = {f.centre_px_meas};
  }
  return compared;
}

/// One replay as a JSON object, with its frames as hidden <img> elements appended to `imgs`
/// (in the document, so the page's load event waits for them).
std::string ReplayJson(const studyfile::TrialResult& t, const fs::path& trial_dir,
                       const compare::ComparedFrames& compared, bool centre_of_mass,
                       const HtmlReportOptions& o, int index, std::string& imgs) {
  const int n_frames = static_cast<int>(compared.frames.size());
  const int impact = static_cast<int>(std::lround(t.impact_time_s * t.fps));
  const int first = std::clamp(impact - o.frames_per_replay / 2, 0, std::max(0, n_frames - 1));
  const int last = std::min(n_frames, first + o.frames_per_replay);
  double scale = 1.0;
  const pipeline::TrialSpec spec = pipeline::ReadTrial(trial_dir);
  const auto uris = EncodeFrames(spec, first, last, o, scale);
  if (uris.empty()) throw std::runtime_error("no frames could be read in " + trial_dir.string());
  const std::vector<std::string>& markers = compared.markers;
  // A ball is drawn as its simulated circle about the simulated centre (image px).
  const bool ball = spec.body.is_ball() || spec.specimen.is_ball();
  const double ball_radius_px =
      ball && t.m_per_px_used > 0 ? spec.specimen.end_radius_m / t.m_per_px_used : core::kNaN;
  std::ostringstream j;
  j << "{\"id\":" << JsonString(t.id) << ",\"surface\":" << JsonString(t.surface)
    << ",\"folder\":" << JsonString(trial_dir.string()) << ",\"scale\":" << JsonNumber(scale)
    << ",\"impact\":" << impact << ",\"centre_of_mass\":" << (centre_of_mass ? "true" : "false")
    << ",\"ball_radius_px\":" << JsonNumber(ball_radius_px) << ",\"markers\":[";
  for (std::size_t m = 0; m < markers.size(); ++m) j << (m ? "," : "") << JsonString(markers[m]);
  j << "],\"frames\":[";
  for (int k = 0; k < static_cast<int>(uris.size()); ++k) {
    const compare::FrameComparison& f = compared.frames[static_cast<std::size_t>(first + k)];
    imgs += "<img class=\"frame\" id=\"f" + std::to_string(index) + "_" + std::to_string(k) +
            "\" alt=\"\" src=\"" + uris[static_cast<std::size_t>(k)] + "\">";
    j << (k ? "," : "") << "{\"frame\":" << first + k << ",\"t_ms\":" << JsonNumber(f.t_s * 1e3)
      << ",\"t_text\":" << JsonString(format::Number(f.t_s * 1e3) + " ms")
      << ",\"residual_text\":" << JsonString(format::Number(LargestResidualPx(f)) + " px")
      << ",\"sim\":[";
    for (std::size_t m = 0; m < markers.size(); ++m)
      j << (m ? "," : "") << "[" << JsonNumber(f.markers_px_sim[m].x()) << ","
        << JsonNumber(f.markers_px_sim[m].y()) << "]";
    j << "],\"meas\":[";
    for (std::size_t m = 0; m < markers.size(); ++m)
      j << (m ? "," : "") << "[" << JsonNumber(f.markers_px_meas[m].x()) << ","
        << JsonNumber(f.markers_px_meas[m].y()) << "]";
    j << "]}";
  }
  j << "]}";
  return j.str();
}

/// A glyph for the page's JSON: {"shape":"ring","colour":"#00e676","size":1,"label":...}.
std::string GlyphJson(const rp::Glyph& g) {
  return std::string("{\"shape\":") + JsonString(rp::ShapeName(g.shape)) +
         ",\"colour\":" + JsonString(rp::HexColour(g)) + ",\"size\":" + JsonNumber(g.size) +
         ",\"label\":" + JsonString(g.label) + "}";
}

/// A glyph drawn as a small inline SVG for the legend, in its colour.
std::string GlyphSvg(const rp::Glyph& g) {
  const std::string c = rp::HexColour(g);
  std::string shape;
  switch (g.shape) {
    case rp::GlyphShape::kRing:
      shape = "<circle cx=\"9\" cy=\"9\" r=\"6\" fill=\"none\" stroke=\"" + c +
              "\" stroke-width=\"2\"/>";
      break;
    case rp::GlyphShape::kPlus:
      shape = "<path d=\"M1 9H17M9 1V17\" stroke=\"" + c + "\" stroke-width=\"2\"/>";
      break;
    case rp::GlyphShape::kArrow:
      shape = "<path d=\"M1 9H16M11 4L16 9L11 14\" fill=\"none\" stroke=\"" + c +
              "\" stroke-width=\"2\"/>";
      break;
  }
  return "<svg class=\"glyph\" width=\"18\" height=\"18\" viewBox=\"0 0 18 18\" "
         "aria-hidden=\"true\">" +
         shape + "</svg>";
}

}  // namespace

std::string ReplaySection(const studyfile::StudyResults& study, const fs::path& h5,
                          const HtmlReportOptions& o, HtmlReportSummary& summary) {
  std::string trials, imgs;
  for (const auto* t : PickReplays(study, o.replay_trials)) {
    try {
      const fs::path dir = TrialFolder(*t, study.study_dir, o.study_dir);
      const compare::ComparedFrames read = compare::ReadComparedFrames(h5, t->id);
      const bool centre_of_mass = read.markers.empty();
      const compare::ComparedFrames frames = ReplayedPoints(read);
      std::string trial_imgs;
      const std::string one =
          ReplayJson(*t, dir, frames, centre_of_mass, o, summary.replays, trial_imgs);
      trials += (summary.replays ? "," : "") + one;
      imgs += trial_imgs;
      ++summary.replays;
    } catch (const std::exception& e) {
      summary.missing_replays.push_back(t->id + ": " + e.what());
      summary.notes += "replay of trial " + t->id + " not drawn: " + e.what() + "\n";
    }
  }
  const std::string F = std::to_string(o.residual_scale);
  std::ostringstream json;
  json << "{\"residual_scale\":" << o.residual_scale
       << ",\"marker_radius\":" << JsonNumber(kMarkerRadiusCanvasPx) << ",\"glyphs\":{\""
       << rp::kMeasured.key << "\":" << GlyphJson(rp::kMeasured) << ",\"" << rp::kSimulated.key
       << "\":" << GlyphJson(rp::kSimulated) << ",\"" << rp::kResidual.key
       << "\":" << GlyphJson(rp::kResidual) << "},\"trials\":[" << trials << "]}";
  std::ostringstream h;
  h << "<section id=\"replay\"><h2>Replay</h2>";
  if (summary.replays == 0) {
    h << "<p class=\"" << (o.replay_trials == 0 ? "note" : "bad") << "\">No replay: "
      << (o.replay_trials == 0 ? "none asked for"
          : summary.missing_replays.empty()
              ? "no trial was measured"
              : "the frames of no replayed trial could be read (below)")
      << ".</p>";
  } else {
    h << "<p class=\"note replay-legend\">The " << o.frames_per_replay
      << " frames around the impact, drawn in the glyphs the overlay video "
         "(<code>hoofimpact overlay</code>) draws too: "
      << "<span class=\"key\" data-glyph=\"measured\">" << GlyphSvg(rp::kMeasured) << " "
      << HtmlEscape(rp::kMeasured.label) << " (tracked centre)</span> "
      << "<span class=\"key\" data-glyph=\"simulated\">" << GlyphSvg(rp::kSimulated) << " "
      << HtmlEscape(rp::kSimulated.label)
      << " (the surface's fitted contact law, started from the measured state before "
         "impact)</span> "
      << "<span class=\"key\" data-glyph=\"residual\">" << GlyphSvg(rp::kResidual) << " "
      << HtmlEscape(rp::kResidual.label)
      << " (simulated &minus; measured) magnified <b id=\"residual-scale\">" << F
      << "&times;</b>, drawn from the measured marker</span>: an arrow " << F
      << " px long stands for a disagreement of 1 px (in image pixels). A body without markers "
         "(a ball, an unmarked outline) shows its "
      << HtmlEscape(rp::kMeasuredCentre.label) << " and " << HtmlEscape(rp::kSimulatedCentre.label)
      << " in those glyphs instead, and a ball its simulated circle. "
      << "Arrow keys step frames.</p>"
      << "<div class=\"replay-controls\"><label>Trial <select id=\"replay-trial\"></select></label>"
      << "<button id=\"replay-prev\" type=\"button\">&#9664; prev</button>"
      << "<input id=\"replay-frame\" type=\"range\" min=\"0\" max=\"0\" value=\"0\" step=\"1\">"
      << "<button id=\"replay-next\" type=\"button\">next &#9654;</button>"
      << "<label><input id=\"replay-overlay\" type=\"checkbox\" checked> overlay</label>"
      << "<span id=\"replay-info\"></span></div>"
      << "<canvas id=\"replay-canvas\" width=\"480\" height=\"270\"></canvas>";
  }
  if (!summary.missing_replays.empty()) {
    h << "<div class=\"replay-missing\"><p class=\"bad\">" << summary.missing_replays.size()
      << " replay(s) could not be drawn (a missing replay does not fail the report):</p><ul>";
    for (const std::string& m : summary.missing_replays) h << "<li>" << HtmlEscape(m) << "</li>";
    h << "</ul></div>";
  }
  h << "<div class=\"frames-store\">" << imgs << "</div>"
    << "<script type=\"application/json\" id=\"replay-data\">" << json.str()
    << "</script></section>";
  return h.str();
}

}  // namespace hoof::report::internal
