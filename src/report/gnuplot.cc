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

void Terminal(std::ostream& os, const std::filesystem::path& output, int width_px, int height_px) {
  os << "set encoding utf8\n";  // labels carry units such as µs
  if (output.extension() == ".svg")
    os << "set terminal svg size " << width_px << "," << height_px
       << " dynamic enhanced font 'Sans,12' background '#ffffff'\n";
  else
    os << "set terminal pngcairo size " << width_px << "," << height_px
       << " enhanced font 'Sans,11'\n";
  os << "set output " << Quote(output.string()) << "\n";
}

/// Data blocks `$<prefix><i>`: "x y [error]" per row.
void DataBlocks(std::ostream& os, const Plot& plot, const std::string& prefix) {
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    const Series& s = plot.series[i];
    os << "$" << prefix << i << " << EOD\n";
    for (std::size_t k = 0; k < s.x.size() && k < s.y.size(); ++k) {
      os << Number(s.x[k]) << " " << Number(s.y[k]);
      if (!s.y_error.empty()) os << " " << Number(k < s.y_error.size() ? s.y_error[k] : NAN);
      os << "\n";
    }
    os << "EOD\n";
  }
}

/// Settings and the plot command of one plot; undoes its objects, arrows and labels after.
void PlotCommands(std::ostream& os, const Plot& plot, const std::string& prefix) {
  os << "set title " << Quote(plot.title) << " noenhanced\n";
  os << "set xlabel " << Quote(plot.x_label) << "\nset ylabel " << Quote(plot.y_label) << "\n";
  os << "set grid\nset key " << plot.key << " box opaque noenhanced\n"
     << "set datafile missing 'NaN'\nset autoscale fix\n"
     << "set offsets graph 0.04, graph 0.04, graph 0.06, graph 0.06\n";
  int obj = 1;
  for (const auto& [a, b] : plot.shaded_x_ranges)
    os << "set object " << obj++ << " rect from " << Number(a) << ", graph 0 to " << Number(b)
       << ", graph 1 fc rgb '#dde8f5' fs solid 0.6 noborder behind\n";
  int arrow = 1;
  for (const auto& [x, label] : plot.vertical_lines) {
    os << "set arrow " << arrow << " from " << Number(x) << ", graph 0 to " << Number(x)
       << ", graph 1 nohead dt 2 lw 1.5 lc rgb '#555555'\n";
    os << "set label " << arrow++ << " " << Quote(label) << " at " << Number(x)
       << ", graph 0.96 offset 0.5, 0 left noenhanced textcolor rgb '#555555'\n";
  }
  os << "plot ";
  bool first = true;
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    const Series& s = plot.series[i];
    const std::string data = "$" + prefix + std::to_string(i);
    const std::string look =
        " lt " + std::to_string(i + 1) + (s.options.empty() ? "" : " " + s.options);
    os << (first ? "" : ", ") << data << " using 1:2 with " << s.style << look << " title "
       << Quote(s.title);
    // Error bars as a second plot of the same data: rows whose error is NaN are skipped there
    // only, so their point is still drawn.
    if (!s.y_error.empty())
      os << ", " << data << " using 1:2:3 with yerrorbars" << look << " notitle";
    first = false;
  }
  for (double y : plot.horizontal_lines) {
    os << (first ? "" : ", ") << Number(y) << " with lines dt 2 lc rgb '#888888' "
       << (y == plot.horizontal_lines.front() ? "title " + Quote(plot.horizontal_lines_title)
                                              : std::string("notitle"));
    first = false;
  }
  os << "\nunset object\nunset arrow\nunset label\n";
}

/// Runs gnuplot on `script` without a shell (its only argument is the script's path), its error
/// output into the file `err_path`. Returns its exit code (-1 when it did not exit) and whether
/// gnuplot is missing.
std::pair<int, bool> RunGnuplot(const std::string& script, const std::string& err_path) {
  int rc = -1;
  bool missing = false;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err_path.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0600);
  std::string arg0 = "gnuplot", arg1 = script;
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

