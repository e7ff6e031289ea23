#include "report/gnuplot.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include "io/atomic_file.h"
#include "io/csv.h"
#include "io/interrupt.h"

namespace hoof::report {
namespace {

namespace fs = std::filesystem;

/// A gnuplot string expression holding `s` exactly: single-quoted pieces (gnuplot substitutes
/// no backquoted command, escape or macro inside single quotes; a quote is doubled), joined by
/// a double-quoted "\n" where `s` breaks its line. Text from a study (an id, a surface) never
/// reaches a double-quoted string, where gnuplot would run `...` as a shell command.
std::string Quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\n') {
      out += "'.\"\\n\".'";
    } else if (c == '\'') {
      out += "''";
    } else if (c == '\r' || c == '\0') {
      out += ' ';  // would end the command
    } else {
      out += c;
    }
  }
  return out + "'";
}

std::string Number(double v) { return std::isfinite(v) ? io::CsvNumber(v) : "NaN"; }

/// A tick step as gnuplot reads it (15 significant digits: 5e-05, not 5.0000000000000002e-05).
std::string Step(double v) {
  std::ostringstream s;
  s.precision(15);
  s << v;
  return s.str();
}

/// An axis label as plain text for the CSV's header: enhanced-text braces dropped, line
/// breaks as spaces, and "(1)" for a label that names no unit.
std::string PlainLabel(const std::string& label) {
  std::string out;
  for (char c : label)
    if (c == '\n' || c == '\r')
      out += ' ';
    else if (c != '{' && c != '}' && c != '\0')
      out += c;
  if (out.empty() || out.back() != ')') out += out.empty() ? "(1)" : " (1)";
  return out;
}

/// Text for a comment line of the script: one line, and no backslash (which would continue
/// the comment onto the next line).
std::string CommentText(const std::string& s) {
  std::string out;
  for (char c : s) out += (c == '\n' || c == '\r' || c == '\\' || c == '\0') ? ' ' : c;
  return out;
}

/// Where one series' values are in the CSV (1-based columns; 0 = none).
struct Columns {
  int x = 0, y = 0, y_error = 0, x_error = 0;
};

/// One plot of a figure: the plot, its panel's title prefix for the CSV ("" when alone) and
/// where its series' columns are.
struct Panel {
  const Plot* plot;
  std::string prefix;
  std::vector<Columns> columns;
};

std::vector<Panel> Layout(const std::vector<const Plot*>& plots, bool multi) {
  std::vector<Panel> out;
  int next = 1;
  for (std::size_t p = 0; p < plots.size(); ++p) {
    Panel panel{plots[p], "", {}};
    if (multi)
      panel.prefix = (plots[p]->title.empty() ? "panel " + std::to_string(p + 1)
                                              : CommentText(plots[p]->title)) +
                     ": ";
    for (const Series& s : plots[p]->series) {
      Columns c;
      c.x = next++;
      c.y = next++;
      if (!s.y_error.empty()) c.y_error = next++;
      if (!s.x_error.empty()) c.x_error = next++;
      next += static_cast<int>(s.extra_columns.size());
      panel.columns.push_back(c);
    }
    out.push_back(std::move(panel));
  }
  return out;
}

std::string SeriesName(const Series& s, std::size_t i) {
  return s.title.empty() ? "series " + std::to_string(i + 1) : CommentText(s.title);
}

/// The CSV's header names, column by column.
std::vector<std::string> HeaderNames(const std::vector<Panel>& panels) {
  std::vector<std::string> names;
  for (const Panel& panel : panels) {
    const std::string x = PlainLabel(panel.plot->x_label), y = PlainLabel(panel.plot->y_label);
    for (std::size_t i = 0; i < panel.plot->series.size(); ++i) {
      const Series& s = panel.plot->series[i];
      const std::string name = panel.prefix + SeriesName(s, i) + ": ";
      names.push_back(name + x);
      names.push_back(name + y);
      if (!s.y_error.empty()) names.push_back(name + "s.e. of " + y);
      if (!s.x_error.empty()) names.push_back(name + "s.e. of " + x);
      for (const auto& [extra, values] : s.extra_columns) names.push_back(name + extra);
    }
  }
  return names;
}

