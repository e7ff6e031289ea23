// Tests of the figures: the cell statistics behind Figures 4 and 5 against hand-computed
// means, standard deviations and standard errors, Figure 3's fitted curves against the flight
// formulas and the measured points of a constructed trial, and that every figure renders (PNG
// of the requested size with content, SVG with its title, its CSV and gnuplot script beside
// it, nothing temporary left, errors naming the figure). The shipped files themselves are
// tested in figure_files_test.cc.
#include "report/figures.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "report/gnuplot.h"
#include "support/test_util.h"

namespace hoof::report {
namespace {

namespace fs = std::filesystem;

using hoof::testing::ExpectErrorContaining;
using hoof::testing::FreshDir;
using hoof::testing::ReadAll;

/// A PNG of the given size that is not blank: curves and text put many grey levels in it.
void ExpectPng(const fs::path& path, int width, int height) {
  const cv::Mat png = cv::imread(path.string());
  ASSERT_FALSE(png.empty()) << path;
  EXPECT_EQ(png.cols, width) << path;
  EXPECT_EQ(png.rows, height) << path;
  cv::Scalar mean, sd;
  cv::meanStdDev(png, mean, sd);
  EXPECT_GT(sd[0], 10.0) << path;
}

int RegularFiles(const fs::path& dir) {
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
  return files;
}

pipeline::TrialAnalysis FlaggedTrial() {
  pipeline::TrialAnalysis t;
  t.spec.id = "concrete_20deg_tilted";
  for (int f = 0; f < 60; ++f)
    t.marker_distance_ratio.push_back(std::cos(0.002 * f * f * M_PI / 180));
  t.marker_distance_ratio[30] = NAN;  // a frame without both markers
  t.out_of_plane_change = 0.01;
  t.out_of_plane_noise = 5e-5;
  t.flags = {"out_of_plane"};
  return t;
}

TEST(FiguresTest, OutOfPlaneFigureIsWrittenAsPngAndSvg) {
  const fs::path dir = FreshDir("figures");
  const pipeline::TrialAnalysis t = FlaggedTrial();
  EXPECT_EQ(WriteOutOfPlaneFigure(t, 0.003, dir, "oop").size(), 4u);
  ExpectPng(dir / "oop.png", 900, 500);
  const std::string svg = ReadAll(dir / "oop.svg");
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  // hoof::format's 4 significant digits: change 1 % and noise 0.005 %.
  EXPECT_NE(svg.find("concrete_20deg_tilted: out-of-plane check FLAGGED (change 1.000 %, noise "
                     "0.005000 %)"),
            std::string::npos);
  // The frame without both markers is undefined in the data, not a number.
  EXPECT_NE(ReadAll(dir / "oop.csv").find("\n30,nan\n"), std::string::npos);
  EXPECT_EQ(RegularFiles(dir), 4);  // PNG, SVG, CSV, script; no temporary file left behind
}

TEST(FiguresTest, AFigureNeedsASeries) {
  const fs::path dir = FreshDir("figures_empty");
  ExpectErrorContaining([&] { WriteFigure(Plot{}, dir, "empty"); }, (dir / "empty").string());
  MultiPlot m;
  m.panels = {Plot{}};
  ExpectErrorContaining([&] { WriteFigure(m, dir, "empty"); }, "needs at least one data series");
  EXPECT_TRUE(fs::is_empty(dir));
}

// Text from a study (ids, surfaces, titles) reaches gnuplot as data, never as a command: neither
// gnuplot's backquotes nor a shell's $(...) run, and the text is drawn as written.
TEST(FiguresTest, TextFromTheStudyRunsNoCommand) {
  const fs::path dir = FreshDir("figures_injection");
  const std::string mark = (dir / "RAN").string();
  Plot p;
  p.title = "steel`touch " + mark + "1` and x$(touch " + mark + "2)\nit's \"quoted\" \\ @macro";
  p.x_label = "x`touch " + mark + "3`";
  p.y_label = "y'";
  p.vertical_lines = {{0.5, "t`touch " + mark + "4`"}};
  Series s;
  s.title = "id`touch " + mark + "5`'";
  s.x = {0, 1};
  s.y = {0, 1};
  p.series.push_back(s);
  // The output's own name may hold the same.
  const std::string name = "plot$(touch " + std::string("RAN6") + ")`touch RAN7`'";
  const fs::path out = dir / (name + ".svg");
  WriteFigure(p, dir, name);
  MultiPlot m;
  m.title = p.title;
  m.panels = {p};
  WriteFigure(m, dir, "multi");
  for (int i = 1; i <= 7; ++i) {
    EXPECT_FALSE(fs::exists(mark + std::to_string(i))) << i;
    EXPECT_FALSE(fs::exists(fs::path("RAN" + std::to_string(i)))) << i;
  }
  ASSERT_TRUE(fs::exists(out));
  const std::string svg = ReadAll(out);
  // Drawn as written (SVG escapes the quote marks and the ampersand-free text stays).
  EXPECT_NE(svg.find("and x$(touch"), std::string::npos);
  EXPECT_NE(svg.find("@macro"), std::string::npos);
}

TEST(FiguresTest, UndefinedErrorBarIsLeftOutNotTheMean) {
  Plot p;
  Series s;
  s.x = {0, 10};
  s.y = {0.8, 0.9};
  s.y_error = {0.04, NAN};  // the second mean is of a single trial without an s.e.
  p.series.push_back(s);
  EXPECT_NE(FigureCsv(p).find("\n0,0.8,0.04\n10,0.9,nan\n"), std::string::npos) << FigureCsv(p);
  // The means are drawn from columns 1:2 (the undefined row included); only the bars use
  // column 3.
  const std::string script = FigureScript(p, "x");
  EXPECT_NE(script.find("data skip 1 using 1:2 with linespoints"), std::string::npos) << script;
  EXPECT_NE(script.find("data skip 1 using 1:2:3 with yerrorbars"), std::string::npos) << script;
  EXPECT_NE(script.find("set datafile missing 'nan'"), std::string::npos) << script;
}

TEST(FiguresTest, FailingRenderNamesTheFigureAndLeavesNothing) {
  const fs::path dir = FreshDir("figures_fail");
  std::ofstream(dir / "not_a_folder") << "x";
  Plot p;
  Series s;
  s.x = {0, 1};
  s.y = {0, 1};
  p.series.push_back(s);
  ExpectErrorContaining([&] { WriteFigure(p, dir / "not_a_folder", "plot"); },
                        (dir / "not_a_folder" / "plot").string());
  // gnuplot itself failing (a style it does not know) also names the figure.
  p.series[0].style = "no_such_style";
  ExpectErrorContaining([&] { WriteFigure(p, dir, "bad"); }, (dir / "bad").string());
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()),
            1);  // only not_a_folder: no figure file, no temporary folder
}

