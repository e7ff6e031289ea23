#pragma once
/// @file
/// Figures through gnuplot (Debian's gnuplot-nox): a small description of a 2-D plot, turned
/// into a gnuplot script with the data inline, rendered to PNG (pngcairo) or SVG by the output
/// file's extension, and written atomically. Several plots can share one image as panels
/// (gnuplot's multiplot).

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace hoof::report {

/// One data series.
struct Series {
  std::string title;  ///< legend entry; empty = none
  std::vector<double> x, y;
  /// Optional error bars (half-length, same length as y). A NaN entry draws the point without
  /// a bar (e.g. the standard deviation of a group of one).
  std::vector<double> y_error;
  std::string style = "linespoints";  ///< gnuplot style: lines, points, linespoints, ...
  /// Extra gnuplot style options appended to `style`, e.g. "lw 2 lc rgb '#1f77b4' pt 7".
  std::string options;
};

/// A 2-D plot.
struct Plot {
  /// The title may hold line breaks ("\n"); the axis labels may use gnuplot's enhanced text
  /// (x_{S}, {/Symbol f}).
  std::string title, x_label, y_label;
  std::vector<Series> series;
  std::vector<std::pair<double, double>> shaded_x_ranges;  ///< e.g. fit windows
  std::vector<double> horizontal_lines;                    ///< dashed reference lines
  std::string horizontal_lines_title = "reference";        ///< their legend entry
  /// Dashed vertical lines at x, each with a text label at its top (e.g. the impact time).
  std::vector<std::pair<double, std::string>> vertical_lines;
  std::string key = "inside bottom left";  ///< gnuplot legend placement
  int width_px = 900, height_px = 500;     ///< image size when rendered alone
};

/// Panels in one image: `rows` rows of plots filled row by row, under a common title. The
/// panels' own sizes are ignored.
struct MultiPlot {
  std::string title;
  std::vector<Plot> panels;
  int rows = 1;  ///< >= 1; columns = ceil(panels / rows)
  int width_px = 900, height_px = 900;
};

/// The gnuplot script for `plot` writing to `output` (data inline, so the script stands alone).
std::string GnuplotScript(const Plot& plot, const std::filesystem::path& output);
/// The gnuplot script for the panels of `figure` writing to `output`.
std::string GnuplotScript(const MultiPlot& figure, const std::filesystem::path& output);

/// Renders `plot` to `output` (.png or .svg) with gnuplot. Throws std::runtime_error naming the
/// file when there is no series, or gnuplot is missing or fails; `output` is written only when
/// complete, and no temporary file is left behind.
void RenderPlot(const Plot& plot, const std::filesystem::path& output);
/// Whether a file name is one of RenderPlot's temporaries ("<figure>.png.tmp-<pid>-<n>.png",
/// its script and its error log; the same for SVG): what a killed run leaves in a figure folder,
/// for io::RemoveStaleTemporaries.
bool IsFigureTemporary(const std::string& name);
/// Renders the panels of `figure` to `output`; otherwise as RenderPlot (every panel needs a
/// series).
void RenderPlot(const MultiPlot& figure, const std::filesystem::path& output);

}  // namespace hoof::report
