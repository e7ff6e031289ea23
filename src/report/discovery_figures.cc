#include "report/discovery_figures.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>

#include "core/frames.h"
#include "format/number_format.h"
#include "io/atomic_file.h"
#include "report/gnuplot.h"

namespace hoof::report {
namespace {

namespace fs = std::filesystem;

constexpr const char* kBefore = "#d62728";  // current / baseline model
constexpr const char* kAfter = "#1f77b4";   // with the effect / final model

template <class Figure>
void Render(const Figure& figure, const fs::path& dir, const std::string& name,
            std::vector<fs::path>& written) {
  for (auto& path : WriteFigure(figure, dir, name)) written.push_back(std::move(path));
}

std::string Percent(double fraction) {
  if (!std::isfinite(fraction)) return format::kUndefined;
  return format::Number(100.0 * fraction) + " %";
}

/// Root mean square of the finite values; NaN when none.
double Rms(const std::vector<double>& v) {
  double sum = 0.0;
  int n = 0;
  for (double x : v)
    if (std::isfinite(x)) {
      sum += x * x;
      ++n;
    }
  return n > 0 ? std::sqrt(sum / n) : core::kNaN;
}

/// An empty series of points in the given look.
Series PointSeries(std::string title, const std::string& options) {
  Series s;
  s.title = std::move(title);
  s.style = "points";
  s.options = options;
  return s;
}

/// Adds the finite (x, y) points of `s` to `plot`, when there is one.
void AddIfData(Plot& plot, Series s) {
  Series kept = s;
  kept.x.clear();
  kept.y.clear();
  for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i)
    if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) {
      kept.x.push_back(s.x[i]);
      kept.y.push_back(s.y[i]);
    }
  if (!kept.x.empty()) plot.series.push_back(std::move(kept));
}

void GapFigure(const discovery::Round& round, int n, const fs::path& dir,
               std::vector<fs::path>& written) {
  std::vector<const discovery::GapTrial*> trials;
  for (const auto& g : round.gap) trials.push_back(&g);
  std::stable_sort(trials.begin(), trials.end(), [](const auto* a, const auto* b) {
    return std::tie(a->surface, a->angle_deg, a->speed_m_s, a->id) <
           std::tie(b->surface, b->angle_deg, b->speed_m_s, b->id);
  });
  Plot p;
  std::ostringstream title;
  title << "Round " << n << ": " << round.accepted << " added. Held-out gap "
        << Percent(round.gap_before) << " → " << Percent(round.gap_after);
  if (std::isfinite(round.gap_shrink))
    title << " (" << discovery::GapChangeText(round.gap_shrink) << ")";
  title << "\n" << trials.size() << " held-out trials, each fitted without its fold";
  p.title = title.str();
  std::string surfaces;
  for (std::size_t i = 0; i < trials.size(); ++i)
    if (i == 0 || trials[i]->surface != trials[i - 1]->surface)
      surfaces += (surfaces.empty() ? "" : ", ") + trials[i]->surface;
  p.x_label = "held-out trial, sorted by surface (" + surfaces + "), angle and speed";
  p.y_label = "gap after impact (% of impact speed)";
  p.key = "outside right top";
  p.width_px = 1000;
  Series before = PointSeries("current model", std::string("pt 6 ps 1.3 lc rgb '") + kBefore + "'");
  Series after =
      PointSeries("with " + round.accepted, std::string("pt 7 ps 1.1 lc rgb '") + kAfter + "'");
  for (std::size_t i = 0; i < trials.size(); ++i) {
    const double x = static_cast<double>(i + 1);
    before.x.push_back(x);
    before.y.push_back(100.0 * trials[i]->gap_before);
    after.x.push_back(x);
    after.y.push_back(100.0 * trials[i]->gap_after);
    if (i > 0 && trials[i]->surface != trials[i - 1]->surface)  // where a surface begins
      p.vertical_lines.emplace_back(x - 0.5, trials[i]->surface);
  }
  AddIfData(p, before);
  AddIfData(p, after);
  if (p.series.empty()) return;
  Render(p, dir, "discovery_gap_round" + std::to_string(n), written);
}

void ResidualFigure(const discovery::DiscoveryResult& r, const fs::path& dir,
                    std::vector<fs::path>& written) {
  MultiPlot figure;
  figure.title =
      "Residuals after impact (measured - simulated) against impact speed: baseline "
      "and final model";
  figure.width_px = 900;
  figure.height_px = 1000;
  // v_y first: it carries e.
  const struct {
    int component;
    const char* label;
  } panels[] = {
      {1, "v_y (normal; carries e)"}, {0, "v_x (along the surface)"}, {2, "w d_EC (spin)"}};
  for (const auto& panel : panels) {
    Plot p;
    p.title = panel.label;
    p.x_label = "impact speed (m/s)";
    p.y_label = "residual (% of impact speed)";
    p.key = "outside right top";
    Series b = PointSeries("", std::string("pt 6 ps 1.2 lc rgb '") + kBefore + "'");
    Series f = PointSeries("", std::string("pt 7 ps 0.9 lc rgb '") + kAfter + "'");
    for (const auto& t : r.residuals) {
      b.x.push_back(t.speed_m_s);
      b.y.push_back(100.0 * t.baseline[panel.component]);
      f.x.push_back(t.speed_m_s);
      f.y.push_back(100.0 * t.final_model[panel.component]);
    }
    b.title = "baseline (rms " + Percent(Rms(b.y) / 100.0) + ")";
    f.title = "final (rms " + Percent(Rms(f.y) / 100.0) + ")";
    AddIfData(p, b);
    AddIfData(p, f);
    if (p.series.empty()) continue;
    p.horizontal_lines = {0.0};
    p.horizontal_lines_title = "zero";
    figure.panels.push_back(std::move(p));
  }
  if (figure.panels.empty()) return;
  figure.rows = static_cast<int>(figure.panels.size());
  Render(figure, dir, "discovery_residuals", written);
}

}  // namespace

std::vector<fs::path> WriteDiscoveryFigures(const discovery::DiscoveryResult& result,
                                            const fs::path& dir) {
  std::vector<fs::path> written;
  io::CreateFolder(dir);  // `dir` may be the report's temporary folder
  for (std::size_t i = 0; i < result.rounds.size(); ++i) {
    const auto& round = result.rounds[i];
    if (round.accepted.empty() || round.gap.empty()) continue;
    GapFigure(round, static_cast<int>(i + 1), dir, written);
  }
  ResidualFigure(result, dir, written);
  return written;
}

}  // namespace hoof::report
