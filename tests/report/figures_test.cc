#include "report/figures.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "report/gnuplot.h"
#include "support/test_util.h"

namespace hoof::report {
namespace {

namespace fs = std::filesystem;

using hoof::testing::ReadAll;

pipeline::TrialAnalysis FlaggedTrial() {
  pipeline::TrialAnalysis t;
  t.spec.id = "concrete_20deg_tilted";
  for (int f = 0; f < 60; ++f) t.marker_distance_ratio.push_back(std::cos(0.002 * f * f * M_PI / 180));
  t.marker_distance_ratio[30] = NAN;  // a frame without both markers
  t.out_of_plane_change = 0.01;
  t.out_of_plane_noise = 5e-5;
  t.flags = {"out_of_plane"};
  return t;
}

TEST(FiguresTest, OutOfPlaneFigureIsWrittenAsPngAndSvg) {
  const fs::path dir = fs::path(HOOF_BINARY_DIR) / "test-output" / "figures";
  fs::remove_all(dir);
  const pipeline::TrialAnalysis t = FlaggedTrial();
  WriteOutOfPlaneFigure(t, 0.003, dir / "oop.png");
  WriteOutOfPlaneFigure(t, 0.003, dir / "oop.svg");
  const cv::Mat png = cv::imread((dir / "oop.png").string());
  ASSERT_FALSE(png.empty());
  EXPECT_EQ(png.cols, 900);
  EXPECT_EQ(png.rows, 500);
  // Not a blank image: the curve and the text put many distinct grey levels in it.
  cv::Scalar mean, sd;
  cv::meanStdDev(png, mean, sd);
  EXPECT_GT(sd[0], 10.0);
  const std::string svg = ReadAll(dir / "oop.svg");
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("concrete_20deg_tilted: out-of-plane check FLAGGED"), std::string::npos);
  // Only the two figures: no temporary files left behind.
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
  EXPECT_EQ(files, 2);
}

TEST(FiguresTest, ScriptCarriesTheDataInline) {
  Plot p;
  p.title = "t";
  p.series.push_back({"a", {1, 2}, {3, NAN}, {}, "lines"});
  const std::string s = GnuplotScript(p, "x.png");
  EXPECT_NE(s.find("$d0 << EOD\n1 3\n2 NaN\nEOD"), std::string::npos) << s;
  EXPECT_NE(s.find("set terminal pngcairo"), std::string::npos);
  EXPECT_NE(GnuplotScript(p, "x.svg").find("set terminal svg"), std::string::npos);
  EXPECT_THROW(RenderPlot(Plot{}, "empty.png"), std::runtime_error);
}

}  // namespace
}  // namespace hoof::report