// ---- Figures 4 and 5: cell statistics ----------------------------------------------------

studyfile::TrialResult Trial(const std::string& surface, double angle_deg, double speed_m_s,
                             double e, double mu_eff, bool success = true, double e_se = 0.0,
                             double mu_eff_se = 0.0) {
  studyfile::TrialResult t;
  t.id = surface + "_" + std::to_string(static_cast<int>(angle_deg)) + "deg";
  t.surface = surface;
  t.surface_angle_deg = angle_deg;
  t.nominal_speed_m_s = speed_m_s;
  t.e = e;
  t.mu_eff = mu_eff;
  t.e_se = e_se;
  t.mu_eff_se = mu_eff_se;
  t.success = success;
  return t;
}

/// A small study; the expected values below are computed by hand.
std::vector<studyfile::TrialResult> SmallTable() {
  return {
      Trial("steel", 0, 2, 0.80, 0.5),  // mu_eff of normal impacts must be left out
      Trial("steel", 0, 2, 0.84, 0.5),
      Trial("steel", 0, 3, 0.88, 0.5),
      Trial("steel", 20, 3, 0.90, 0.15, true, /*e_se=*/0.012, /*mu_eff_se=*/0.03),
      Trial("steel", 20, 3, 0.10, 0.90, /*success=*/false),  // failed: left out everywhere
      Trial("asphalt", 0, 2, 0.50, 0.5),
      Trial("asphalt", 0, 3, 0.60, 0.5),
      Trial("asphalt", 20, 2, 0.55, 0.20),
      Trial("asphalt", 20, 2, 0.57, 0.30),
      Trial("asphalt", 20, 3, 0.62, 0.25),
      Trial("asphalt", 20, 3, 0.58, 0.29),
  };
}

