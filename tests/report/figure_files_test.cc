// Tests of a figure's shipped files (report/gnuplot.h): tick steps and label formats chosen from
// the data's range against hand-worked expectations, tick labels read back from the SVG (a tiny
// range once printed "2.67766" three times), the CSV's header and rows written out by hand,
// `gnuplot NAME.gp` remaking the images from NAME.csv in another folder, and the error bars of
// the velocity figures (the paper's Figures 6 and 7) taken from the trials' standard errors.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "compare/trial_comparison.h"
#include "report/comparison_figures.h"
#include "report/gnuplot.h"
#include "support/test_util.h"

namespace hoof::report {
namespace {

namespace fs = std::filesystem;
using hoof::testing::FreshDir;
using hoof::testing::ReadAll;

Series Points(std::string title, std::vector<double> x, std::vector<double> y) {
  Series s;
  s.title = std::move(title);
  s.x = std::move(x);
  s.y = std::move(y);
  s.style = "points";
  return s;
}

/// The numeric tick labels of an SVG that gnuplot wrote, by axis: the y axis' are right-aligned
/// (text-anchor end), the x axis' centred. Text that is not a number (titles, key) is skipped.
struct TickLabels {
  std::vector<std::string> x, y;
};
TickLabels ReadTickLabels(const std::string& svg) {
  TickLabels out;
  static const std::regex label(
      R"re(text-anchor="(\w+)">\s*<text><tspan[^>]*>([^<]*)</tspan></text>)re");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), label); it != std::sregex_iterator();
       ++it) {
    const std::string text = (*it)[2].str();
    std::size_t used = 0;
    try {
      std::stod(text, &used);
    } catch (const std::exception&) {
      continue;
    }
    if (used != text.size()) continue;
    ((*it)[1].str() == "end" ? out.y : out.x).push_back(text);
  }
  return out;
}

/// Labels all different, at least 3, and evenly spaced by `step`.
void ExpectDistinctEvenTicks(const std::vector<std::string>& labels, double step) {
  ASSERT_GE(labels.size(), 3u);
  EXPECT_EQ(std::set<std::string>(labels.begin(), labels.end()).size(), labels.size());
  for (std::size_t i = 1; i < labels.size(); ++i)
    EXPECT_NEAR(std::stod(labels[i]) - std::stod(labels[i - 1]), step, 1e-9 * step)
        << labels[i - 1] << " " << labels[i];
}

// ---- Tick steps and formats -----------------------------------------------------------------

TEST(ChooseTicksTest, StepAndDecimalsFollowTheRange) {
  // 2.6776 .. 2.6778 padded by 6 % each side: 2.24e-4 / 8 = 2.8e-5 -> step 5e-5, 5 decimals.
  Ticks t = ChooseTicks({2.6776, 2.6777, 2.6778}, 0.06);
  ASSERT_TRUE(t.valid);
  EXPECT_DOUBLE_EQ(t.step, 5e-5);
  EXPECT_EQ(t.format, "%.5f");
  EXPECT_FALSE(t.fixed_range);
  // The user's case: 2.677660 .. 2.677664 -> 4.48e-6 / 8 = 5.6e-7 -> step 1e-6, 6 decimals.
  t = ChooseTicks({2.677660, 2.677664}, 0.06);
  EXPECT_DOUBLE_EQ(t.step, 1e-6);
  EXPECT_EQ(t.format, "%.6f");
  // 0 .. 100 padded by 4 %: 108 / 8 = 13.5 -> step 20, no decimals.
  t = ChooseTicks({0, 100}, 0.04);
  EXPECT_DOUBLE_EQ(t.step, 20.0);
  EXPECT_EQ(t.format, "%.0f");
  // 0.5 .. 0.9 unpadded: 0.05 -> step 0.05, 2 decimals.
  t = ChooseTicks({0.9, 0.5, NAN}, 0.0);
  EXPECT_DOUBLE_EQ(t.step, 0.05);
  EXPECT_EQ(t.format, "%.2f");
  // Every value the same: the range is set, 5 +- 0.25 -> 0.5 / 8 = 0.0625 -> step 0.1.
  t = ChooseTicks({5, 5}, 0.06);
  EXPECT_TRUE(t.fixed_range);
  EXPECT_DOUBLE_EQ(t.low, 4.75);
  EXPECT_DOUBLE_EQ(t.high, 5.25);
  EXPECT_DOUBLE_EQ(t.step, 0.1);
  EXPECT_EQ(t.format, "%.1f");
  // All zero: -1 .. 1 -> 0.25 -> step 0.5.
  t = ChooseTicks({0, 0}, 0.06);
  EXPECT_TRUE(t.fixed_range);
  EXPECT_DOUBLE_EQ(t.low, -1.0);
  EXPECT_DOUBLE_EQ(t.step, 0.5);
  // Large and tiny values in scientific notation, with the digits down to the step's:
  // 1e7 .. 2e7 -> 1.25e6 -> step 2e6, labels "1.2e+07": one decimal of the mantissa.
  t = ChooseTicks({1e7, 2e7}, 0.0);
  EXPECT_DOUBLE_EQ(t.step, 2e6);
  EXPECT_EQ(t.format, "%.1e");
  // 1e-9 .. 2e-9 -> step 2e-10 (10 decimals in fixed notation: too many) -> "%.1e".
  t = ChooseTicks({1e-9, 2e-9}, 0.0);
  EXPECT_DOUBLE_EQ(t.step, 2e-10);
  EXPECT_EQ(t.format, "%.1e");
  // Nothing finite: gnuplot chooses.
  EXPECT_FALSE(ChooseTicks({NAN, INFINITY}, 0.06).valid);
  EXPECT_FALSE(ChooseTicks({}, 0.06).valid);
}