std::string Csv(const std::vector<Panel>& panels) {
  std::ostringstream os;
  const std::vector<std::string> names = HeaderNames(panels);
  for (std::size_t i = 0; i < names.size(); ++i) os << (i ? "," : "") << io::CsvEscape(names[i]);
  os << "\n";
  std::size_t rows = 0;
  for (const Panel& panel : panels)
    for (const Series& s : panel.plot->series)
      rows = std::max(rows, std::min(s.x.size(), s.y.size()));
  const auto cell = [](const std::vector<double>& v, std::size_t r, std::size_t n) {
    return r < n ? io::CsvNumber(r < v.size() ? v[r] : NAN) : std::string();
  };
  for (std::size_t r = 0; r < rows; ++r) {
    bool first = true;
    for (const Panel& panel : panels)
      for (const Series& s : panel.plot->series) {
        const std::size_t n = std::min(s.x.size(), s.y.size());
        std::vector<const std::vector<double>*> columns = {&s.x, &s.y};
        if (!s.y_error.empty()) columns.push_back(&s.y_error);
        if (!s.x_error.empty()) columns.push_back(&s.x_error);
        for (const auto& extra : s.extra_columns) columns.push_back(&extra.second);
        for (const auto* c : columns) {
          os << (first ? "" : ",") << cell(*c, r, n);
          first = false;
        }
      }
    os << "\n";
  }
  return os.str();
}

/// The finite values of an axis, error bars included.
void Collect(std::vector<double>& out, const std::vector<double>& v,
             const std::vector<double>& error) {
  for (std::size_t k = 0; k < v.size(); ++k) {
    if (!std::isfinite(v[k])) continue;
    out.push_back(v[k]);
    const double e = k < error.size() ? error[k] : NAN;
    if (std::isfinite(e)) {
      out.push_back(v[k] - std::abs(e));
      out.push_back(v[k] + std::abs(e));
    }
  }
}

/// The tick settings of axis `axis` ("x" or "y") for `values`, padded by `padding` of the range
/// each side (the figure's offsets).
void TickCommands(std::ostream& os, const std::string& axis, const std::vector<double>& values,
                  double padding, const std::string& indent) {
  const Ticks t = ChooseTicks(values, padding);
  if (!t.valid) {
    os << indent << "set " << axis << "tics autofreq\n"
       << indent << "set format " << axis << " '% h'\n";
    return;
  }
  os << indent << "set " << axis << "tics " << Step(t.step) << "\n"
     << indent << "set format " << axis << " '" << t.format << "'\n";
  if (t.fixed_range)
    os << indent << "set " << axis << "range [" << Step(t.low) << ":" << Step(t.high) << "]\n";
}

constexpr double kPadX = 0.04, kPadY = 0.06;  // the figures' offsets, fractions of the range