struct Expected {
  const char* surface;
  double level;
  std::size_t n;
  double mean, sd;  // sd NaN = undefined
  double se;        // s.e. of the mean: sd / sqrt(n), or a lone trial's own s.e. (NaN: none)
};

void ExpectCells(const std::vector<CellSummary>& got, const std::vector<Expected>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) {
    SCOPED_TRACE(std::string(want[i].surface) + " at " + std::to_string(want[i].level));
    EXPECT_EQ(got[i].surface, want[i].surface);
    EXPECT_EQ(got[i].level, want[i].level);
    EXPECT_EQ(got[i].n, want[i].n);
    EXPECT_NEAR(got[i].mean, want[i].mean, 1e-12);
    if (std::isnan(want[i].sd))
      EXPECT_TRUE(std::isnan(got[i].sd)) << got[i].sd;
    else
      EXPECT_NEAR(got[i].sd, want[i].sd, 1e-12);
    if (std::isnan(want[i].se))
      EXPECT_TRUE(std::isnan(got[i].se)) << got[i].se;
    else
      EXPECT_NEAR(got[i].se, want[i].se, 1e-12);
  }
}

TEST(StudySummaryTest, RestitutionByAngleMatchesHandComputedValues) {
  // steel 0: 0.80 0.84 0.88 -> mean 0.84, s.d. sqrt((0.0016 + 0 + 0.0016) / 2) = 0.04.
  // steel 20: 0.90 alone (the failed 0.10 is out) -> s.d. undefined, s.e. its own 0.012.
  // The s.e. of the others: s.d. / sqrt(n).
  // asphalt 0: 0.50 0.60 -> 0.55, sqrt(0.005). asphalt 20: 0.55 0.57 0.62 0.58 -> 0.58,
  // deviations -0.03 -0.01 0.04 0 -> sqrt(0.0026 / 3).
  ExpectCells(SummarizeByCell(SmallTable(), StudyQuantity::kRestitution, StudyFactor::kImpactAngle),
              {{"steel", 0, 3, 0.84, 0.04, 0.04 / std::sqrt(3.0)},
               {"steel", 20, 1, 0.90, NAN, 0.012},
               {"asphalt", 0, 2, 0.55, std::sqrt(0.005), std::sqrt(0.005 / 2)},
               {"asphalt", 20, 4, 0.58, std::sqrt(0.0026 / 3), std::sqrt(0.0026 / 3) / 2}});
}

TEST(StudySummaryTest, RestitutionBySpeedMatchesHandComputedValues) {
  // steel 2: 0.80 0.84 -> 0.82, sqrt(0.0008); steel 3: 0.88 0.90 -> 0.89, sqrt(0.0002);
  // asphalt 2: 0.50 0.55 0.57 -> 0.54, sqrt(0.0026 / 2); asphalt 3: 0.60 0.62 0.58 -> 0.60, 0.02.
  ExpectCells(SummarizeByCell(SmallTable(), StudyQuantity::kRestitution, StudyFactor::kSpeed),
              {{"steel", 2, 2, 0.82, std::sqrt(0.0008), 0.02},
               {"steel", 3, 2, 0.89, std::sqrt(0.0002), 0.01},
               {"asphalt", 2, 3, 0.54, std::sqrt(0.0013), std::sqrt(0.0013 / 3)},
               {"asphalt", 3, 3, 0.60, 0.02, 0.02 / std::sqrt(3.0)}});
}

TEST(StudySummaryTest, FrictionUsesObliqueSuccessfulTrialsOnly) {
  // steel 20: 0.15 alone; asphalt 20: 0.20 0.30 0.25 0.29 -> 0.26, deviations
  // -0.06 0.04 -0.01 0.03 -> sqrt(0.0062 / 3). By speed: asphalt 2: 0.20 0.30 -> 0.25,
  // sqrt(0.005); asphalt 3: 0.25 0.29 -> 0.27, sqrt(0.0008).
  ExpectCells(
      SummarizeByCell(SmallTable(), StudyQuantity::kEffectiveFriction, StudyFactor::kImpactAngle),
      {{"steel", 20, 1, 0.15, NAN, 0.03},
       {"asphalt", 20, 4, 0.26, std::sqrt(0.0062 / 3), std::sqrt(0.0062 / 3) / 2}});
  ExpectCells(SummarizeByCell(SmallTable(), StudyQuantity::kEffectiveFriction, StudyFactor::kSpeed),
              {{"steel", 3, 1, 0.15, NAN, 0.03},
               {"asphalt", 2, 2, 0.25, std::sqrt(0.005), 0.05},
               {"asphalt", 3, 2, 0.27, std::sqrt(0.0008), 0.02}});
}