// The velocity figure printed four y-ticks, three of them "2.67766": the labels read back from
// the SVG now all differ, on both axes, and step evenly.
TEST(FigureFilesTest, TicksOfATinyRangeAreAllDistinct) {
  const fs::path dir = FreshDir("figure_files/ticks");
  for (const auto& [name, lo, hi] :
       {std::tuple<const char*, double, double>{"a", 2.6776, 2.6778}, {"b", 2.677660, 2.677664}}) {
    Plot p;
    p.title = "tiny range";
    p.x_label = "impact speed (m/s)";
    p.y_label = "normal velocity of C after (m/s)";
    p.series.push_back(
        Points("steel", {3.0000, 3.0001, 3.0002, 3.0003}, {lo, lo + (hi - lo) / 3, hi, hi}));
    WriteFigure(p, dir, name);
    const TickLabels labels = ReadTickLabels(ReadAll(dir / (std::string(name) + ".svg")));
    SCOPED_TRACE(name);
    ExpectDistinctEvenTicks(labels.y, ChooseTicks({lo, hi}, 0.06).step);
    ExpectDistinctEvenTicks(labels.x, ChooseTicks({3.0, 3.0003}, 0.04).step);
  }
}

// ---- The shipped files ----------------------------------------------------------------------

TEST(FigureFilesTest, CsvNamesEachColumnWithItsUnit) {
  Plot p;
  p.x_label = "position x_{S} of C (mm)";
  p.y_label = "coefficient of restitution e";
  Series a = Points("steel", {1, 2, 3}, {0.5, 0.25, NAN});
  a.y_error = {0.01, NAN, 0.03};
  a.x_error = {0.1, 0.2, 0.3};
  a.extra_columns = {{"trials in the cell (1)", {3, 1, 2}}};
  p.series = {a, Points("a, \"b\"", {4}, {0.125})};
  EXPECT_EQ(FigureCsv(p),
            "steel: position x_S of C (mm),steel: coefficient of restitution e (1),"
            "steel: s.e. of coefficient of restitution e (1),"
            "steel: s.e. of position x_S of C (mm),steel: trials in the cell (1),"
            "\"a, \"\"b\"\": position x_S of C (mm)\","
            "\"a, \"\"b\"\": coefficient of restitution e (1)\"\n"
            "1,0.5,0.01,0.1,3,4,0.125\n"
            "2,0.25,nan,0.2,1,,\n"
            "3,nan,0.03,0.3,2,,\n");
  // Panels of one image prefix their title.
  MultiPlot m;
  Plot b;
  b.title = "(b) angle";
  b.x_label = "time t (ms)";
  b.y_label = "angle θ (°)";
  b.series = {Points("", {1}, {2})};
  m.panels = {b};
  EXPECT_EQ(FigureCsv(m),
            "(b) angle: series 1: time t (ms),(b) angle: series 1: angle θ (°)\n1,2\n");
}