/// Settings and the plot command of one panel; undoes its objects, arrows and labels after.
void PlotCommands(std::ostream& os, const Panel& panel, const std::string& indent) {
  const Plot& plot = *panel.plot;
  os << indent << "set title " << Quote(plot.title) << " noenhanced\n";
  os << indent << "set xlabel " << Quote(plot.x_label) << "\n"
     << indent << "set ylabel " << Quote(plot.y_label) << "\n";
  os << indent << "set grid\n"
     << indent << "set key " << plot.key << " box opaque noenhanced\n"
     << indent << "set autoscale fix\n"
     << indent << "set offsets graph " << kPadX << ", graph " << kPadX << ", graph " << kPadY
     << ", graph " << kPadY << "\n";
  std::vector<double> xs, ys;
  for (const Series& s : plot.series) {
    Collect(xs, s.x, s.x_error);
    Collect(ys, s.y, s.y_error);
  }
  for (double y : plot.horizontal_lines)
    if (std::isfinite(y)) ys.push_back(y);
  TickCommands(os, "x", xs, kPadX, indent);
  TickCommands(os, "y", ys, kPadY, indent);
  int obj = 1;
  for (const auto& [a, b] : plot.shaded_x_ranges)
    os << indent << "set object " << obj++ << " rect from " << Number(a) << ", graph 0 to "
       << Number(b) << ", graph 1 fc rgb '#dde8f5' fs solid 0.6 noborder behind\n";
  int arrow = 1;
  for (const auto& [x, label] : plot.vertical_lines) {
    os << indent << "set arrow " << arrow << " from " << Number(x) << ", graph 0 to " << Number(x)
       << ", graph 1 nohead dt 2 lw 1.5 lc rgb '#555555'\n";
    os << indent << "set label " << arrow++ << " " << Quote(label) << " at " << Number(x)
       << ", graph 0.96 offset 0.5, 0 left noenhanced textcolor rgb '#555555'\n";
  }
  os << indent << "plot ";
  bool first = true;
  const std::string more = ", \\\n" + indent + "     ";
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    const Series& s = plot.series[i];
    const Columns& c = panel.columns[i];
    const std::string look =
        " lt " + std::to_string(i + 1) + (s.options.empty() ? "" : " " + s.options);
    const std::string at = std::to_string(c.x) + ":" + std::to_string(c.y);
    os << (first ? "" : more) << "data skip 1 using " << at << " with " << s.style << look
       << " title " << Quote(s.title);
    // Error bars as further plots of the same points, one per axis: rows whose error is
    // undefined are skipped there only, so their point (and its other bar) is still drawn.
    if (c.y_error)
      os << more << "data skip 1 using " << at << ":" << c.y_error << " with yerrorbars" << look
         << " notitle";
    if (c.x_error)
      os << more << "data skip 1 using " << at << ":" << c.x_error << " with xerrorbars" << look
         << " notitle";
    first = false;
  }
  for (double y : plot.horizontal_lines) {
    os << (first ? "" : more) << Number(y) << " with lines dt 2 lc rgb '#888888' "
       << (y == plot.horizontal_lines.front() ? "title " + Quote(plot.horizontal_lines_title)
                                              : std::string("notitle"));
    first = false;
  }
  os << "\n"
     << indent << "unset object\n"
     << indent << "unset arrow\n"
     << indent << "unset label\n";
}

/// The script around the panels: header comments naming the files and the columns, the loop
/// over the two images.
std::string Script(const std::vector<Panel>& panels, const std::string& name, int width_px,
                   int height_px, const std::string& multiplot_line, bool multi) {
  std::ostringstream os;
  const std::string csv = name + ".csv";
  os << "# " << CommentText(name) << ".gp: remakes " << CommentText(name) << ".svg and "
     << CommentText(name) << ".png from " << CommentText(csv) << ".\n"
     << "# Run `gnuplot " << CommentText(name) << ".gp` in the folder that holds it (written by\n"
     << "# hoofimpact; see docs/figures.md). Restyle here: sizes and fonts in `set terminal`,\n"
     << "# colours (lc), point types (pt), sizes (ps) and line widths (lw) on the `plot` lines.\n"
     << "# The tick steps and label formats (`set xtics`, `set format`) were chosen for the data\n"
     << "# as written; delete those lines to let gnuplot choose after editing the data.\n"
     << "# Error bars are ±1 standard error (the 's.e. of' columns).\n"
     << "# Columns of " << CommentText(csv) << ":\n";
  const std::vector<std::string> names = HeaderNames(panels);
  for (std::size_t i = 0; i < names.size(); ++i)
    os << "#   " << i + 1 << ": " << CommentText(names[i]) << "\n";
  os << "set encoding utf8  # labels carry units such as µs, m/s and °\n"
     << "set datafile separator comma\n"
     << "set datafile missing 'nan'\n"
     << "data = " << Quote(csv) << "\n"
     << "do for [out in \"svg png\"] {\n"
     << "  if (out eq \"svg\") {\n"
     << "    set terminal svg size " << width_px << "," << height_px
     << " dynamic enhanced font 'Sans,12' background '#ffffff'\n"
     << "  } else {\n"
     << "    set terminal pngcairo size " << width_px << "," << height_px
     << " enhanced font 'Sans,11'\n"
     << "  }\n"
     << "  set output " << Quote(name + ".") << ".out\n";
  if (multi) os << multiplot_line;
  for (const Panel& panel : panels) PlotCommands(os, panel, "  ");
  if (multi) os << "  unset multiplot\n";
  os << "  set output\n}\n";
  return os.str();
}