TEST(StudySummaryTest, TrialsWithoutSpeedOrValueAreLeftOut) {
  std::vector<studyfile::TrialResult> t = {Trial("steel", 0, NAN, 0.8, NAN),
                                           Trial("steel", 10, 2, NAN, NAN)};
  EXPECT_TRUE(SummarizeByCell(t, StudyQuantity::kRestitution, StudyFactor::kSpeed).empty());
  ExpectCells(SummarizeByCell(t, StudyQuantity::kRestitution, StudyFactor::kImpactAngle),
              {{"steel", 0, 1, 0.8, NAN, NAN}});  // no s.e. of its own: no bar
  EXPECT_TRUE(
      SummarizeByCell(t, StudyQuantity::kEffectiveFriction, StudyFactor::kImpactAngle).empty());
}

TEST(StudyFiguresTest, AllFourStudyFiguresRender) {
  const fs::path dir = FreshDir("study_figures");
  studyfile::StudyResults study;
  study.name = "small-table";
  study.trials = SmallTable();
  const auto written = WriteStudyFigures(study, dir);
  ASSERT_EQ(written.size(), 16u);
  const std::pair<const char*, const char*> figures[] = {
      {"e_by_angle", "Coefficient of restitution by impact angle"},
      {"e_by_speed", "Coefficient of restitution by nominal speed"},
      {"mu_eff_by_angle", "Effective coefficient of friction (oblique impacts) by impact angle"},
      {"mu_eff_by_speed", "Effective coefficient of friction (oblique impacts) by nominal speed"}};
  for (const auto& [name, title] : figures) {
    ExpectPng(dir / (std::string(name) + ".png"), 900, 550);
    const std::string svg = ReadAll(dir / (std::string(name) + ".svg"));
    EXPECT_NE(svg.find(title), std::string::npos) << name;
    EXPECT_NE(svg.find("mean ± 1 s.e. of the mean (s.d./√n)"), std::string::npos) << name;
  }
  EXPECT_EQ(RegularFiles(dir), 16);
  // e by angle's data: per surface the nudged level, mean, s.e., then the level itself, n and
  // s.d. Steel at 0°: mean 0.84, s.e. 0.04 / sqrt(3), n 3, s.d. 0.04.
  const std::string csv = ReadAll(dir / "e_by_angle.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "steel: impact angle φ (°),steel: coefficient of restitution e (1),"
            "steel: s.e. of coefficient of restitution e (1),"
            "steel: impact angle φ (°) without the sideways nudge,"
            "steel: trials in the cell (1),steel: s.d. of the trials (1),"
            "asphalt: impact angle φ (°),asphalt: coefficient of restitution e (1),"
            "asphalt: s.e. of coefficient of restitution e (1),"
            "asphalt: impact angle φ (°) without the sideways nudge,"
            "asphalt: trials in the cell (1),asphalt: s.d. of the trials (1)");
  const std::size_t row = csv.find('\n') + 1;
  std::vector<double> first;
  std::stringstream cells(csv.substr(row, csv.find('\n', row) - row));
  for (std::string cell; std::getline(cells, cell, ',');) first.push_back(std::stod(cell));
  ASSERT_EQ(first.size(), 12u);
  EXPECT_NEAR(first[1], 0.84, 1e-12);
  EXPECT_NEAR(first[2], 0.04 / std::sqrt(3.0), 1e-12);
  EXPECT_EQ(first[3], 0.0);
  EXPECT_EQ(first[4], 3.0);
  EXPECT_NEAR(first[5], 0.04, 1e-12);
  // A study of normal impacts only has no friction figures.
  study.trials = {Trial("steel", 0, 2, 0.8, NAN), Trial("steel", 0, 2, 0.82, NAN)};
  EXPECT_EQ(WriteStudyFigures(study, FreshDir("study_figures_normal")).size(), 8u);
}

// ---- Figure 3 ------------------------------------------------------------------------------

constexpr double kFps = 8000.0;
constexpr double kPhi = 20.0 * std::numbers::pi / 180.0;
constexpr double kD = 0.0135;
constexpr double kG = 9.81;
const Eigen::Vector2d kImpactC_W(0.10, 0.20);