TEST(FigureFilesTest, ScriptReadsTheCsvAndWritesBothImagesByRelativeNames) {
  Plot p;
  p.y_label = "y";
  p.series = {Points("s", {0, 10}, {0.8, 0.9})};
  p.series[0].y_error = {0.04, NAN};
  p.series[0].style = "linespoints";
  const std::string script = FigureScript(p, "e_by_angle");
  for (const char* want :
       {"data = 'e_by_angle.csv'\n", "set datafile separator comma\n",
        "set terminal svg size 900,500", "set terminal pngcairo size 900,500",
        "set output 'e_by_angle.'.out\n", "do for [out in \"svg png\"]",
        // The points from columns 1:2 (a row without an error bar included); the bars from 1:2:3.
        "data skip 1 using 1:2 with linespoints", "data skip 1 using 1:2:3 with yerrorbars",
        "#   3: s: s.e. of y (1)\n"})
    EXPECT_NE(script.find(want), std::string::npos) << want << "\n" << script;
}

TEST(FigureFilesTest, FourFilesAndNothingTemporary) {
  const fs::path dir = FreshDir("figure_files/four");
  Plot p;
  p.series = {Points("s", {0, 1}, {0, 1})};
  const auto written = WriteFigure(p, dir, "plot");
  EXPECT_EQ(written, (std::vector<fs::path>{dir / "plot.png", dir / "plot.svg", dir / "plot.csv",
                                            dir / "plot.gp"}));
  int entries = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    ++entries;
    EXPECT_TRUE(e.is_regular_file()) << e.path();
  }
  EXPECT_EQ(entries, 4);
  const cv::Mat png = cv::imread((dir / "plot.png").string());
  EXPECT_EQ(png.cols, 900);
  EXPECT_EQ(png.rows, 500);
  EXPECT_TRUE(IsFigureTemporary("plot.figure.tmp-123-4"));
  EXPECT_FALSE(IsFigureTemporary("plot.svg"));
}

/// The coordinates of everything the SVG draws: its paths (lines, axes, bars) and where its
/// points are placed (`<use ... transform='translate(x,y) ...'>`).
std::vector<std::string> DrawnCoordinates(const std::string& svg) {
  static const std::regex path(R"re((?:d|transform)='([^']*)')re");
  std::vector<std::string> out;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), path); it != std::sregex_iterator();
       ++it)
    out.push_back((*it)[1].str());
  return out;
}

void RunGnuplotIn(const fs::path& dir, const std::string& script) {
  const std::string command = "cd '" + dir.string() + "' && gnuplot " + script + " 2>gnuplot.err";
  ASSERT_EQ(std::system(command.c_str()), 0) << ReadAll(dir / "gnuplot.err");
}

/// Copies a figure's .gp and .csv into a fresh folder, remakes it there with gnuplot, and
/// expects the same SVG; then changes one value of the CSV and expects a different drawing.
void ExpectRemade(const fs::path& shipped, const std::string& name, const std::string& from,
                  const std::string& to) {
  const fs::path again = FreshDir("figure_files/remade_" + name);
  fs::copy_file(shipped / (name + ".gp"), again / (name + ".gp"));
  fs::copy_file(shipped / (name + ".csv"), again / (name + ".csv"));
  RunGnuplotIn(again, name + ".gp");
  ASSERT_TRUE(fs::is_regular_file(again / (name + ".png")));
  const std::string svg = ReadAll(shipped / (name + ".svg"));
  EXPECT_EQ(ReadAll(again / (name + ".svg")), svg);
  EXPECT_EQ(ReadAll(again / (name + ".png")), ReadAll(shipped / (name + ".png")));
  // The script reads the CSV: one value changed moves a point.
  std::string csv = ReadAll(again / (name + ".csv"));
  const std::size_t at = csv.find(from);
  ASSERT_NE(at, std::string::npos) << csv;
  csv.replace(at, from.size(), to);
  std::ofstream(again / (name + ".csv"), std::ios::trunc) << csv;
  RunGnuplotIn(again, name + ".gp");
  EXPECT_NE(DrawnCoordinates(ReadAll(again / (name + ".svg"))), DrawnCoordinates(svg));
}

