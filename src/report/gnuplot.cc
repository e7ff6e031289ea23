#include "report/gnuplot.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "io/atomic_file.h"
#include "io/csv.h"

namespace hoof::report {
namespace {

std::string Quote(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string Number(double v) { return std::isfinite(v) ? io::CsvNumber(v) : "NaN"; }

}  // namespace

std::string GnuplotScript(const Plot& plot, const std::filesystem::path& output) {
  std::ostringstream os;
  const std::string ext = output.extension().string();
  if (ext == ".svg")
    os << "set terminal svg size " << plot.width_px << "," << plot.height_px
       << " dynamic enhanced font 'Sans,12' background '#ffffff'\n";
  else
    os << "set terminal pngcairo size " << plot.width_px << "," << plot.height_px
       << " enhanced font 'Sans,11'\n";
  os << "set output " << Quote(output.string()) << "\n";
  os << "set title " << Quote(plot.title) << " noenhanced\n";
  os << "set xlabel " << Quote(plot.x_label) << "\nset ylabel " << Quote(plot.y_label) << "\n";
  os << "set grid\nset key inside bottom left box opaque noenhanced\nset datafile missing 'NaN'\n";
  int obj = 1;
  for (const auto& [a, b] : plot.shaded_x_ranges)
    os << "set object " << obj++ << " rect from " << Number(a) << ", graph 0 to " << Number(b)
       << ", graph 1 fc rgb '#dde8f5' fs solid 0.6 noborder behind\n";
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    const Series& s = plot.series[i];
    os << "$d" << i << " << EOD\n";
    for (std::size_t k = 0; k < s.x.size() && k < s.y.size(); ++k) {
      os << Number(s.x[k]) << " " << Number(s.y[k]);
      if (!s.y_error.empty()) os << " " << Number(k < s.y_error.size() ? s.y_error[k] : 0.0);
      os << "\n";
    }
    os << "EOD\n";
  }
  os << "plot ";
  bool first = true;
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    const Series& s = plot.series[i];
    os << (first ? "" : ", ") << "$d" << i << " using 1:2" << (s.y_error.empty() ? "" : ":3")
       << " with " << (s.y_error.empty() ? s.style : "yerrorbars") << " title " << Quote(s.title);
    first = false;
  }
  for (double y : plot.horizontal_lines) {
    os << (first ? "" : ", ") << Number(y) << " with lines dt 2 lc rgb '#888888' "
       << (y == plot.horizontal_lines.front() ? "title " + Quote(plot.horizontal_lines_title)
                                               : std::string("notitle"));
    first = false;
  }
  os << "\nset output\n";
  return os.str();
}

void RenderPlot(const Plot& plot, const std::filesystem::path& output) {
  if (plot.series.empty())
    throw std::runtime_error(output.string() + ": a figure needs at least one data series");
  const auto tmp_out = io::TemporaryPathFor(output).string() + output.extension().string();
  const auto script = io::TemporaryPathFor(output).string() + ".gp";
  if (output.has_parent_path()) std::filesystem::create_directories(output.parent_path());
  io::WriteTextAtomically(script, GnuplotScript(plot, tmp_out));
  const std::string cmd = "gnuplot " + Quote(script) + " 2>" + Quote(script + ".err");
  const int rc = std::system(cmd.c_str());
  std::string err;
  {
    std::ifstream in(script + ".err");
    std::stringstream ss;
    ss << in.rdbuf();
    err = ss.str();
  }
  std::error_code ec;
  std::filesystem::remove(script, ec);
  std::filesystem::remove(script + ".err", ec);
  if (rc != 0 || !std::filesystem::exists(tmp_out) || std::filesystem::file_size(tmp_out) == 0) {
    std::filesystem::remove(tmp_out, ec);
    throw std::runtime_error(output.string() + ": gnuplot failed" +
                             (rc == 127 * 256 ? " (not installed? tools/install-deps installs "
                                                "gnuplot-nox)"
                                              : "") +
                             (err.empty() ? "" : ": " + err));
  }
  io::CommitTemporary(tmp_out, output);
}

}  // namespace hoof::report
