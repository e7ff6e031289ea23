// The residuals' structure against the noise model (docs/discovery.md, "Structure tests"): per
// surface and component, the level and the trends with impact speed and with surface angle, each
// a weighted regression with the variance the noise model predicts for every trial; and the
// marker distance ratio's level and drift in time. They describe what disagrees; they do not
// decide what is named.
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <sstream>

#include <boost/math/distributions/normal.hpp>

#include "discovery/internal.h"
#include "stats/distributions.h"

namespace hoof::discovery::internal {
namespace {

double NormalTwoSided(double z) {
  return 2 * boost::math::cdf(boost::math::complement(boost::math::normal(), std::abs(z)));
}

/// Holm's step-down adjustment, in place.
void Holm(std::vector<StructureTest>& tests, double alpha) {
  std::vector<std::size_t> order(tests.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return tests[a].p < tests[b].p; });
  double running = 0.0;
  const double m = static_cast<double>(tests.size());
  for (std::size_t j = 0; j < order.size(); ++j) {
    auto& t = tests[order[j]];
    running = std::max(running, std::min(1.0, (m - static_cast<double>(j)) * t.p));
    t.p_holm = running;
    t.significant = t.p_holm < alpha;
  }
}

struct Point {
  double x, r, var;
};

/// The noise model's weighted mean of `v`'s residuals against 0 (covariate "level"), or the
/// weighted slope of the residuals against x (`covariate`, per `unit` = `unit_scale` of x):
/// z statistics, since the variances are the noise model's. None without two distinct x.
std::optional<StructureTest> Regress(const std::vector<Point>& v, int c, const std::string& scope,
                                     const std::string& covariate, const std::string& unit,
                                     double unit_scale) {
  double sw = 0, sx = 0, sr = 0;
  for (const auto& p : v) sw += 1 / p.var, sx += p.x / p.var, sr += p.r / p.var;
  const double mx = sx / sw, mr = sr / sw;
  StructureTest t;
  t.quantity = kComponentName[c];
  t.scope = scope;
  t.covariate = covariate;
  if (covariate == "level") {
    t.test = "mean z";
    t.statistic = mr * std::sqrt(sw);
    t.p = NormalTwoSided(t.statistic);
    std::ostringstream d;
    d << t.quantity << " residual " << Fmt(100 * mr, 2) << " % of the impact speed on average ("
      << v.size() << " trials)";
    t.description = d.str();
    return t;
  }
  double sxx = 0, sxr = 0;
  std::set<double> distinct;
  for (const auto& p : v) {
    sxx += (p.x - mx) * (p.x - mx) / p.var;
    sxr += (p.x - mx) * (p.r - mr) / p.var;
    distinct.insert(std::round(p.x * 1e6));
  }
  if (distinct.size() < 2 || !(sxx > 0)) return std::nullopt;
  const double b = sxr / sxx;
  t.test = "slope z";
  t.statistic = b * std::sqrt(sxx);
  t.p = NormalTwoSided(t.statistic);
  std::ostringstream d;
  d << t.quantity << " residual " << (b >= 0 ? "rises " : "falls ")
    << Fmt(std::abs(100 * b * unit_scale), 2) << " % of the impact speed per " << unit << " of "
    << covariate << " (" << v.size() << " trials)";
  t.description = d.str();
  return t;
}

/// Where conditions were repeated on `surface`: do the cell means of component `c` stand off
/// zero by more than the scatter within cells allows? Free of the noise model (a check of it).
void LackOfFitTests(const Workspace& ws, const std::vector<Eigen::Vector3d>& r, std::size_t surface,
                    int c, const DiscoveryOptions& options, std::vector<StructureTest>& tests) {
  std::map<double, std::map<int, std::vector<double>>> cells;  // angle -> cell -> residuals
  for (std::size_t i = 0; i < ws.obs.size(); ++i) {
    const Obs& o = ws.obs[i];
    if (o.surface == static_cast<int>(surface) && o.used[static_cast<std::size_t>(c)] &&
        std::isfinite(r[i][c]))
      cells[o.angle_deg][o.cell].push_back(r[i][c]);
  }
  for (const auto& [angle, of_cell] : cells) {
    double ss_lof = 0, ss_pe = 0, n = 0;
    for (const auto& [cell, v] : of_cell) {
      const double m = std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
      const double beyond = std::max(0.0, std::abs(m) - options.replicate_tolerance);
      ss_lof += static_cast<double>(v.size()) * beyond * beyond;
      for (double x : v) ss_pe += (x - m) * (x - m);
      n += static_cast<double>(v.size());
    }
    const double df1 = static_cast<double>(of_cell.size()), df2 = n - df1;
    if (df2 < 2) continue;
    StructureTest t;
    t.quantity = kComponentName[c];
    t.scope = ws.surfaces[surface] + " " + Fmt(angle) + " deg";
    t.covariate = "cells (speed)";
    t.test = "lack-of-fit F";
    t.df1 = df1;
    t.df2 = df2;
    t.statistic = (ss_lof / df1) / std::max(ss_pe / df2, 1e-30);
    t.p = stats::FUpperTail(t.statistic, df1, df2);
    std::ostringstream d;
    d << t.quantity << " cell means stand off zero beyond "
      << Fmt(100 * options.replicate_tolerance, 2)
      << " % of the impact speed by more than the scatter within cells allows (" << of_cell.size()
      << " cells, " << n << " trials)";
    t.description = d.str();
    tests.push_back(t);
  }
}

/// The tests of component `c`'s residuals on `surface`: their level, their trends with speed
/// and angle, the lack of fit of repeated cells, and the trend with speed at each angle (an
/// effect whose speed dependence changes with the angle, friction for one, can cancel in the
/// pooled trend).
void ComponentTests(const Workspace& ws, const std::vector<Eigen::Vector3d>& r,
                    const std::vector<Sensitivity>& s, const Noise& noise, std::size_t surface,
                    int c, const DiscoveryOptions& options, std::vector<StructureTest>& tests) {
  std::vector<Point> by_speed, by_angle;
  for (std::size_t i = 0; i < ws.obs.size(); ++i) {
    const Obs& o = ws.obs[i];
    if (o.surface != static_cast<int>(surface) || !o.used[static_cast<std::size_t>(c)] ||
        !std::isfinite(r[i][c]))
      continue;
    const TrialCovariance cov = Covariance(ws, o, s[i], noise);
    const auto at =
        std::find(cov.components.begin(), cov.components.end(), c) - cov.components.begin();
    const double var = cov.cov(at, at);
    by_speed.push_back({o.scale, r[i][c], var});
    by_angle.push_back({o.angle_deg, r[i][c], var});
  }
  if (by_speed.size() < 4) return;
  const std::string scope = ws.surfaces[surface];
  for (auto t :
       {Regress(by_speed, c, scope, "level", "", 1), Regress(by_speed, c, scope, "speed", "m/s", 1),
        Regress(by_angle, c, scope, "angle", "10 deg", 10)})
    if (t) tests.push_back(*t);
  LackOfFitTests(ws, r, surface, c, options, tests);
  std::map<double, std::vector<Point>> at_angle;
  for (std::size_t k = 0; k < by_speed.size(); ++k) at_angle[by_angle[k].x].push_back(by_speed[k]);
  if (at_angle.size() > 1)
    for (const auto& [angle, v] : at_angle) {
      if (v.size() < 4) continue;
      if (auto t = Regress(v, c, scope + " " + Fmt(angle) + " deg", "speed", "m/s", 1))
        tests.push_back(*t);
    }
}

/// Image-level evidence: the projected marker distance against the model's, and its drift,
/// each one-sided against the tolerance (a test of |mean| > tolerance).
void MarkerRatioTests(const Workspace& ws, double tilt_rad, const DiscoveryOptions& options,
                      std::vector<StructureTest>& tests) {
  std::vector<double> dev, slope;
  for (const Obs& o : ws.obs) {
    if (std::isfinite(o.marker_ratio)) dev.push_back(o.marker_ratio - std::cos(tilt_rad));
    if (std::isfinite(o.marker_ratio_slope)) slope.push_back(o.marker_ratio_slope);
  }
  auto mean_t = [&](const std::vector<double>& v, const std::string& covariate,
                    const std::string& what, double tolerance, const std::string& unit) {
    if (v.size() < 3) return;
    const double n = static_cast<double>(v.size());
    const double m = std::accumulate(v.begin(), v.end(), 0.0) / n;
    double ss = 0;
    for (double x : v) ss += (x - m) * (x - m);
    const double se = std::sqrt(ss / (n - 1) / n);
    StructureTest t;
    t.quantity = "marker_ratio";
    t.scope = "all";
    t.covariate = covariate;
    t.test = "mean t (|mean| > " + Fmt(tolerance) + unit + ")";
    t.df1 = n - 1;
    t.statistic = se > 0 ? (std::abs(m) - tolerance) / se : 0.0;
    const double p2 = se > 0 ? stats::TTwoSided(t.statistic, n - 1) : 1.0;
    t.p = t.statistic > 0 ? p2 / 2 : 1 - p2 / 2;
    t.description = what + " " + Fmt(m, 3) + unit + " (" + std::to_string(v.size()) + " trials)";
    tests.push_back(t);
  };
  mean_t(dev, "level", "projected / layout marker distance minus the model's",
         options.marker_ratio_tolerance, "");
  // A drift of the ratio by the tolerance over the flight windows (about 4 ms).
  mean_t(slope, "time in the trial", "drift of the projected / layout marker distance",
         options.marker_ratio_tolerance / 4e-3, " per s");
}

}  // namespace

std::vector<StructureTest> StructureTests(const Workspace& ws,
                                          const std::vector<Eigen::Vector3d>& r,
                                          const std::vector<Sensitivity>& s, const Noise& noise,
                                          double tilt_rad, const DiscoveryOptions& options) {
  std::vector<StructureTest> tests;
  for (std::size_t surface = 0; surface < ws.surfaces.size(); ++surface)
    for (int c = 0; c < kComponents; ++c)
      ComponentTests(ws, r, s, noise, surface, c, options, tests);
  MarkerRatioTests(ws, tilt_rad, options, tests);
  Holm(tests, options.alpha);
  return tests;
}

}  // namespace hoof::discovery::internal