TEST(FigureFilesTest, GnuplotRemakesAFigureFromItsShippedScriptAndData) {
  const fs::path dir = FreshDir("figure_files/shipped");
  Plot p;
  p.title = "e by angle\nmean ± 1 s.e.";
  p.x_label = "impact angle φ (°)";
  p.y_label = "coefficient of restitution e";
  Series s = Points("steel", {0, 10, 20}, {0.81, 0.76, 0.72});
  s.y_error = {0.01, NAN, 0.02};
  s.x_error = {0.5, 0.5, 0.5};
  p.series = {s, Points("asphalt", {0, 10}, {0.55, 0.52})};
  p.horizontal_lines = {0.6};
  p.vertical_lines = {{5.0, "t*"}};
  p.shaded_x_ranges = {{12, 14}};
  WriteFigure(p, dir, "e_by_angle");
  ExpectRemade(dir, "e_by_angle", "0.76", "0.66");
  // Panels of one image, too.
  MultiPlot m;
  m.title = "two panels";
  m.rows = 2;
  Plot a, b;
  a.series = {Points("x", {1, 2, 3}, {4, 5, 6})};
  b.series = {Points("y", {1, 2}, {7.25, 8})};
  m.panels = {a, b};
  WriteFigure(m, dir, "panels");
  ExpectRemade(dir, "panels", "7.25", "7.75");
}

// The bars are drawn, not only written to the CSV: gnuplot draws them as line segments in the
// series' colour (points are placed symbols, axes and grid are black and grey), a vertical and
// a horizontal bar with their end caps per point.
std::size_t ColouredSegments(const std::string& svg) {
  static const std::regex coloured(R"re(<path stroke='rgb\([^']*\)'\s+d='([^']*)')re");
  std::size_t n = 0;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), coloured);
       it != std::sregex_iterator(); ++it) {
    const std::string d = (*it)[1].str();
    n += static_cast<std::size_t>(std::count(d.begin(), d.end(), 'M'));
  }
  return n;
}

TEST(FigureFilesTest, ErrorBarsAreDrawn) {
  const fs::path dir = FreshDir("figure_files/bars");
  Plot p;
  p.series = {Points("s", {1, 2, 3}, {1, 2, 1.5})};
  WriteFigure(p, dir, "plain");
  EXPECT_EQ(ColouredSegments(ReadAll(dir / "plain.svg")), 0u);
  p.series[0].y_error = {0.1, 0.2, 0.1};
  p.series[0].x_error = {0.05, 0.05, 0.05};
  WriteFigure(p, dir, "bars");
  EXPECT_EQ(ColouredSegments(ReadAll(dir / "bars.svg")), 3u * 6u);
  // A bar whose error is undefined is left out; the point's other bar and the other points'
  // bars stay (a vertical bar and its caps are 3 segments, a horizontal one 3).
  p.series[0].y_error = {0.1, NAN, 0.1};
  WriteFigure(p, dir, "no_middle_y_bar");
  EXPECT_EQ(ColouredSegments(ReadAll(dir / "no_middle_y_bar.svg")), 2u * 3u + 3u * 3u);
  p.series[0].x_error.clear();
  WriteFigure(p, dir, "two_bars");
  EXPECT_EQ(ColouredSegments(ReadAll(dir / "two_bars.svg")), 2u * 3u);
}

// ---- Figures 6 and 7: error bars from the standard errors -----------------------------------

studyfile::TrialResult Trial(const std::string& id, const std::string& surface, double angle_deg,
                             double v_before_y, double se_before_y, Eigen::Vector2d se_after) {
  studyfile::TrialResult t;
  t.id = id;
  t.surface = surface;
  t.surface_angle_deg = angle_deg;
  t.success = true;
  t.v_SC_before_m_s = {0.5, v_before_y};
  t.v_SC_before_se_m_s = {0.001, se_before_y};
  t.v_SC_after_se_m_s = se_after;
  return t;
}

compare::TrialComparison Compared(Eigen::Vector2d meas, Eigen::Vector2d sim, Eigen::Vector2d se) {
  compare::TrialComparison c;
  c.success = true;
  c.v_SC_after_meas = meas;
  c.v_SC_after_sim = sim;
  c.v_SC_after_sim_se = se;
  return c;
}

