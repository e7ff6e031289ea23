#pragma once
/// @file
/// Figures through gnuplot (Debian's gnuplot-nox): a small description of a 2-D plot, written
/// as a figure that anyone can restyle. Figure NAME is four files in one folder:
///  - NAME.csv: the plotted data, one header row naming each column with its unit;
///  - NAME.gp: the gnuplot script; `gnuplot NAME.gp` run in that folder reads NAME.csv and
///    writes the two images (relative paths only, so the folder can be moved);
///  - NAME.svg and NAME.png: the images, made by running that very script.
/// Several plots can share one image as panels (gnuplot's multiplot). The tick step and the
/// tick labels' decimals are chosen from the data's range, so no two tick labels read alike.
/// Error bars are half-lengths; the figures of this program draw ±1 standard error.

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace hoof::report {

/// One data series.
struct Series {
  std::string title;  ///< legend entry; empty = none
  std::vector<double> x, y;
  /// Optional vertical error bars (half-length, same length as y). A NaN entry draws the point
  /// without a bar (e.g. a cell of one trial).
  std::vector<double> y_error;
  /// Optional horizontal error bars (half-length, same length as x), as y_error.
  std::vector<double> x_error;
  std::string style = "linespoints";  ///< gnuplot style: lines, points, linespoints, ...
  /// Extra gnuplot style options appended to `style`, e.g. "lw 2 lc rgb '#1f77b4' pt 7".
  std::string options;
  /// Further columns of the figure's CSV that are not drawn (name with unit, one value per
  /// point), e.g. the number of trials behind each mean.
  std::vector<std::pair<std::string, std::vector<double>>> extra_columns;
};

/// A 2-D plot.
struct Plot {
  /// The title may hold line breaks ("\n"); the axis labels may use gnuplot's enhanced text
  /// (x_{S}, μ_{eff}; UTF-8 such as µs and ° is drawn as written) and carry their unit in
  /// parentheses at the end, which the CSV's header repeats ("(1)" where there is none).
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

/// The figure's data as CSV: for each series (of each panel) its columns x, y, then the error
/// bars' half-lengths (y, then x) when it has them, then its extra columns; a series shorter
/// than the longest leaves its cells empty below its last point, and an undefined value is
/// "nan". Header names are "<series>: <axis label>" ("<panel>: <series>: ..." in a multiplot)
/// with the axis label's unit, and "s.e. of ..." for the error bars.
std::string FigureCsv(const Plot& plot);
std::string FigureCsv(const MultiPlot& figure);

/// The gnuplot script of figure `name`: reads `name`.csv and writes `name`.svg and `name`.png,
/// all in the folder gnuplot runs in.
std::string FigureScript(const Plot& plot, const std::string& name);
std::string FigureScript(const MultiPlot& figure, const std::string& name);

/// Writes figure `name` into `dir` (created when missing): NAME.csv, NAME.gp, and NAME.svg and
/// NAME.png made by running gnuplot on that script. Each file is renamed into place only when
/// all four are complete, and nothing temporary is left behind. Returns the files written:
/// PNG, SVG, CSV, script. Throws std::runtime_error naming `dir`/`name` when there is no
/// series (or a panel without one), gnuplot is missing or fails, or a file cannot be written.
std::vector<std::filesystem::path> WriteFigure(const Plot& plot, const std::filesystem::path& dir,
                                               const std::string& name);
std::vector<std::filesystem::path> WriteFigure(const MultiPlot& figure,
                                               const std::filesystem::path& dir,
                                               const std::string& name);

/// Whether a file name is one of WriteFigure's temporaries (the folder "<name>.figure.tmp-<pid>-
/// <n>" it renders in, and the temporaries of earlier versions, "<figure>.png.tmp-..." and
/// ".svg.tmp-..."): what a killed run leaves in a figure folder, for io::RemoveStaleTemporaries.
bool IsFigureTemporary(const std::string& name);

/// Tick marks chosen from the range of an axis' values: a step of 1, 2 or 5 times a power of
/// ten giving at most 8 ticks over the range (padded as the figure pads it), and a printf
/// format with as many decimals as the step needs, so that neighbouring labels always differ.
/// When every value is the same (or the range is below 1e-9 of their size) the range itself is
/// set, ±5 % of the value (±1 about zero). `valid` is false when there is no finite value.
struct Ticks {
  bool valid = false;
  double step = 0.0;
  std::string format;  ///< e.g. "%.5f", or "%.3e" for very large or very small values
  bool fixed_range = false;
  double low = 0.0, high = 0.0;  ///< when fixed_range
};
Ticks ChooseTicks(const std::vector<double>& values, double padding_fraction);

}  // namespace hoof::report
