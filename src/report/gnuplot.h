#pragma once
/// @file
/// Figures through gnuplot (Debian's gnuplot-nox): a small description of a 2-D plot, turned
/// into a gnuplot script with the data inline, rendered to PNG (pngcairo) or SVG by the output
/// file's extension, and written atomically.

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace hoof::report {

/// One data series.
struct Series {
  std::string title;
  std::vector<double> x, y;
  std::vector<double> y_error;       ///< optional error bars (same length as y)
  std::string style = "linespoints"; ///< gnuplot style: lines, points, linespoints, ...
};

/// A 2-D plot.
struct Plot {
  std::string title, x_label, y_label;
  std::vector<Series> series;
  std::vector<std::pair<double, double>> shaded_x_ranges;  ///< e.g. fit windows
  std::vector<double> horizontal_lines;                     ///< dashed reference lines
  std::string horizontal_lines_title = "reference";         ///< their legend entry
  int width_px = 900, height_px = 500;
};

/// The gnuplot script for `plot` writing to `output` (data inline, so the script stands alone).
std::string GnuplotScript(const Plot& plot, const std::filesystem::path& output);

/// Renders `plot` to `output` (.png or .svg) with gnuplot. Throws std::runtime_error naming the
/// file when gnuplot is missing or fails; `output` is written only when complete.
void RenderPlot(const Plot& plot, const std::filesystem::path& output);

}  // namespace hoof::report