std::vector<const Plot*> PanelsOf(const MultiPlot& figure) {
  std::vector<const Plot*> out;
  for (const Plot& p : figure.panels) out.push_back(&p);
  return out;
}

std::string MultiplotLine(const MultiPlot& figure) {
  const std::size_t rows = static_cast<std::size_t>(std::max(figure.rows, 1));
  const std::size_t cols = (figure.panels.size() + rows - 1) / rows;
  std::ostringstream os;
  os << "  set multiplot layout " << rows << "," << cols << " title " << Quote(figure.title)
     << " noenhanced font ',13'\n";
  return os.str();
}

/// Runs gnuplot on `script` (a name in `dir`) in the folder `dir`, without a shell, its error
/// output into the file `err_path`. Returns its exit code (-1 when it did not exit) and whether
/// gnuplot is missing.
std::pair<int, bool> RunGnuplot(const fs::path& dir, const std::string& script,
                                const std::string& err_path) {
  int rc = -1;
  bool missing = false;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err_path.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0600);
  const std::string dir_text = dir.string();
  posix_spawn_file_actions_addchdir_np(&actions, dir_text.c_str());  // glibc >= 2.29
  std::string arg0 = "gnuplot", arg1 = "./" + script;  // "./": a name may start with '-'
  char* argv[] = {arg0.data(), arg1.data(), nullptr};
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  io::ResetChildSignals(attributes);  // Ctrl-C reaches gnuplot too
  pid_t pid = 0;
  std::optional<io::CreatingTemporary> creating(std::in_place);  // an interrupt sees the child
  const int spawned = posix_spawnp(&pid, "gnuplot", &actions, &attributes, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  if (spawned == 0) io::TrackChild(pid);
  creating.reset();
  if (spawned == 0) {
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    io::UntrackChild(pid);
    rc = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    missing = rc == 127;
  } else {
    missing = spawned == ENOENT;
  }
  return {rc, missing};
}

std::string ReadText(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool NonEmptyFile(const fs::path& path) {
  std::error_code ec;
  return fs::is_regular_file(path, ec) && fs::file_size(path, ec) > 0 && !ec;
}

/// Writes the CSV and the script into a private temporary folder inside `dir`, runs gnuplot
/// there, and renames the four files into `dir`; see WriteFigure.
std::vector<fs::path> Commit(const fs::path& dir, const std::string& name, const std::string& csv,
                             const std::string& script) {
  const fs::path figure = dir / name;
  if (name.empty() || name.find('/') != std::string::npos || name == "." || name == "..")
    throw std::runtime_error(figure.string() + ": a figure's name must be a file name");
  try {
    io::CreateFolder(dir);  // `dir` may be the report's temporary folder
  } catch (const std::exception& e) {
    throw std::runtime_error(figure.string() + ": " + e.what());
  }
  const fs::path tmp = io::TemporaryPathFor(dir / (name + ".figure"));  // an interrupt removes it
  const auto cleanup = [&tmp] {
    std::error_code ec;
    fs::remove_all(tmp, ec);
    io::UntrackTemporary(tmp);
  };
  const std::vector<std::string> files = {name + ".png", name + ".svg", name + ".csv",
                                          name + ".gp"};
  try {
    io::CreateFolder(tmp);
    {
      std::ofstream(tmp / files[2], std::ios::binary) << csv;
      std::ofstream(tmp / files[3], std::ios::binary) << script;
    }
    if (!NonEmptyFile(tmp / files[2]) || !NonEmptyFile(tmp / files[3]))
      throw std::runtime_error("cannot write its data and script in " + dir.string());
    const std::string err_path = (fs::absolute(tmp) / (name + ".err")).string();
    const auto [rc, missing] = RunGnuplot(fs::absolute(tmp), files[3], err_path);
    const std::string err = ReadText(err_path);
    if (rc != 0 || !NonEmptyFile(tmp / files[0]) || !NonEmptyFile(tmp / files[1]))
      throw std::runtime_error(
          std::string("gnuplot failed") +
          (missing ? " (not installed? tools/install-deps installs gnuplot-nox)" : "") +
          (err.empty() ? "" : ": " + err));
    std::vector<fs::path> written;
    for (const std::string& f : files) {
      io::CommitTemporary(tmp / f, dir / f);
      written.push_back(dir / f);
    }
    cleanup();
    return written;
  } catch (const std::exception& e) {
    cleanup();
    throw std::runtime_error(figure.string() + ": " + e.what());
  }
}

}  // namespace