TEST(VelocityPlotsTest, EveryPointCarriesItsStandardErrors) {
  studyfile::StudyResults study;
  study.trials = {Trial("n1", "steel", 0, -2.5, 0.004, {0.002, 0.003}),
                  Trial("o1", "steel", 20, -2.0, 0.005, {0.006, 0.007}),
                  Trial("n2", "asphalt", 0, -3.0, 0.008, {0.009, 0.011})};
  ComparedById row;
  row["n1"] = Compared({0.01, 1.9}, {0.02, 1.95}, {0.012, 0.013});
  row["o1"] = Compared({0.4, 1.5}, {0.45, 1.55}, {0.014, 0.015});
  row["n2"] = Compared({0.0, 1.2}, {0.0, 1.25}, {0.016, 0.017});
  const VelocityPlots plots = MakeVelocityPlots(study, row);
  // Normal impacts: per surface, measured then simulated, against |v_C,y| before.
  ASSERT_EQ(plots.normal.series.size(), 4u);
  const Series& steel_measured = plots.normal.series[0];
  EXPECT_EQ(steel_measured.title, "steel measured");
  EXPECT_EQ(steel_measured.x, std::vector<double>{2.5});
  EXPECT_EQ(steel_measured.x_error, std::vector<double>{0.004});
  EXPECT_EQ(steel_measured.y, std::vector<double>{1.9});
  EXPECT_EQ(steel_measured.y_error, std::vector<double>{0.003});
  const Series& steel_simulated = plots.normal.series[1];
  EXPECT_EQ(steel_simulated.title, "steel simulated");
  EXPECT_EQ(steel_simulated.y, std::vector<double>{1.95});
  EXPECT_EQ(steel_simulated.y_error, std::vector<double>{0.013});
  EXPECT_EQ(plots.normal.series[3].y_error, std::vector<double>{0.017});  // asphalt simulated
  EXPECT_NE(plots.normal.title.find("±1 s.e."), std::string::npos);
  // Oblique: simulated on x, measured on y, both components; then the line of equality.
  ASSERT_EQ(plots.oblique.series.size(), 3u);
  const Series& along = plots.oblique.series[0];
  EXPECT_EQ(along.title, "steel along the surface");
  EXPECT_EQ(along.x, std::vector<double>{0.45});
  EXPECT_EQ(along.x_error, std::vector<double>{0.014});
  EXPECT_EQ(along.y, std::vector<double>{0.4});
  EXPECT_EQ(along.y_error, std::vector<double>{0.006});
  const Series& normal = plots.oblique.series[1];
  EXPECT_EQ(normal.x_error, std::vector<double>{0.015});
  EXPECT_EQ(normal.y_error, std::vector<double>{0.007});
  EXPECT_TRUE(plots.oblique.series[2].y_error.empty());
  // The bars reach the shipped data and are drawn.
  const fs::path dir = FreshDir("figure_files/velocity");
  WriteFigure(plots.normal, dir, "velocity_normal");
  const std::string csv = ReadAll(dir / "velocity_normal.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "steel measured: normal impact speed of C before (m/s),"
            "steel measured: normal velocity of C after (m/s),"
            "steel measured: s.e. of normal velocity of C after (m/s),"
            "steel measured: s.e. of normal impact speed of C before (m/s),"
            "steel simulated: normal impact speed of C before (m/s),"
            "steel simulated: normal velocity of C after (m/s),"
            "steel simulated: s.e. of normal velocity of C after (m/s),"
            "steel simulated: s.e. of normal impact speed of C before (m/s),"
            "asphalt measured: normal impact speed of C before (m/s),"
            "asphalt measured: normal velocity of C after (m/s),"
            "asphalt measured: s.e. of normal velocity of C after (m/s),"
            "asphalt measured: s.e. of normal impact speed of C before (m/s),"
            "asphalt simulated: normal impact speed of C before (m/s),"
            "asphalt simulated: normal velocity of C after (m/s),"
            "asphalt simulated: s.e. of normal velocity of C after (m/s),"
            "asphalt simulated: s.e. of normal impact speed of C before (m/s)");
  EXPECT_NE(csv.find("\n2.5,1.9,0.003,0.004,"), std::string::npos) << csv;
  const std::string script = ReadAll(dir / "velocity_normal.gp");
  EXPECT_NE(script.find("using 1:2:3 with yerrorbars"), std::string::npos) << script;
  EXPECT_NE(script.find("using 1:2:4 with xerrorbars"), std::string::npos) << script;
}

}  // namespace
}  // namespace hoof::report