/// Free flight of C about the impact time t* = 20.5 frames: p* + v dt - g dt^2 / 2 y_W.
Eigen::Vector2d FlightC(const Eigen::Vector2d& v, double dt) {
  return kImpactC_W + v * dt + Eigen::Vector2d(0, -0.5 * kG * dt * dt);
}

/// A trial whose poses follow the before fit up to t* and the after fit from then on:
/// before v_WC = (0.4, -3.1) m/s, theta 90 deg, no spin; after v_WC = (0.6, 2.2) m/s,
/// w = 40 rad/s. Fit windows: frames 0-19 and 21-41 (42 frames in all).
pipeline::TrialAnalysis ConstructedTrial() {
  pipeline::TrialAnalysis t;
  t.spec.id = "steel_20deg_constructed";
  t.spec.surface = "steel";
  t.spec.surface_angle_deg = 20.0;
  t.spec.fps = kFps;
  t.spec.nominal_speed_m_s = 3.0;
  t.spec.specimen.d_EC_m = kD;
  auto& k = t.impact;
  k.success = true;
  k.e = 0.8;
  k.impact_time_s = 20.5 / kFps;
  k.before = {};
  k.before.first_frame = 0;
  k.before.last_frame = 19;
  k.before.p_WC = kImpactC_W;
  k.before.v_WC = {0.4, -3.1};
  k.before.theta_W_rad = std::numbers::pi / 2;
  k.before.w_rad_s = 0.0;
  k.after = k.before;
  k.after.first_frame = 21;
  k.after.last_frame = 41;
  k.after.v_WC = {0.6, 2.2};
  k.after.w_rad_s = 40.0;
  for (int f = 0; f < 42; ++f) {
    const double dt = f / kFps - k.impact_time_s;
    const auto& fit = dt < 0 ? k.before : k.after;
    const double theta = fit.theta_W_rad + fit.w_rad_s * dt;
    tracking::BodyPose p;
    p.valid = f != 7;  // one frame without a pose
    p.theta_W_rad = theta;
    p.p_WE = FlightC(fit.v_WC, dt) - kD * Eigen::Vector2d(std::cos(theta), std::sin(theta));
    t.poses.push_back(p);
  }
  return t;
}

TEST(DisplacementFigureTest, MeasuredPointsAreCentreOfMassInSurfaceFrame) {
  const DisplacementCurves c = ComputeDisplacementCurves(ConstructedTrial(), 42);
  ASSERT_TRUE(c.has_fit);
  EXPECT_NEAR(c.impact_time_ms, 20.5 / 8.0, 1e-12);
  ASSERT_EQ(c.measured.t_ms.size(), 41u);  // frame 7 has no pose
  // Frame 0 by hand: dt = -20.5 / 8000 s; r = C - C* in W; x_S = r.x cos phi - r.y sin phi,
  // y_S = r.x sin phi + r.y cos phi (mm); theta 90 deg.
  const double dt = -20.5 / kFps;
  const Eigen::Vector2d r = FlightC({0.4, -3.1}, dt) - kImpactC_W;
  EXPECT_NEAR(c.measured.t_ms[0], 0.0, 1e-12);
  EXPECT_NEAR(c.measured.x_S_mm[0], 1e3 * (r.x() * std::cos(kPhi) - r.y() * std::sin(kPhi)), 1e-9);
  EXPECT_NEAR(c.measured.y_S_mm[0], 1e3 * (r.x() * std::sin(kPhi) + r.y() * std::cos(kPhi)), 1e-9);
  EXPECT_NEAR(c.measured.theta_deg[0], 90.0, 1e-9);
  // Falling onto the surface: C is above it (y_S > 0) before the impact.
  EXPECT_GT(c.measured.y_S_mm[0], 5.0);
  EXPECT_EQ(c.measured.t_ms[7], 8.0 / 8.0);  // the 8th point is frame 8
}