Ticks ChooseTicks(const std::vector<double>& values, double padding_fraction) {
  Ticks t;
  double lo = INFINITY, hi = -INFINITY;
  for (double v : values)
    if (std::isfinite(v)) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  if (!(lo <= hi)) return t;
  t.valid = true;
  const double size = std::max(std::abs(lo), std::abs(hi));
  double span = hi - lo;
  if (span <= 1e-9 * size || span == 0.0) {
    const double centre = 0.5 * (lo + hi);
    const double half = centre != 0.0 ? 0.05 * std::abs(centre) : 1.0;
    t.fixed_range = true;
    t.low = centre - half;
    t.high = centre + half;
    lo = t.low;
    hi = t.high;
    span = hi - lo;
  } else {
    lo -= padding_fraction * span;
    hi += padding_fraction * span;
    span = hi - lo;
  }
  // The smallest step of 1, 2 or 5 times a power of ten that gives at most 8 intervals.
  const double raw = span / 8.0;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  const double m = raw / power;
  t.step = power * (m <= 1.0 + 1e-9 ? 1.0 : m <= 2.0 + 1e-9 ? 2.0 : m <= 5.0 + 1e-9 ? 5.0 : 10.0);
  const int step_exponent = static_cast<int>(std::floor(std::log10(t.step) + 1e-9));
  const double largest = std::max(std::abs(lo), std::abs(hi));
  const int decimals = std::max(0, -step_exponent);
  if (decimals <= 6 && largest < 1e6) {
    t.format = "%." + std::to_string(decimals) + "f";
  } else {
    // Scientific: the mantissa keeps the digits down to the step's for the largest label;
    // smaller labels have a smaller exponent, so they keep at least as many.
    const int largest_exponent = static_cast<int>(std::floor(std::log10(largest)));
    t.format = "%." + std::to_string(std::max(0, largest_exponent - step_exponent)) + "e";
  }
  return t;
}

std::string FigureCsv(const Plot& plot) { return Csv(Layout({&plot}, false)); }

std::string FigureCsv(const MultiPlot& figure) { return Csv(Layout(PanelsOf(figure), true)); }

std::string FigureScript(const Plot& plot, const std::string& name) {
  return Script(Layout({&plot}, false), name, plot.width_px, plot.height_px, "", false);
}

std::string FigureScript(const MultiPlot& figure, const std::string& name) {
  return Script(Layout(PanelsOf(figure), true), name, figure.width_px, figure.height_px,
                MultiplotLine(figure), true);
}

std::vector<fs::path> WriteFigure(const Plot& plot, const fs::path& dir, const std::string& name) {
  if (plot.series.empty())
    throw std::runtime_error((dir / name).string() + ": a figure needs at least one data series");
  return Commit(dir, name, FigureCsv(plot), FigureScript(plot, name));
}

std::vector<fs::path> WriteFigure(const MultiPlot& figure, const fs::path& dir,
                                  const std::string& name) {
  if (figure.panels.empty())
    throw std::runtime_error((dir / name).string() + ": a figure needs a panel");
  for (const Plot& p : figure.panels)
    if (p.series.empty())
      throw std::runtime_error((dir / name).string() + ": panel \"" + p.title +
                               "\" needs at least one data series");
  return Commit(dir, name, FigureCsv(figure), FigureScript(figure, name));
}

bool IsFigureTemporary(const std::string& name) {
  return name.find(".figure.tmp-") != std::string::npos ||
         name.find(".png.tmp-") != std::string::npos || name.find(".svg.tmp-") != std::string::npos;
}

}  // namespace hoof::report