/// Runs gnuplot on the script that `make_script(temporary_output)` gives and commits the
/// output; see RenderPlot.
template <class MakeScript>
void Render(const std::filesystem::path& output, const MakeScript& make_script) {
  const auto tmp_out = io::TemporaryPathFor(output).string() + output.extension().string();
  const auto script = io::TemporaryPathFor(output).string() + ".gp";
  const std::string err_path = script + ".err";
  for (const auto& t : {tmp_out, script, err_path})
    io::TrackTemporary(t);  // an interrupt removes them
  std::error_code ec;
  if (output.has_parent_path()) {
    const io::CreatingTemporary creating;  // the folder may be a temporary (the report's figures)
    std::filesystem::create_directories(output.parent_path(), ec);
  }
  if (ec) throw std::runtime_error(output.string() + ": cannot create its folder: " + ec.message());
  try {
    io::WriteTextAtomically(script, make_script(tmp_out));
  } catch (const std::exception& e) {
    throw std::runtime_error(output.string() + ": cannot write the gnuplot script: " + e.what());
  }
  const auto [rc, missing] = RunGnuplot(script, err_path);
  std::string err;
  {
    std::ifstream in(err_path);
    std::stringstream ss;
    ss << in.rdbuf();
    err = ss.str();
  }
  std::filesystem::remove(script, ec);
  std::filesystem::remove(err_path, ec);
  io::UntrackTemporary(script);
  io::UntrackTemporary(err_path);
  if (rc != 0 || !std::filesystem::exists(tmp_out) || std::filesystem::file_size(tmp_out) == 0) {
    std::filesystem::remove(tmp_out, ec);
    io::UntrackTemporary(tmp_out);
    throw std::runtime_error(
        output.string() + ": gnuplot failed" +
        (missing ? " (not installed? tools/install-deps installs gnuplot-nox)" : "") +
        (err.empty() ? "" : ": " + err));
  }
  io::CommitTemporary(tmp_out, output);
}

}  // namespace

std::string GnuplotScript(const Plot& plot, const std::filesystem::path& output) {
  std::ostringstream os;
  Terminal(os, output, plot.width_px, plot.height_px);
  DataBlocks(os, plot, "d");
  PlotCommands(os, plot, "d");
  os << "set output\n";
  return os.str();
}

std::string GnuplotScript(const MultiPlot& figure, const std::filesystem::path& output) {
  std::ostringstream os;
  Terminal(os, output, figure.width_px, figure.height_px);
  const std::size_t rows = static_cast<std::size_t>(std::max(figure.rows, 1));
  const std::size_t cols = (figure.panels.size() + rows - 1) / rows;
  const auto prefix = [](std::size_t p) {  // a stream, not "p" + ...: GCC 12 -Wrestrict
    std::ostringstream s;
    s << "p" << p << "d";
    return s.str();
  };
  for (std::size_t p = 0; p < figure.panels.size(); ++p)
    DataBlocks(os, figure.panels[p], prefix(p));
  os << "set multiplot layout " << rows << "," << cols << " title " << Quote(figure.title)
     << " noenhanced font ',13'\n";
  for (std::size_t p = 0; p < figure.panels.size(); ++p)
    PlotCommands(os, figure.panels[p], prefix(p));
  os << "unset multiplot\nset output\n";
  return os.str();
}

void RenderPlot(const Plot& plot, const std::filesystem::path& output) {
  if (plot.series.empty())
    throw std::runtime_error(output.string() + ": a figure needs at least one data series");
  Render(output, [&](const std::string& tmp) { return GnuplotScript(plot, tmp); });
}

void RenderPlot(const MultiPlot& figure, const std::filesystem::path& output) {
  if (figure.panels.empty()) throw std::runtime_error(output.string() + ": a figure needs a panel");
  for (const Plot& p : figure.panels)
    if (p.series.empty())
      throw std::runtime_error(output.string() + ": panel \"" + p.title +
                               "\" needs at least one data series");
  Render(output, [&](const std::string& tmp) { return GnuplotScript(figure, tmp); });
}

bool IsFigureTemporary(const std::string& name) {
  return name.find(".png.tmp-") != std::string::npos || name.find(".svg.tmp-") != std::string::npos;
}

}  // namespace hoof::report
