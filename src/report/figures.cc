#include "report/figures.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "core/frames.h"
#include "format/number_format.h"
#include "report/gnuplot.h"

namespace hoof::report {

std::vector<std::filesystem::path> WriteOutOfPlaneFigure(const pipeline::TrialAnalysis& trial,
                                                         double threshold,
                                                         const std::filesystem::path& dir,
                                                         const std::string& name) {
  Series s;
  s.title = "projected / layout marker distance";
  std::vector<double> finite;
  for (std::size_t f = 0; f < trial.marker_distance_ratio.size(); ++f) {
    s.x.push_back(static_cast<double>(f));
    s.y.push_back(100.0 * trial.marker_distance_ratio[f]);
    if (std::isfinite(trial.marker_distance_ratio[f]))
      finite.push_back(100.0 * trial.marker_distance_ratio[f]);
  }
  Plot plot;
  const bool flagged =
      std::find(trial.flags.begin(), trial.flags.end(), "out_of_plane") != trial.flags.end();
  plot.title = trial.spec.id + ": out-of-plane check " + (flagged ? "FLAGGED" : "passed") +
               " (change " + format::Number(100 * trial.out_of_plane_change) + " %, noise " +
               format::Number(100 * trial.out_of_plane_noise) + " %)";
  plot.y_label = "marker distance (% of the layout's)";
  plot.x_label = "frame number";
  plot.series.reserve(1);
  plot.series.push_back(s);
  if (trial.impact.success) {
    plot.shaded_x_ranges.emplace_back(trial.impact.before.first_frame,
                                      trial.impact.before.last_frame);
    plot.shaded_x_ranges.emplace_back(trial.impact.after.first_frame,
                                      trial.impact.after.last_frame);
  }
  if (!finite.empty()) {
    std::nth_element(finite.begin(),
                     finite.begin() + static_cast<std::ptrdiff_t>(finite.size() / 2), finite.end());
    const double median = finite[finite.size() / 2];
    const double limit = 100 * std::max(threshold, 8.0 * trial.out_of_plane_noise);
    plot.horizontal_lines = {median - limit / 2, median + limit / 2};
    plot.horizontal_lines_title = "flag threshold (a change wider than the band)";
  }
  return WriteFigure(plot, dir, name);
}

// ---- Figure 3 -------------------------------------------------------------------------------

namespace {

/// Converts C's position in W to the figure's units and frame.
struct FigureFrame {
  Eigen::Vector2d origin_W, x_S, y_S;
  void Add(DisplacementSamples& s, double t_s, const Eigen::Vector2d& p_WC,
           double theta_rad) const {
    const Eigen::Vector2d r = p_WC - origin_W;
    s.t_ms.push_back(1e3 * t_s);
    s.x_S_mm.push_back(1e3 * x_S.dot(r));
    s.y_S_mm.push_back(1e3 * y_S.dot(r));
    s.theta_deg.push_back(core::RadToDeg(theta_rad));
  }
};

/// `fit` sampled evenly over [t0_s, t1_s] (times since frame 0) about the impact time.
DisplacementSamples SampleFit(const kinematics::FlightFit& fit, double impact_time_s, double t0_s,
                              double t1_s, int samples, double g, const FigureFrame& frame) {
  DisplacementSamples s;
  for (int i = 0; i < samples; ++i) {
    const double t = t0_s + (t1_s - t0_s) * i / (samples - 1);
    const double dt = t - impact_time_s;
    const Eigen::Vector2d p = fit.p_WC + fit.v_WC * dt + Eigen::Vector2d(0, -0.5 * g * dt * dt);
    frame.Add(s, t, p, fit.theta_W_rad + fit.w_rad_s * dt);
  }
  return s;
}

}  // namespace

DisplacementCurves ComputeDisplacementCurves(const pipeline::TrialAnalysis& trial,
                                             int samples_per_fit, double gravity_m_s2) {
  if (samples_per_fit < 2)
    throw std::invalid_argument("samples_per_fit must be >= 2, got " +
                                std::to_string(samples_per_fit));
  const double phi = core::DegToRad(trial.spec.surface_angle_deg);
  const double d = trial.spec.specimen.d_EC_m;
  const double fps = trial.spec.fps;
  const auto com = [d](const tracking::BodyPose& p) {
    return Eigen::Vector2d(p.p_WE + d * core::BodyRotation(p.theta_W_rad).x_B());
  };
  DisplacementCurves c;
  const auto& k = trial.impact;
  c.has_fit = k.success;
  const auto R_WS = core::SurfaceRotation(phi);
  FigureFrame frame{{0, 0}, R_WS.x_S(), R_WS.y_S()};
  if (c.has_fit) {
    frame.origin_W = k.before.p_WC;
  } else {
    const auto first = std::find_if(trial.poses.begin(), trial.poses.end(),
                                    [](const tracking::BodyPose& p) { return p.valid; });
    if (first != trial.poses.end()) frame.origin_W = com(*first);
  }
  for (std::size_t f = 0; f < trial.poses.size(); ++f)
    if (trial.poses[f].valid)
      frame.Add(c.measured, static_cast<double>(f) / fps, com(trial.poses[f]),
                trial.poses[f].theta_W_rad);
  if (c.has_fit) {
    c.impact_time_ms = 1e3 * k.impact_time_s;
    c.fit_before = SampleFit(k.before, k.impact_time_s, k.before.first_frame / fps, k.impact_time_s,
                             samples_per_fit, gravity_m_s2, frame);
    c.fit_after = SampleFit(k.after, k.impact_time_s, k.impact_time_s, k.after.last_frame / fps,
                            samples_per_fit, gravity_m_s2, frame);
  }
  return c;
}

namespace {

Series Curve(std::string title, const std::vector<double>& t, const std::vector<double>& y,
             std::string style, std::string options) {
  Series s;
  s.title = std::move(title);
  s.x = t;
  s.y = y;
  s.style = std::move(style);
  s.options = std::move(options);
  return s;
}

constexpr const char* kPointsX = "lc rgb '#1f77b4' pt 7 ps 0.6";
constexpr const char* kPointsY = "lc rgb '#d62728' pt 5 ps 0.6";
constexpr const char* kLineX = "lc rgb '#0b3c68' lw 2";
constexpr const char* kLineY = "lc rgb '#7a1010' lw 2";

}  // namespace

std::vector<std::filesystem::path> WriteDisplacementFigure(const pipeline::TrialAnalysis& trial,
                                                           const std::filesystem::path& dir,
                                                           const std::string& name) {
  const DisplacementCurves c = ComputeDisplacementCurves(trial);
  if (c.measured.t_ms.empty())
    throw std::runtime_error((dir / name).string() + ": trial " + trial.spec.id +
                             " has no valid pose to plot");
  Plot a, b;
  a.title = "(a) displacement of the centre of mass C in the surface frame S";
  a.x_label = "time t (ms)";
  a.y_label = "displacement of C (mm)";
  a.key = "inside bottom right";
  b.title = "(b) angle of the hoof wall";
  b.x_label = "time t (ms)";
  b.y_label = "angle θ of x_B from x_W (°)";
  b.key = "inside top left";
  const auto& m = c.measured;
  a.series.push_back(Curve("x_S (along the surface)", m.t_ms, m.x_S_mm, "points", kPointsX));
  a.series.push_back(Curve("y_S (normal)", m.t_ms, m.y_S_mm, "points", kPointsY));
  b.series.push_back(Curve("measured", m.t_ms, m.theta_deg, "points", kPointsX));
  if (c.has_fit) {
    for (const DisplacementSamples* f : {&c.fit_before, &c.fit_after}) {
      const bool first = f == &c.fit_before;
      a.series.push_back(
          Curve(first ? "x_S fit (parabola)" : "", f->t_ms, f->x_S_mm, "lines", kLineX));
      a.series.push_back(
          Curve(first ? "y_S fit (parabola)" : "", f->t_ms, f->y_S_mm, "lines", kLineY));
      b.series.push_back(Curve(first ? "fit (line)" : "", f->t_ms, f->theta_deg, "lines", kLineX));
    }
    const std::string label = "impact, t* = " + format::Number(c.impact_time_ms) + " ms";
    a.vertical_lines.emplace_back(c.impact_time_ms, label);
    b.vertical_lines.emplace_back(c.impact_time_ms, label);
  }
  // The clip's other impacts (pipeline/trial_impacts.h), each marked at its time.
  if (trial.impacts.size() > 1)
    for (const auto& k : trial.impacts) {
      if (trial.impact.success && k.index == trial.impact.index) continue;
      const double t_ms = 1e3 * k.impact_time_s;
      const std::string label =
          "impact " + std::to_string(k.index) +
          (k.success ? ", e = " + format::Number(k.e, format::Kind::kCoefficient)
                     : " (not measured)");
      a.vertical_lines.emplace_back(t_ms, label);
      b.vertical_lines.emplace_back(t_ms, label);
    }
  // Nominal settings to 3 significant digits; e with its standard error.
  std::string title = trial.spec.id + ": " + trial.spec.surface + ", surface angle " +
                      format::Significant(trial.spec.surface_angle_deg, 3) + "°";
  if (trial.spec.nominal_speed_m_s)
    title += ", nominal speed " + format::Significant(*trial.spec.nominal_speed_m_s, 3) + " m/s";
  if (trial.impact.success) {
    const double se = trial.impact.e_se;
    title += " (e = " + format::WithError(trial.impact.e, se, format::Kind::kCoefficient) +
             (std::isfinite(se) && se > 0 ? ", ±1 s.e.)" : ")");
  }
  MultiPlot fig;
  fig.title = title;
  fig.panels = {a, b};
  fig.rows = 2;
  fig.width_px = 900;
  fig.height_px = 900;
  return WriteFigure(fig, dir, name);
}

std::vector<std::filesystem::path> WriteHeightFigure(const pipeline::TrialAnalysis& trial,
                                                     const std::filesystem::path& dir,
                                                     const std::string& name) {
  if (!trial.arcs || trial.arcs->status != kinematics::ArcFitStatus::kFitted ||
      !(trial.arcs->a_norm > 0))
    throw std::runtime_error((dir / name).string() + ": trial " + trial.spec.id +
                             " was not measured by its flight arcs");
  const kinematics::FlightArcs& arcs = *trial.arcs;
  const Eigen::Vector2d up = -arcs.a_W / arcs.a_norm;
  const double d_EC = trial.spec.specimen.d_EC_m;
  auto time_of = [&](std::size_t f) {
    return f < trial.timing.t_s.size() ? trial.timing.t_s[f] : core::kNaN;
  };
  std::vector<double> h;  // each pose's height along up (m), NaN without a pose
  for (const auto& p : trial.poses)
    h.push_back(p.valid ? up.dot(p.p_WE + d_EC * core::BodyRotation(p.theta_W_rad).x_B())
                        : core::kNaN);
  double level =
      trial.contact_line && trial.contact_line->measured ? trial.contact_line->level_m : core::kNaN;
  if (!std::isfinite(level)) {
    level = 1e300;
    for (double v : h)
      if (std::isfinite(v)) level = std::min(level, v);
  }
  Series on, off;
  for (std::size_t f = 0; f < h.size() && f < arcs.frames.size(); ++f) {
    if (!std::isfinite(h[f]) || !std::isfinite(time_of(f))) continue;
    const bool fitted = arcs.frames[f].role == kinematics::ArcFrameRole::kArc;
    Series& s = fitted ? on : off;
    s.x.push_back(1e3 * time_of(f));
    s.y.push_back(1e3 * (h[f] - level));
  }
  on.title = "measured, on an arc";
  on.style = "points";
  on.options = kPointsX;
  off.title = "measured, left out (contact, outlier, not in flight)";
  off.style = "points";
  off.options = "lc rgb '#999999' pt 6 ps 0.7";
  Plot plot;
  plot.title = trial.spec.id +
               ": height of C above the contact level, with the flight arcs\n"
               "each impact dashed with its e (n/m: found, not measured)";
  plot.x_label = "time t (ms)";
  plot.y_label = "height of C (mm)";
  plot.key = "below center horizontal";
  plot.series.push_back(on);
  if (!off.x.empty()) plot.series.push_back(off);
  bool first = true;
  for (std::size_t k = 0; k < arcs.arcs.size(); ++k) {
    const kinematics::FlightArc& a = arcs.arcs[k];
    if (!a.fitted) continue;
    const double t0 = time_of(static_cast<std::size_t>(a.first_frame));
    const double t1 = time_of(static_cast<std::size_t>(a.last_frame));
    if (!std::isfinite(t0) || !std::isfinite(t1)) continue;
    Series c;
    c.title = first ? "fitted arcs (one shared acceleration)" : "";
    first = false;
    c.style = "lines";
    c.options = kLineX;
    for (int i = 0; i <= 40; ++i) {
      const double t = t0 + (t1 - t0) * i / 40.0;
      c.x.push_back(1e3 * t);
      c.y.push_back(
          1e3 * (up.dot(kinematics::ArcPosition(arcs, arcs.x, static_cast<int>(k), t)) - level));
    }
    plot.series.push_back(c);
  }
  for (const auto& k : trial.impacts) {
    if (!std::isfinite(k.impact_time_s)) continue;
    plot.vertical_lines.emplace_back(
        1e3 * k.impact_time_s, k.success ? "e " + format::Significant(k.e, 3) : std::string("n/m"));
  }
  plot.horizontal_lines = {0.0};
  plot.horizontal_lines_title = "contact level";
  plot.width_px = 1000;
  plot.height_px = 560;
  return WriteFigure(plot, dir, name);
}

// ---- Figures 4 and 5 ------------------------------------------------------------------------

namespace {

double Value(const studyfile::TrialResult& t, StudyQuantity q) {
  return q == StudyQuantity::kRestitution ? t.e : t.mu_eff;
}

double StandardError(const studyfile::TrialResult& t, StudyQuantity q) {
  return q == StudyQuantity::kRestitution ? t.e_se : t.mu_eff_se;
}

double Level(const studyfile::TrialResult& t, StudyFactor f) {
  return f == StudyFactor::kImpactAngle ? t.surface_angle_deg : t.nominal_speed_m_s;
}

}  // namespace

std::vector<CellSummary> SummarizeByCell(const std::vector<studyfile::TrialResult>& trials,
                                         StudyQuantity quantity, StudyFactor factor) {
  std::vector<std::string> surfaces;  // in order of first appearance
  // Per cell: the values and the trials' own standard errors.
  std::map<std::pair<std::size_t, double>, std::vector<std::pair<double, double>>> cells;
  for (const auto& t : trials) {
    const double v = Value(t, quantity), level = Level(t, factor);
    if (!t.success || !std::isfinite(v) || !std::isfinite(level)) continue;
    if (quantity == StudyQuantity::kEffectiveFriction && !(t.surface_angle_deg > 0)) continue;
    auto it = std::find(surfaces.begin(), surfaces.end(), t.surface);
    if (it == surfaces.end()) it = surfaces.insert(surfaces.end(), t.surface);
    cells[{static_cast<std::size_t>(it - surfaces.begin()), level}].emplace_back(
        v, StandardError(t, quantity));
  }
  std::vector<CellSummary> out;
  for (const auto& [key, values] : cells) {
    CellSummary s;
    s.surface = surfaces[key.first];
    s.level = key.second;
    s.n = values.size();
    double sum = 0.0;
    for (const auto& [v, se] : values) sum += v;
    s.mean = sum / static_cast<double>(s.n);
    double ss = 0.0;
    for (const auto& [v, se] : values) ss += (v - s.mean) * (v - s.mean);
    s.sd = s.n > 1 ? std::sqrt(ss / static_cast<double>(s.n - 1)) : NAN;
    const double own_se = values.front().second;
    s.se = s.n > 1 ? s.sd / std::sqrt(static_cast<double>(s.n))
                   : (std::isfinite(own_se) && own_se > 0 ? own_se : NAN);
    out.push_back(s);
  }
  return out;
}

namespace {

/// One series per surface, nudged sideways (see WriteStudyFigure).
std::vector<Series> SurfaceSeries(const std::vector<CellSummary>& cells,
                                  const std::string& level_name) {
  std::vector<double> levels;
  std::vector<std::string> surfaces;
  for (const auto& c : cells) {
    levels.push_back(c.level);
    if (std::find(surfaces.begin(), surfaces.end(), c.surface) == surfaces.end())
      surfaces.push_back(c.surface);
  }
  std::sort(levels.begin(), levels.end());
  double spacing = 0.0;
  for (std::size_t i = 1; i < levels.size(); ++i)
    if (levels[i] > levels[i - 1] && (spacing == 0.0 || levels[i] - levels[i - 1] < spacing))
      spacing = levels[i] - levels[i - 1];
  if (spacing == 0.0) spacing = 1.0;
  static const char* const kColours[] = {"#1f77b4", "#d62728", "#2ca02c",
                                         "#9467bd", "#ff7f0e", "#8c564b"};
  static const int kPointTypes[] = {7, 5, 9, 11, 13, 15};
  std::vector<Series> out;
  for (std::size_t k = 0; k < surfaces.size(); ++k) {
    Series s;
    s.title = surfaces[k];
    s.options = std::string("lw 1.5 ps 1.3 lc rgb '") + kColours[k % 6] + "' pt " +
                std::to_string(kPointTypes[k % 6]);
    const double shift =
        0.05 * spacing * (static_cast<double>(k) - 0.5 * static_cast<double>(surfaces.size() - 1));
    std::vector<double> level, n, sd;
    for (const auto& c : cells)
      if (c.surface == surfaces[k]) {
        s.x.push_back(c.level + shift);
        s.y.push_back(c.mean);
        s.y_error.push_back(c.se);
        level.push_back(c.level);
        n.push_back(static_cast<double>(c.n));
        sd.push_back(c.sd);
      }
    s.extra_columns = {{level_name + " without the sideways nudge", level},
                       {"trials in the cell (1)", n},
                       {"s.d. of the trials (1)", sd}};
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace

std::vector<std::filesystem::path> WriteStudyFigure(const studyfile::StudyResults& study,
                                                    StudyQuantity quantity, StudyFactor factor,
                                                    const std::filesystem::path& dir,
                                                    const std::string& name) {
  const std::vector<CellSummary> cells = SummarizeByCell(study.trials, quantity, factor);
  if (cells.empty()) return {};
  std::size_t n_min = cells.front().n, n_max = cells.front().n;
  for (const auto& c : cells) {
    n_min = std::min(n_min, c.n);
    n_max = std::max(n_max, c.n);
  }
  const bool e = quantity == StudyQuantity::kRestitution;
  const bool angle = factor == StudyFactor::kImpactAngle;
  std::string title = std::string(e ? "Coefficient of restitution"
                                    : "Effective coefficient of friction (oblique impacts)") +
                      " by " + (angle ? "impact angle" : "nominal speed");
  if (!study.name.empty()) title += " (" + study.name + ")";
  title += "\nmean ± 1 s.e. of the mean (s.d./√n), n = " + std::to_string(n_min);
  if (n_max != n_min) title += "–" + std::to_string(n_max);
  title += " trials per point";
  if (n_min == 1) title += "\na cell of one trial: that trial's own s.e.";
  Plot plot;
  plot.title = title;
  plot.x_label = angle ? "impact angle φ (°)" : "nominal impact speed (m/s)";
  plot.y_label = e ? "coefficient of restitution e" : "effective coefficient of friction μ_{eff}";
  plot.key = "outside right top";
  plot.series = SurfaceSeries(cells, plot.x_label);
  plot.width_px = 900;
  plot.height_px = 550;
  return WriteFigure(plot, dir, name);
}

std::vector<std::filesystem::path> WriteStudyFigures(const studyfile::StudyResults& study,
                                                     const std::filesystem::path& dir) {
  struct Item {
    const char* name;
    StudyQuantity quantity;
    StudyFactor factor;
  };
  const Item items[] = {
      {"e_by_angle", StudyQuantity::kRestitution, StudyFactor::kImpactAngle},
      {"e_by_speed", StudyQuantity::kRestitution, StudyFactor::kSpeed},
      {"mu_eff_by_angle", StudyQuantity::kEffectiveFriction, StudyFactor::kImpactAngle},
      {"mu_eff_by_speed", StudyQuantity::kEffectiveFriction, StudyFactor::kSpeed}};
  std::vector<std::filesystem::path> written;
  for (const Item& item : items)
    for (auto& path : WriteStudyFigure(study, item.quantity, item.factor, dir, item.name))
      written.push_back(std::move(path));
  return written;
}

std::vector<std::string> WriteTrialFigures(const pipeline::TrialAnalysis& r,
                                           const pipeline::TrialAnalysisOptions& options,
                                           const std::string& dir, bool always, bool displacement) {
  std::vector<std::string> written;
  if (dir.empty()) return written;
  const bool flagged = std::find(r.flags.begin(), r.flags.end(), "out_of_plane") != r.flags.end();
  const bool any_pose = std::any_of(r.poses.begin(), r.poses.end(),
                                    [](const tracking::BodyPose& p) { return p.valid; });
  if (!r.marker_distance_ratio.empty() && (flagged || always))
    for (const auto& path :
         WriteOutOfPlaneFigure(r, options.out_of_plane_threshold, dir, r.spec.id + "_out_of_plane"))
      written.push_back(path.string());
  if (displacement && any_pose)
    for (const auto& path : WriteDisplacementFigure(r, dir, r.spec.id + "_displacement"))
      written.push_back(path.string());
  if (displacement && r.arcs && r.arcs->status == kinematics::ArcFitStatus::kFitted &&
      r.arcs->a_norm > 0)
    for (const auto& path : WriteHeightFigure(r, dir, r.spec.id + "_height"))
      written.push_back(path.string());
  return written;
}

}  // namespace hoof::report