TEST(DisplacementFigureTest, FittedCurvesPassThroughTheMeasuredPoints) {
  // 42 samples from frame 0 to t* = 20.5 frames (and from t* to frame 41) put a sample on
  // every frame time (half-frame steps).
  const DisplacementCurves c = ComputeDisplacementCurves(ConstructedTrial(), 42);
  ASSERT_EQ(c.fit_before.t_ms.size(), 42u);
  ASSERT_EQ(c.fit_after.t_ms.size(), 42u);
  EXPECT_NEAR(c.fit_before.t_ms.front(), 0.0, 1e-12);
  EXPECT_NEAR(c.fit_before.t_ms.back(), 20.5 / 8.0, 1e-12);
  EXPECT_NEAR(c.fit_after.t_ms.front(), 20.5 / 8.0, 1e-12);
  EXPECT_NEAR(c.fit_after.t_ms.back(), 41.0 / 8.0, 1e-12);
  // Both fits meet at the origin at t*: the displacement is measured from C at the impact.
  for (const auto* f : {&c.fit_before, &c.fit_after}) {
    EXPECT_NEAR(f->x_S_mm[f == &c.fit_before ? 41 : 0], 0.0, 1e-9);
    EXPECT_NEAR(f->y_S_mm[f == &c.fit_before ? 41 : 0], 0.0, 1e-9);
  }
  int checked = 0;
  for (std::size_t i = 0; i < c.measured.t_ms.size(); ++i) {
    const double frame = c.measured.t_ms[i] * 8.0;  // ms -> frames at 8000 fps
    const bool before = frame < 20.5;
    const DisplacementSamples& fit = before ? c.fit_before : c.fit_after;
    const auto j = static_cast<std::size_t>(std::lround(2.0 * (before ? frame : frame - 20.5)));
    SCOPED_TRACE("frame " + std::to_string(frame));
    ASSERT_LT(j, fit.t_ms.size());
    EXPECT_NEAR(fit.t_ms[j], c.measured.t_ms[i], 1e-12);
    EXPECT_NEAR(fit.x_S_mm[j], c.measured.x_S_mm[i], 1e-9);
    EXPECT_NEAR(fit.y_S_mm[j], c.measured.y_S_mm[i], 1e-9);
    EXPECT_NEAR(fit.theta_deg[j], c.measured.theta_deg[i], 1e-9);
    ++checked;
  }
  EXPECT_EQ(checked, 41);
  // After the impact the angle grows at w = 40 rad/s: at frame 41, 20.5 frames after t*.
  EXPECT_NEAR(c.fit_after.theta_deg.back(), 90.0 + 40.0 * 20.5 / kFps * 180 / std::numbers::pi,
              1e-9);
}

TEST(DisplacementFigureTest, WithoutFitOnlyTheMeasuredPoints) {
  pipeline::TrialAnalysis t = ConstructedTrial();
  t.impact.success = false;
  const DisplacementCurves c = ComputeDisplacementCurves(t);
  EXPECT_FALSE(c.has_fit);
  EXPECT_TRUE(c.fit_before.t_ms.empty());
  EXPECT_EQ(c.measured.t_ms.size(), 41u);
  EXPECT_NEAR(c.measured.x_S_mm[0], 0.0, 1e-12);  // from the first valid pose
  EXPECT_THROW(ComputeDisplacementCurves(t, 1), std::invalid_argument);
}

TEST(DisplacementFigureTest, RendersAsPngAndSvg) {
  const fs::path dir = FreshDir("displacement_figure");
  const pipeline::TrialAnalysis t = ConstructedTrial();
  WriteDisplacementFigure(t, dir, "d");
  ExpectPng(dir / "d.png", 900, 900);
  const std::string svg = ReadAll(dir / "d.svg");
  EXPECT_NE(svg.find("steel_20deg_constructed: steel, surface angle 20.0°"), std::string::npos);
  EXPECT_NE(svg.find("(a) displacement of the centre of mass C"), std::string::npos);
  EXPECT_NE(svg.find("angle θ of x"), std::string::npos);
  EXPECT_EQ(RegularFiles(dir), 4);
  // The panels' columns carry their units.
  const std::string csv = ReadAll(dir / "d.csv");
  EXPECT_EQ(csv.find("(a) displacement of the centre of mass C in the surface frame S: x_S (along "
                     "the surface): time t (ms),"),
            0u)
      << csv.substr(0, 200);
  EXPECT_NE(csv.find("(b) angle of the hoof wall: measured: angle θ of x_B from x_W (°)"),
            std::string::npos);
  pipeline::TrialAnalysis empty;
  empty.spec.id = "no_poses";
  ExpectErrorContaining([&] { WriteDisplacementFigure(empty, dir, "e"); }, (dir / "e").string());
}

}  // namespace
}  // namespace hoof::report
