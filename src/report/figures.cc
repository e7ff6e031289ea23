#include "report/figures.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "report/gnuplot.h"

namespace hoof::report {

void WriteOutOfPlaneFigure(const pipeline::TrialAnalysis& trial, double threshold,
                           const std::filesystem::path& output) {
  Series s;
  s.title = "projected / layout marker distance";
  std::vector<double> finite;
  for (std::size_t f = 0; f < trial.marker_distance_ratio.size(); ++f) {
    s.x.push_back(static_cast<double>(f));
    s.y.push_back(100.0 * trial.marker_distance_ratio[f]);
    if (std::isfinite(trial.marker_distance_ratio[f])) finite.push_back(100.0 * trial.marker_distance_ratio[f]);
  }
  Plot plot;
  const bool flagged =
      std::find(trial.flags.begin(), trial.flags.end(), "out_of_plane") != trial.flags.end();
  std::ostringstream title;
  title.precision(3);
  title << trial.spec.id << ": out-of-plane check " << (flagged ? "FLAGGED" : "passed")
        << " (change " << 100 * trial.out_of_plane_change << " %, noise "
        << 100 * trial.out_of_plane_noise << " %)";
  plot.title = title.str();
  plot.x_label = "frame";
  plot.y_label = "marker distance (% of the layout's)";
  plot.series.reserve(1);
  plot.series.push_back(s);
  if (trial.impact.success) {
    plot.shaded_x_ranges.emplace_back(trial.impact.before.first_frame, trial.impact.before.last_frame);
    plot.shaded_x_ranges.emplace_back(trial.impact.after.first_frame, trial.impact.after.last_frame);
  }
  if (!finite.empty()) {
    std::nth_element(finite.begin(), finite.begin() + static_cast<std::ptrdiff_t>(finite.size() / 2), finite.end());
    const double median = finite[finite.size() / 2];
    const double limit = 100 * std::max(threshold, 8.0 * trial.out_of_plane_noise);
    plot.horizontal_lines = {median - limit / 2, median + limit / 2};
    plot.horizontal_lines_title = "flag threshold (a change wider than the band)";
  }
  RenderPlot(plot, output);
}

}  // namespace hoof::report
