// Discovery workflow (docs/discovery.md): baseline residuals, structure tests, the candidate
// library fitted with Ceres and ranked by leave-trials-out error, the gap on held-out trials,
// and the verdict.
#include "discovery/discovery.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <ceres/ceres.h>

#include "compare/trial_comparison.h"
#include "stats/distributions.h"

namespace hoof::discovery {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kG = dynamics::kStandardGravity_m_s2;
constexpr int kComponents = 3;  // v_x, v_y, w d
const char* const kComponentName[kComponents] = {"v_x", "v_y", "w"};

bool IsMeasurement(const std::string& key) { return key == "out_of_plane"; }

const LibraryEntry& Entry(const std::string& key) {
  for (const auto& e : Library())
    if (e.key == key) return e;
  throw std::invalid_argument("candidates: unknown effect '" + key + "'");
}

/// Sets the extension of `key` to `value` (its own units).
void Apply(const std::string& key, double value, dynamics::ContactExtensions& x) {
  if (key == "hunt_crossley") x.hunt_crossley_N_s_m2 = value;
  else if (key == "hertz_stiffness") x.stiffness_exponent_extra = value;
  else if (key == "plastic_unloading") x.unloading_stiffness_ratio = value;
  else if (key == "static_friction") x.static_friction_excess = value;
  else if (key == "tangential_compliance") x.tangential_compliance_ratio = value;
  else if (key == "rolling_resistance") x.rolling_resistance_m = value;
  else throw std::invalid_argument("no contact extension for '" + key + "'");
}

std::string Fmt(double v, int precision = 3) {
  if (!std::isfinite(v)) return "n/a";
  std::ostringstream s;
  s.precision(precision);
  s << v;
  return s.str();
}

/// " unit", or nothing for a dimensionless "1".
std::string UnitSuffix(const std::string& unit) { return unit == "1" || unit.empty() ? "" : " " + unit; }

/// A fraction as a whole percentage ("95"), never in exponent form.
std::string Percent(double fraction) {
  if (!std::isfinite(fraction)) return "n/a";
  std::ostringstream s;
  s << std::fixed;
  s.precision(0);
  s << 100 * fraction;
  return s.str();
}

std::string FmtP(double p) {
  if (p < 1e-300) return "< 1e-300";
  std::ostringstream s;
  s.precision(2);
  if (p < 1e-3) s << std::scientific;
  s << p;
  return s.str();
}

/// A measured trial as the workflow uses it.
struct Obs {
  const pipeline::TrialAnalysis* trial = nullptr;
  int surface = 0;
  double angle_deg = 0.0, speed_m_s = 0.0;
  bool normal = false;
  int cell = 0, fold = 0;
  dynamics::SpecimenParameters specimen;
  dynamics::ImpactConditions conditions;
  double t_touch_s = 0.0, impact_time_s = 0.0, phi = 0.0;
  Eigen::Vector3d measured{0, 0, 0};  // v_x, v_y, w d after impact, in S
  double scale = 1.0;                 // impact speed |v_SC before|
  std::array<int, kComponents> group{-1, -1, -1};  // noise group per used component, -1 unused
  double marker_ratio = kNaN;        // mean over the flight windows
  double marker_ratio_slope = kNaN;  // per second, over the flight windows
};

/// Parameter values of a model.
struct Model {
  std::vector<double> zeta, mu;          // per surface
  std::map<std::string, double> effects;  // contact effects, own units
  double tilt_rad = 0.0;                  // out-of-plane (measurement) effect
};

/// Noise level per group and how well a model fits.
struct Fit {
  Model model;
  std::vector<double> sigma;  // per group
  double loglik = 0.0;        // profile log likelihood (constants dropped)
  std::map<std::string, double> effect_se;
  std::vector<double> zeta_se, mu_se;
  bool ok = true;
  std::string message;
};

class Workspace {
 public:
  std::vector<Obs> obs;
  std::vector<std::string> surfaces;
  std::vector<double> k;           // per surface (the paper's; not identified)
  std::vector<bool> has_oblique;   // per surface
  std::vector<std::string> group_names;
  /// The comparison's per-surface fit (zeta from normal trials, mu from oblique): the start of
  /// the baseline fit.
  std::vector<double> zeta_start, mu_start;
  /// Per group: the scatter of the measurements within cells (same surface, angle and speed),
  /// free of any model. The held-out error of every model is weighed by it.
  std::vector<double> pure_error;
  double ratio_pure_error = 1e-4;  // the same for the marker distance ratio
  double rtol = 1e-8;
  int threads = 2;
  mutable std::atomic<long long> simulations{0};

  /// v_x, v_y and w d after the impact at the measured impact time, in S.
  Eigen::Vector3d Predict(const Obs& o, double zeta, double mu, const dynamics::ContactExtensions& x,
                          bool* ok) const {
    dynamics::ContactParameters c(k[static_cast<std::size_t>(o.surface)],
                                  dynamics::DampingForRatio(zeta, k[static_cast<std::size_t>(o.surface)],
                                                            o.specimen.mass_kg),
                                  mu);
    c.extensions = x;
    dynamics::SimulatorOptions so;
    so.relative_tolerance = rtol;
    ++simulations;
    const auto r = dynamics::ImpactSimulator(o.specimen, c, so).Simulate(o.conditions);
    *ok = r.success;
    if (!r.success) return {0, 0, 0};
    const Eigen::Vector2d g_S = dynamics::GravityInSurfaceFrame(o.phi, kG);
    const Eigen::Vector2d v =
        r.at_separation.v_SC + g_S * (o.impact_time_s - (o.t_touch_s + r.t_separation_s));
    return {v.x(), v.y(), r.at_separation.w_rad_s * o.specimen.d_EC_m};
  }

  dynamics::ContactExtensions Extensions(const Model& m) const {
    dynamics::ContactExtensions x;
    for (const auto& [key, value] : m.effects) Apply(key, value, x);
    return x;
  }

  /// Residuals (measured - model) / impact speed of every obs; unused components are NaN.
  std::vector<Eigen::Vector3d> Residuals(const Model& m, const std::vector<int>& which) const {
    std::vector<Eigen::Vector3d> out(which.size(), Eigen::Vector3d::Constant(kNaN));
    const dynamics::ContactExtensions x = Extensions(m);
    ParallelFor(which.size(), [&](std::size_t i) {
      const Obs& o = obs[static_cast<std::size_t>(which[i])];
      bool ok = false;
      const auto s = static_cast<std::size_t>(o.surface);
      const Eigen::Vector3d p = Predict(o, m.zeta[s], m.mu[s], x, &ok);
      if (!ok) return;
      for (int c = 0; c < kComponents; ++c)
        if (o.group[static_cast<std::size_t>(c)] >= 0) out[i][c] = (o.measured[c] - p[c]) / o.scale;
    });
    return out;
  }

  void ParallelFor(std::size_t n, const std::function<void(std::size_t)>& f) const {
    const std::size_t t = std::min<std::size_t>(static_cast<std::size_t>(std::max(1, threads)), n);
    if (t <= 1) {
      for (std::size_t i = 0; i < n; ++i) f(i);
      return;
    }
    std::atomic<std::size_t> next{0};
    std::vector<std::thread> pool;
    for (std::size_t w = 0; w < t; ++w)
      pool.emplace_back([&] {
        for (std::size_t i = next++; i < n; i = next++) f(i);
      });
    for (auto& th : pool) th.join();
  }

  /// Per-group root mean square of residuals (with a floor), and the profile log likelihood.
  std::pair<std::vector<double>, double> Noise(const std::vector<Eigen::Vector3d>& r,
                                               const std::vector<int>& which) const {
    std::vector<double> ss(group_names.size(), 0.0), n(group_names.size(), 0.0);
    for (std::size_t i = 0; i < which.size(); ++i) {
      const Obs& o = obs[static_cast<std::size_t>(which[i])];
      for (int c = 0; c < kComponents; ++c) {
        const int g = o.group[static_cast<std::size_t>(c)];
        if (g < 0) continue;
        // A failed simulation counts as a large misfit rather than vanishing from the sum.
        const double v = std::isfinite(r[i][c]) ? r[i][c] : 1.0;
        ss[static_cast<std::size_t>(g)] += v * v;
        n[static_cast<std::size_t>(g)] += 1;
      }
    }
    std::vector<double> sigma(group_names.size(), 1.0);
    double ll = 0.0;
    for (std::size_t g = 0; g < ss.size(); ++g) {
      if (n[g] == 0) continue;
      const double ms = std::max(ss[g] / n[g], kSigmaFloor * kSigmaFloor);
      sigma[g] = std::sqrt(ms);
      ll -= 0.5 * n[g] * std::log(ms);
    }
    return {sigma, ll};
  }

  static constexpr double kSigmaFloor = 1e-6;
};

/// Ceres cost of one trial: its used residual components over their group's noise.
struct TrialCost {
  const Workspace* ws;
  const Obs* o;
  const std::vector<double>* sigma;
  bool mu_free;
  double mu_fixed;
  std::vector<std::string> effect_keys;   // free effects, in block order
  std::vector<double> effect_scale;       // value = u * scale
  std::map<std::string, double> fixed_effects;
  std::vector<int> components;

  bool operator()(double const* const* p, double* residuals) const {
    std::size_t b = 0;
    const double zeta = p[b++][0];
    const double mu = mu_free ? p[b++][0] : mu_fixed;
    dynamics::ContactExtensions x;
    for (const auto& [key, value] : fixed_effects) Apply(key, value, x);
    for (std::size_t j = 0; j < effect_keys.size(); ++j) Apply(effect_keys[j], p[b++][0] * effect_scale[j], x);
    bool ok = false;
    Eigen::Vector3d pred;
    try {
      pred = ws->Predict(*o, zeta, mu, x, &ok);
    } catch (const std::exception&) {
      ok = false;
    }
    for (std::size_t i = 0; i < components.size(); ++i) {
      const int c = components[i];
      const double s = (*sigma)[static_cast<std::size_t>(o->group[static_cast<std::size_t>(c)])];
      residuals[i] = ok ? (o->measured[c] - pred[c]) / o->scale / s : 1.0 / s;
    }
    return true;
  }
};

/// Fits the per-surface zeta and mu and the `free_effects` (others fixed at their values in
/// `start`) to the trials `which`: two passes of reweighting, each a Ceres solve.
Fit FitModel(const Workspace& ws, const std::vector<int>& which, const Model& start,
             const std::vector<std::string>& free_effects) {
  Fit fit;
  fit.model = start;
  const std::size_t S = ws.surfaces.size();
  std::vector<bool> surface_used(S, false), surface_oblique(S, false);
  for (int i : which) {
    const Obs& o = ws.obs[static_cast<std::size_t>(i)];
    surface_used[static_cast<std::size_t>(o.surface)] = true;
    if (!o.normal) surface_oblique[static_cast<std::size_t>(o.surface)] = true;
  }
  fit.sigma = ws.Noise(ws.Residuals(fit.model, which), which).first;
  std::vector<double> zeta = start.zeta, mu = start.mu;
  std::vector<double> u(free_effects.size()), scale(free_effects.size());
  for (std::size_t j = 0; j < free_effects.size(); ++j) {
    scale[j] = Entry(free_effects[j]).probe;
    const auto it = start.effects.find(free_effects[j]);
    u[j] = it == start.effects.end() ? 0.0 : it->second / scale[j];
  }
  std::map<std::string, double> fixed;
  for (const auto& [key, value] : start.effects)
    if (std::find(free_effects.begin(), free_effects.end(), key) == free_effects.end()) fixed[key] = value;

  for (int pass = 0; pass < 2; ++pass) {
    ceres::Problem::Options po;
    ceres::Problem problem(po);
    int blocks = 0;
    for (int i : which) {
      const Obs& o = ws.obs[static_cast<std::size_t>(i)];
      const auto s = static_cast<std::size_t>(o.surface);
      auto* f = new TrialCost{&ws, &o, &fit.sigma, !o.normal && surface_oblique[s], mu[s], free_effects, scale, fixed, {}};
      for (int c = 0; c < kComponents; ++c)
        if (o.group[static_cast<std::size_t>(c)] >= 0) f->components.push_back(c);
      ceres::NumericDiffOptions nd;
      nd.relative_step_size = 1e-4;
      auto* cost = new ceres::DynamicNumericDiffCostFunction<TrialCost, ceres::CENTRAL>(f, ceres::TAKE_OWNERSHIP, nd);
      std::vector<double*> params{&zeta[s]};
      if (f->mu_free) params.push_back(&mu[s]);
      for (double& v : u) params.push_back(&v);
      for (std::size_t b = 0; b < params.size(); ++b) cost->AddParameterBlock(1);
      cost->SetNumResiduals(static_cast<int>(f->components.size()));
      problem.AddResidualBlock(cost, nullptr, params);
      ++blocks;
    }
    if (blocks == 0) break;
    for (std::size_t s = 0; s < S; ++s) {
      if (!surface_used[s]) continue;
      problem.SetParameterLowerBound(&zeta[s], 0, 1e-4);
      problem.SetParameterUpperBound(&zeta[s], 0, 5.0);
      if (surface_oblique[s] && problem.HasParameterBlock(&mu[s])) {
        problem.SetParameterLowerBound(&mu[s], 0, 0.0);
        problem.SetParameterUpperBound(&mu[s], 0, 2.0);
      }
    }
    for (std::size_t j = 0; j < u.size(); ++j) {
      problem.SetParameterLowerBound(&u[j], 0, 0.0);
      problem.SetParameterUpperBound(&u[j], 0, Entry(free_effects[j]).upper / scale[j]);
    }
    ceres::Solver::Options so;
    so.linear_solver_type = ceres::DENSE_QR;
    so.max_num_iterations = 40;
    so.function_tolerance = 1e-9;
    so.parameter_tolerance = 1e-8;
    so.num_threads = ws.threads;
    so.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    if (!summary.IsSolutionUsable()) {
      fit.ok = false;
      fit.message = summary.message;
    }
    fit.model.zeta = zeta;
    fit.model.mu = mu;
    for (std::size_t j = 0; j < u.size(); ++j) fit.model.effects[free_effects[j]] = u[j] * scale[j];
    const auto [sigma, ll] = ws.Noise(ws.Residuals(fit.model, which), which);
    fit.loglik = ll;
    if (pass == 1) {
      // Standard errors from the Gauss-Newton normal matrix at the solution (noise fixed).
      ceres::Problem::EvaluateOptions eo;
      std::vector<double*> order;
      for (std::size_t s = 0; s < S; ++s) {
        if (problem.HasParameterBlock(&zeta[s]) && !problem.IsParameterBlockConstant(&zeta[s])) order.push_back(&zeta[s]);
        if (problem.HasParameterBlock(&mu[s]) && !problem.IsParameterBlockConstant(&mu[s])) order.push_back(&mu[s]);
      }
      for (double& v : u) order.push_back(&v);
      eo.parameter_blocks = order;
      eo.num_threads = ws.threads;
      ceres::CRSMatrix crs;
      problem.Evaluate(eo, nullptr, nullptr, nullptr, &crs);
      Eigen::MatrixXd J = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
      for (int r = 0; r < crs.num_rows; ++r)
        for (int q = crs.rows[static_cast<std::size_t>(r)]; q < crs.rows[static_cast<std::size_t>(r) + 1]; ++q)
          J(r, crs.cols[static_cast<std::size_t>(q)]) = crs.values[static_cast<std::size_t>(q)];
      const Eigen::MatrixXd cov = (J.transpose() * J).completeOrthogonalDecomposition().pseudoInverse();
      fit.zeta_se.assign(S, kNaN);
      fit.mu_se.assign(S, kNaN);
      std::size_t col = 0;
      for (std::size_t s = 0; s < S; ++s) {
        if (problem.HasParameterBlock(&zeta[s]) && !problem.IsParameterBlockConstant(&zeta[s]))
          fit.zeta_se[s] = std::sqrt(std::max(0.0, cov(static_cast<Eigen::Index>(col), static_cast<Eigen::Index>(col)))), ++col;
        if (problem.HasParameterBlock(&mu[s]) && !problem.IsParameterBlockConstant(&mu[s]))
          fit.mu_se[s] = std::sqrt(std::max(0.0, cov(static_cast<Eigen::Index>(col), static_cast<Eigen::Index>(col)))), ++col;
      }
      for (std::size_t j = 0; j < u.size(); ++j, ++col)
        fit.effect_se[free_effects[j]] =
            scale[j] * std::sqrt(std::max(0.0, cov(static_cast<Eigen::Index>(col), static_cast<Eigen::Index>(col))));
    }
    fit.sigma = sigma;
  }
  return fit;
}

/// The out-of-plane (measurement) model: the marker distance ratio is cos(tilt) in every trial.
struct TiltFit {
  double tilt_rad = 0.0, tilt_se_rad = kNaN;
  double sigma = 1.0, loglik = 0.0;
};

TiltFit FitTilt(const Workspace& ws, const std::vector<int>& which, bool free) {
  TiltFit f;
  std::vector<double> r;
  for (int i : which) {
    const double v = ws.obs[static_cast<std::size_t>(i)].marker_ratio;
    if (std::isfinite(v)) r.push_back(v);
  }
  if (r.empty()) return f;
  const double n = static_cast<double>(r.size());
  const double mean = std::accumulate(r.begin(), r.end(), 0.0) / n;
  const double c = free ? std::clamp(mean, -1.0, 1.0) : 1.0;
  if (free) f.tilt_rad = std::acos(std::min(1.0, c));
  double ss = 0;
  for (double v : r) ss += (v - std::cos(f.tilt_rad)) * (v - std::cos(f.tilt_rad));
  const double ms = std::max(ss / n, 1e-14);
  f.sigma = std::sqrt(ms);
  f.loglik = -0.5 * n * std::log(ms);
  if (free && f.tilt_rad > 0 && n > 1) f.tilt_se_rad = f.sigma / std::sqrt(n - 1) / std::sin(f.tilt_rad);
  return f;
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

/// Structure tests of a model's residuals over all trials: per surface, angle and component a
/// lack-of-fit F test of the cell means (speeds) against the scatter within cells; and the
/// marker distance ratio against the out-of-plane model (mean t test, and its drift in time).
std::vector<StructureTest> StructureTests(const Workspace& ws, const std::vector<Eigen::Vector3d>& r,
                                          double tilt_rad, double alpha, double ratio_tolerance,
                                          double velocity_tolerance) {
  std::vector<StructureTest> tests;
  // Groups are (surface, angle, component); cells within them are speeds.
  for (std::size_t g = 0; g < ws.group_names.size(); ++g) {
    std::map<int, std::vector<double>> cells;
    std::vector<std::pair<double, double>> xy;  // speed, residual
    int comp = -1;
    std::string surface;
    double angle = 0;
    for (std::size_t i = 0; i < ws.obs.size(); ++i) {
      const Obs& o = ws.obs[i];
      for (int c = 0; c < kComponents; ++c)
        if (o.group[static_cast<std::size_t>(c)] == static_cast<int>(g) && std::isfinite(r[i][c])) {
          cells[o.cell].push_back(r[i][c]);
          xy.emplace_back(o.speed_m_s, r[i][c]);
          comp = c;
          surface = ws.surfaces[static_cast<std::size_t>(o.surface)];
          angle = o.angle_deg;
        }
    }
    if (comp < 0) continue;
    double ss_lof = 0, ss_pe = 0, n = 0;
    for (const auto& [cell, v] : cells) {
      const double m = std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
      // Only the part of a cell mean beyond the tolerance counts (a test of |mean| > tolerance).
      const double beyond = std::max(0.0, std::abs(m) - velocity_tolerance);
      ss_lof += static_cast<double>(v.size()) * beyond * beyond;
      for (double x : v) ss_pe += (x - m) * (x - m);
      n += static_cast<double>(v.size());
    }
    const double df1 = static_cast<double>(cells.size()), df2 = n - df1;
    if (df2 < 1) continue;
    StructureTest t;
    t.quantity = kComponentName[comp];
    t.scope = surface + " " + Fmt(angle) + " deg";
    t.covariate = "cells (speed)";
    t.test = "lack-of-fit F (|cell mean| > " + Fmt(100 * velocity_tolerance) + " %)";
    t.df1 = df1;
    t.df2 = df2;
    const double pe = std::max(ss_pe / df2, 1e-30);
    t.statistic = (ss_lof / df1) / pe;
    t.p = stats::FUpperTail(t.statistic, df1, df2);
    // In words: the mean residual and its slope against speed.
    double mx = 0, my = 0;
    for (const auto& [x, y] : xy) mx += x, my += y;
    mx /= static_cast<double>(xy.size());
    my /= static_cast<double>(xy.size());
    double sxx = 0, sxy = 0;
    for (const auto& [x, y] : xy) sxx += (x - mx) * (x - mx), sxy += (x - mx) * (y - my);
    std::ostringstream d;
    d << t.quantity << " residual " << Fmt(100 * my, 2) << " % of the impact speed on average";
    if (sxx > 0) d << ", " << (sxy >= 0 ? "+" : "") << Fmt(100 * sxy / sxx, 2) << " % per m/s of speed";
    d << " (" << static_cast<int>(n) << " trials, " << cells.size() << " speeds)";
    t.description = d.str();
    tests.push_back(t);
  }
  // Image-level evidence: the projected marker distance against the model's.
  std::vector<double> dev, slope;
  for (const Obs& o : ws.obs) {
    if (std::isfinite(o.marker_ratio)) dev.push_back(o.marker_ratio - std::cos(tilt_rad));
    if (std::isfinite(o.marker_ratio_slope)) slope.push_back(o.marker_ratio_slope);
  }
  // One-sided against the tolerance: the test is of |mean| > tolerance.
  auto mean_t = [&](const std::vector<double>& v, const std::string& covariate, const std::string& what,
                    double tolerance, const std::string& unit) {
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
  mean_t(dev, "level", "projected / layout marker distance minus the model's", ratio_tolerance, "");
  // A drift of the ratio by the tolerance over the flight windows (about 4 ms).
  mean_t(slope, "time in the trial", "drift of the projected / layout marker distance", ratio_tolerance / 4e-3,
         " per s");
  Holm(tests, alpha);
  return tests;
}

double Rms(const Eigen::Vector3d& r) {
  double s = 0;
  int n = 0;
  for (int c = 0; c < kComponents; ++c)
    if (std::isfinite(r[c])) s += r[c] * r[c], ++n;
  return n ? std::sqrt(s / n) : kNaN;
}

/// Held-out error of one trial: mean over its components of (residual / training noise)^2.
double HeldOutError(const Obs& o, const Eigen::Vector3d& r, const std::vector<double>& sigma) {
  double s = 0;
  int n = 0;
  for (int c = 0; c < kComponents; ++c) {
    const int g = o.group[static_cast<std::size_t>(c)];
    if (g < 0) continue;
    const double v = std::isfinite(r[c]) ? r[c] : 1.0;
    s += std::pow(v / sigma[static_cast<std::size_t>(g)], 2);
    ++n;
  }
  return n ? s / n : kNaN;
}

/// Per fold: the model fitted without the fold, and the fold's residuals and errors.
struct CrossValidation {
  std::vector<double> error;             // per obs (held out)
  std::vector<Eigen::Vector3d> residual;  // per obs (held out)
  double mean_error = 0.0;
};

CrossValidation CrossValidate(const Workspace& ws, const Model& start, const std::vector<std::string>& free_effects,
                              int folds) {
  CrossValidation cv;
  cv.error.assign(ws.obs.size(), kNaN);
  cv.residual.assign(ws.obs.size(), Eigen::Vector3d::Constant(kNaN));
  for (int f = 0; f < folds; ++f) {
    std::vector<int> train, test;
    for (std::size_t i = 0; i < ws.obs.size(); ++i) (ws.obs[i].fold == f ? test : train).push_back(static_cast<int>(i));
    if (test.empty() || train.empty()) continue;
    const Fit fit = FitModel(ws, train, start, free_effects);
    const auto r = ws.Residuals(fit.model, test);
    for (std::size_t j = 0; j < test.size(); ++j) {
      const auto i = static_cast<std::size_t>(test[j]);
      cv.residual[i] = r[j];
      cv.error[i] = HeldOutError(ws.obs[i], r[j], ws.pure_error);
    }
  }
  double s = 0;
  int n = 0;
  for (double e : cv.error)
    if (std::isfinite(e)) s += e, ++n;
  cv.mean_error = n ? s / n : kNaN;
  return cv;
}

/// The same for the out-of-plane model, on the marker distance ratio.
CrossValidation CrossValidateTilt(const Workspace& ws, bool free, int folds) {
  CrossValidation cv;
  cv.error.assign(ws.obs.size(), kNaN);
  cv.residual.assign(ws.obs.size(), Eigen::Vector3d::Constant(kNaN));
  for (int f = 0; f < folds; ++f) {
    std::vector<int> train;
    for (std::size_t i = 0; i < ws.obs.size(); ++i)
      if (ws.obs[i].fold != f) train.push_back(static_cast<int>(i));
    const TiltFit t = FitTilt(ws, train, free);
    for (std::size_t i = 0; i < ws.obs.size(); ++i) {
      const Obs& o = ws.obs[i];
      if (o.fold != f || !std::isfinite(o.marker_ratio)) continue;
      const double r = o.marker_ratio - std::cos(t.tilt_rad);
      cv.residual[i] = {r, kNaN, kNaN};
      cv.error[i] = r * r / (ws.ratio_pure_error * ws.ratio_pure_error);
    }
  }
  double s = 0;
  int n = 0;
  for (double e : cv.error)
    if (std::isfinite(e)) s += e, ++n;
  cv.mean_error = n ? s / n : kNaN;
  return cv;
}

/// One-sided paired t test that `b` has lower errors than `a`.
double PairedImprovementP(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> d;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::isfinite(a[i]) && std::isfinite(b[i])) d.push_back(a[i] - b[i]);
  if (d.size() < 3) return 1.0;
  const double n = static_cast<double>(d.size());
  const double m = std::accumulate(d.begin(), d.end(), 0.0) / n;
  double ss = 0;
  for (double x : d) ss += (x - m) * (x - m);
  const double se = std::sqrt(ss / (n - 1) / n);
  if (!(se > 0)) return m > 0 ? 0.0 : 1.0;
  const double p2 = stats::TTwoSided(m / se, n - 1);
  return m > 0 ? p2 / 2 : 1 - p2 / 2;
}

/// Builds the workspace from the measured trials; throws std::runtime_error when too few.
void Build(const std::vector<pipeline::TrialAnalysis>& trials, const DiscoveryOptions& options, int* skipped,
           Workspace& ws) {
  ws.rtol = options.relative_tolerance;
  ws.threads = options.jobs > 0 ? options.jobs : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::map<std::string, int> surface_index;
  std::map<std::string, int> cell_index, group_index;
  *skipped = 0;
  std::vector<const pipeline::TrialAnalysis*> used;
  for (const auto& t : trials) {
    if (!t.success) {
      ++*skipped;
      continue;
    }
    used.push_back(&t);
  }
  // Baseline per surface from the comparison's rules (zeta from normal trials, mu from oblique).
  std::map<std::string, compare::SurfaceModel> base;
  for (const auto* t : used)
    if (!base.count(t->spec.surface)) base[t->spec.surface] = compare::FitSurfaceModel(t->spec.surface, trials);
  for (const auto* t : used) {
    const auto& m = base.at(t->spec.surface);
    if (!m.success) {
      ++*skipped;
      continue;
    }
    Obs o;
    o.trial = t;
    const auto [it, added] = surface_index.try_emplace(t->spec.surface, static_cast<int>(ws.surfaces.size()));
    if (added) {
      ws.surfaces.push_back(t->spec.surface);
      ws.k.push_back(m.k_N_m);
      ws.zeta_start.push_back(m.zeta_fit.zeta);
      ws.mu_start.push_back(std::isfinite(m.mu) ? m.mu : 0.3);
      ws.has_oblique.push_back(false);
    }
    o.surface = it->second;
    o.angle_deg = t->spec.surface_angle_deg;
    o.normal = std::abs(o.angle_deg) < 1e-9;
    if (!o.normal) ws.has_oblique[static_cast<std::size_t>(o.surface)] = true;
    o.scale = t->impact.v_SC_before.norm();
    if (!(o.scale > 0)) {
      ++*skipped;
      continue;
    }
    o.speed_m_s = t->spec.nominal_speed_m_s.value_or(std::round(o.scale * 4) / 4);
    o.specimen = compare::SpecimenOf(*t);
    dynamics::ContactParameters contact = m.Contact();
    if (!std::isfinite(contact.mu)) contact.mu = 0.3;
    o.t_touch_s = compare::SimulatedTouchTime(*t, contact);
    o.conditions = compare::MeasuredConditions(*t, o.t_touch_s);
    o.impact_time_s = t->impact.impact_time_s;
    o.phi = o.angle_deg * std::numbers::pi / 180.0;
    o.measured = {t->impact.v_SC_after.x(), t->impact.v_SC_after.y(), t->impact.w_after_rad_s * o.specimen.d_EC_m};
    const std::string cell_key = t->spec.surface + "|" + Fmt(o.angle_deg, 6) + "|" + Fmt(o.speed_m_s, 6);
    o.cell = cell_index.try_emplace(cell_key, static_cast<int>(cell_index.size())).first->second;
    for (int c = 0; c < kComponents; ++c) {
      if (o.normal && c != 1) continue;
      const std::string g = t->spec.surface + " " + Fmt(o.angle_deg) + " deg " + kComponentName[c];
      const auto [gi, gadded] = group_index.try_emplace(g, static_cast<int>(ws.group_names.size()));
      if (gadded) ws.group_names.push_back(g);
      o.group[static_cast<std::size_t>(c)] = gi->second;
    }
    // Image-level evidence: the marker distance ratio over the flight windows.
    std::vector<std::pair<double, double>> tr;
    for (const auto* fit : {&t->impact.before, &t->impact.after})
      for (int f = fit->first_frame; f <= fit->last_frame; ++f)
        if (f >= 0 && static_cast<std::size_t>(f) < t->marker_distance_ratio.size() &&
            std::isfinite(t->marker_distance_ratio[static_cast<std::size_t>(f)]))
          tr.emplace_back(f / t->spec.fps, t->marker_distance_ratio[static_cast<std::size_t>(f)]);
    if (tr.size() >= 3) {
      double mx = 0, my = 0;
      for (const auto& [x, y] : tr) mx += x, my += y;
      mx /= static_cast<double>(tr.size());
      my /= static_cast<double>(tr.size());
      double sxx = 0, sxy = 0;
      for (const auto& [x, y] : tr) sxx += (x - mx) * (x - mx), sxy += (x - mx) * (y - my);
      o.marker_ratio = my;
      o.marker_ratio_slope = sxx > 0 ? sxy / sxx : kNaN;
    }
    ws.obs.push_back(o);
  }
  // Folds: trials of each cell dealt round-robin, continuing from cell to cell.
  std::vector<std::size_t> order(ws.obs.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) {
    if (ws.obs[a].cell != ws.obs[b].cell) return ws.obs[a].cell < ws.obs[b].cell;
    return ws.obs[a].trial->spec.id < ws.obs[b].trial->spec.id;
  });
  int next = 0;
  for (std::size_t i : order) ws.obs[i].fold = next++ % options.folds;
  // Pure error per group: pooled within-cell variance of the measured values.
  std::vector<double> ss(ws.group_names.size(), 0.0), df(ws.group_names.size(), 0.0);
  std::map<std::pair<int, int>, std::vector<double>> cell_values;  // (group, cell) -> values
  for (const Obs& o : ws.obs)
    for (int c = 0; c < kComponents; ++c)
      if (o.group[static_cast<std::size_t>(c)] >= 0)
        cell_values[{o.group[static_cast<std::size_t>(c)], o.cell}].push_back(o.measured[c] / o.scale);
  for (const auto& [key, v] : cell_values) {
    if (v.size() < 2) continue;
    const double m = std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
    for (double x : v) ss[static_cast<std::size_t>(key.first)] += (x - m) * (x - m);
    df[static_cast<std::size_t>(key.first)] += static_cast<double>(v.size()) - 1;
  }
  double pooled_ss = 0, pooled_df = 0;
  for (std::size_t g = 0; g < ss.size(); ++g) pooled_ss += ss[g], pooled_df += df[g];
  const double fallback = pooled_df > 0 ? std::sqrt(pooled_ss / pooled_df) : 1e-3;
  ws.pure_error.assign(ws.group_names.size(), fallback);
  {
    std::map<int, std::vector<double>> ratios;
    for (const Obs& o : ws.obs)
      if (std::isfinite(o.marker_ratio)) ratios[o.cell].push_back(o.marker_ratio);
    double rs = 0, rd = 0;
    for (const auto& [cell, v] : ratios) {
      if (v.size() < 2) continue;
      const double m = std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
      for (double x : v) rs += (x - m) * (x - m);
      rd += static_cast<double>(v.size()) - 1;
    }
    if (rd >= 2) ws.ratio_pure_error = std::max(std::sqrt(rs / rd), 1e-7);
  }
  for (std::size_t g = 0; g < ss.size(); ++g)
    if (df[g] >= 2) ws.pure_error[g] = std::max(std::sqrt(ss[g] / df[g]), Workspace::kSigmaFloor);
}

Model BaselineStart(const Workspace& ws) {
  Model m;
  m.zeta = ws.zeta_start;
  m.mu = ws.mu_start;
  return m;
}

std::vector<SurfaceFit> SurfaceFits(const Workspace& ws, const Fit& f) {
  std::vector<SurfaceFit> out;
  for (std::size_t s = 0; s < ws.surfaces.size(); ++s) {
    SurfaceFit sf;
    sf.surface = ws.surfaces[s];
    sf.zeta = f.model.zeta[s];
    sf.zeta_se = s < f.zeta_se.size() ? f.zeta_se[s] : kNaN;
    sf.mu = ws.has_oblique[s] ? f.model.mu[s] : kNaN;
    sf.mu_se = ws.has_oblique[s] && s < f.mu_se.size() ? f.mu_se[s] : kNaN;
    sf.k_N_m = ws.k[s];
    for (const Obs& o : ws.obs) sf.trials += o.surface == static_cast<int>(s) ? 1 : 0;
    out.push_back(sf);
  }
  return out;
}

}  // namespace

const std::vector<LibraryEntry>& Library() {
  static const std::vector<LibraryEntry> library = {
      {"hunt_crossley", "velocity-dependent (Hunt-Crossley) damping", "c", "N s/m^2", 2e7, 5e8, false,
       "extra damping c |delta| delta' in compression: e falls as the impact speed rises",
       "impacts over a wider range of speeds, or the force through the contact (its hysteresis "
       "loop grows with speed)"},
      {"hertz_stiffness", "nonlinear (Hertzian) stiffness", "p", "1", 0.5, 1.0, false,
       "elastic force k |delta| (|delta| / delta_ref)^p: the effective damping ratio changes with "
       "speed, e rises with speed",
       "the contact duration against impact speed (it shortens with speed only for a stiffening "
       "contact), or the force through the contact"},
      {"plastic_unloading", "dissipative (plastic) restitution", "r", "1", 0.5, 10.0, false,
       "unloading stiffer than loading, k (1 + r): lower e at every speed",
       "the force through the contact (unloading path) or the residual indentation of the surface"},
      {"static_friction", "static friction above kinetic", "mu_s - mu", "1", 0.1, 1.0, false,
       "stick holds up to (mu + excess) P: the impulse ratio at angles near the stick limit",
       "oblique impacts at angles near the stick limit (tan(angle) close to mu)"},
      {"tangential_compliance", "tangential contact compliance", "k/k_t", "1", 1.0, 10.0, false,
       "a tangential spring at the contact point: spin and v_C.x after small-angle impacts, T's "
       "tangential velocity can reverse",
       "the tangential velocity of the contact point through the contact, filmed at a higher rate"},
      {"rolling_resistance", "rolling resistance (contact torque)", "rho", "m", 5e-4, 1e-2, false,
       "a contact torque: less spin after oblique impacts, v_C nearly unchanged",
       "spin after impacts with a known initial spin"},
      {"out_of_plane", "out-of-plane rotation (a measurement effect)", "tilt", "deg", 10.0, 60.0, true,
       "the projected marker distance shrinks by cos(tilt): apparent changes of the pose",
       "a second camera or a mirror view (stereo)"},
  };
  return library;
}

void DiscoveryOptions::Validate() const {
  if (!(alpha > 0 && alpha < 0.5)) throw std::invalid_argument("alpha must be in (0, 0.5), got " + Fmt(alpha));
  if (folds < 2) throw std::invalid_argument("folds must be >= 2, got " + std::to_string(folds));
  if (max_rounds < 1) throw std::invalid_argument("max_rounds must be >= 1, got " + std::to_string(max_rounds));
  if (jobs < 0) throw std::invalid_argument("jobs must be >= 0, got " + std::to_string(jobs));
  if (!(relative_tolerance > 0 && relative_tolerance <= 1e-4))
    throw std::invalid_argument("relative_tolerance must be in (0, 1e-4], got " + Fmt(relative_tolerance));
  if (!(velocity_tolerance >= 0 && velocity_tolerance < 0.1))
    throw std::invalid_argument("velocity_tolerance must be in [0, 0.1), got " + Fmt(velocity_tolerance));
  if (!(marker_ratio_tolerance >= 0 && marker_ratio_tolerance < 0.1))
    throw std::invalid_argument("marker_ratio_tolerance must be in [0, 0.1), got " + Fmt(marker_ratio_tolerance));
  for (const auto& k : candidates) Entry(k);
}

DiscoveryResult Discover(const std::vector<pipeline::TrialAnalysis>& trials, const DiscoveryOptions& options,
                         const std::function<void(const std::string&)>& progress) {
  options.Validate();
  const auto t0 = std::chrono::steady_clock::now();
  auto say = [&](const std::string& s) {
    if (progress) progress(s);
  };
  DiscoveryResult out;
  int skipped = 0;
  Workspace ws;
  Build(trials, options, &skipped, ws);
  out.trials_skipped = skipped;
  out.trials_used = static_cast<int>(ws.obs.size());
  if (ws.obs.size() < 6) {
    out.message = "too few measured trials with a fitted surface model (" + std::to_string(ws.obs.size()) +
                  "; at least 6 are needed)";
    return out;
  }
  std::vector<std::string> keys = options.candidates;
  if (keys.empty())
    for (const auto& e : Library()) keys.push_back(e.key);
  std::vector<int> all(ws.obs.size());
  std::iota(all.begin(), all.end(), 0);
  const double bonferroni = options.alpha / static_cast<double>(keys.size());
  const double n_res = [&] {
    double n = 0;
    for (const Obs& o : ws.obs)
      for (int g : o.group) n += g >= 0 ? 1 : 0;
    return n;
  }();
  int n_ratio = 0;
  for (const Obs& o : ws.obs) n_ratio += std::isfinite(o.marker_ratio) ? 1 : 0;

  say("baseline: fitting zeta and mu per surface to " + std::to_string(ws.obs.size()) + " trials");
  Fit current = FitModel(ws, all, BaselineStart(ws), {});
  out.baseline = SurfaceFits(ws, current);
  bool tilt_on = false;
  TiltFit tilt = FitTilt(ws, all, false);
  std::vector<std::string> accepted;

  for (int round = 1; round <= options.max_rounds; ++round) {
    Round rd;
    rd.index = round;
    const auto residuals = ws.Residuals(current.model, all);
    rd.tests = StructureTests(ws, residuals, tilt.tilt_rad, options.alpha, options.marker_ratio_tolerance,
                              options.velocity_tolerance);
    const bool any_significant = std::any_of(rd.tests.begin(), rd.tests.end(), [](auto& t) { return t.significant; });
    say("round " + std::to_string(round) + ": " +
        std::to_string(std::count_if(rd.tests.begin(), rd.tests.end(), [](auto& t) { return t.significant; })) +
        " significant disagreement(s) of " + std::to_string(rd.tests.size()) + " tests");
    std::vector<std::string> free_current;
    for (const auto& a : accepted)
      if (!IsMeasurement(a)) free_current.push_back(a);
    const CrossValidation cv_current = CrossValidate(ws, current.model, free_current, options.folds);
    const CrossValidation cv_tilt_current = CrossValidateTilt(ws, tilt_on, options.folds);
    std::map<std::string, CrossValidation> cvs;
    std::map<std::string, Fit> fits;
    std::map<std::string, TiltFit> tilt_fits;
    for (const auto& key : keys) {
      if (std::find(accepted.begin(), accepted.end(), key) != accepted.end()) continue;
      const LibraryEntry& e = Entry(key);
      CandidateResult c;
      c.key = key;
      c.name = e.name;
      c.parameter = e.parameter;
      c.unit = e.unit;
      c.measurement_effect = e.measurement_effect;
      say("  " + key);
      if (e.measurement_effect) {
        if (n_ratio < 3) {
          c.message = "fewer than 3 trials with a marker distance";
          c.identifiability = "not tested by these data";
          rd.candidates.push_back(c);
          continue;
        }
        const TiltFit tf = FitTilt(ws, all, true);
        tilt_fits[key] = tf;
        c.fitted = true;
        c.estimate = tf.tilt_rad * 180 / std::numbers::pi;
        c.se = tf.tilt_se_rad * 180 / std::numbers::pi;
        c.lr_statistic = std::max(0.0, 2 * (tf.loglik - tilt.loglik));
        c.p_value = 0.5 * stats::ChiSquaredUpperTail(c.lr_statistic, 1);  // boundary at 0
        c.delta_aic = -c.lr_statistic + 2;
        c.delta_bic = -c.lr_statistic + std::log(static_cast<double>(n_ratio));
        const CrossValidation cv = CrossValidateTilt(ws, true, options.folds);
        cvs[key] = cv;
        c.cv_error = cv.mean_error;
        c.cv_error_current = cv_tilt_current.mean_error;
        c.cv_p = PairedImprovementP(cv_tilt_current.error, cv.error);
        c.identifiability = "identified";
        // A tilt too small to tell from the calibration's own limits is not named.
        c.significant = c.p_value < bonferroni && c.cv_error < c.cv_error_current &&
                        1 - std::cos(tf.tilt_rad) > options.marker_ratio_tolerance;
        rd.candidates.push_back(c);
        continue;
      }
      // Identifiability probe: the effect fixed at a realistic size, the rest refitted.
      Model probe_start = current.model;
      probe_start.effects[key] = e.probe;
      const Fit probe = FitModel(ws, all, probe_start, free_current);
      const double probe_lr = 2 * (probe.loglik - current.loglik);
      // Without refitting, how much does the probe change the fit?
      const double fixed_lr = 2 * (ws.Noise(ws.Residuals(probe_start, all), all).second - current.loglik);
      const double chi95 = stats::ChiSquaredQuantile(0.95, 1);
      if (std::abs(fixed_lr) < chi95) {
        c.identifiability = "not tested by these data";
      } else if (std::abs(probe_lr) < chi95) {
        std::vector<std::string> moved;
        for (std::size_t s = 0; s < ws.surfaces.size(); ++s) {
          if (std::abs(probe.model.zeta[s] - current.model.zeta[s]) > 1e-3 * current.model.zeta[s] &&
              std::find(moved.begin(), moved.end(), "zeta") == moved.end())
            moved.push_back("zeta");
          if (ws.has_oblique[s] && std::abs(probe.model.mu[s] - current.model.mu[s]) > 1e-3 &&
              std::find(moved.begin(), moved.end(), "mu") == moved.end())
            moved.push_back("mu");
        }
        std::string what;
        for (const auto& m : moved) what += (what.empty() ? "" : " and ") + std::string("a changed ") + m;
        if (what.empty()) what = "the baseline";
        c.identifiability = "indistinguishable from " + what;
        c.confounded_with = what;
      } else {
        c.identifiability = "identified";
      }
      // The free fit, from the better of the two starts.
      Model start = probe.loglik > current.loglik ? probe.model : current.model;
      if (start.effects.find(key) == start.effects.end() || start.effects[key] == 0) start.effects[key] = 0.1 * e.probe;
      std::vector<std::string> free = free_current;
      free.push_back(key);
      Fit f = FitModel(ws, all, start, free);
      if (probe.loglik > f.loglik) {  // the probe point fits better than the local optimum found
        f = FitModel(ws, all, probe.model, free);
      }
      c.fitted = f.ok;
      c.message = f.message;
      c.estimate = f.model.effects[key];
      c.se = f.effect_se.count(key) ? f.effect_se[key] : kNaN;
      c.lr_statistic = std::max(0.0, 2 * (f.loglik - current.loglik));
      c.p_value = 0.5 * stats::ChiSquaredUpperTail(c.lr_statistic, 1);  // boundary at 0
      c.delta_aic = -c.lr_statistic + 2;
      c.delta_bic = -c.lr_statistic + std::log(n_res);
      const CrossValidation cv = CrossValidate(ws, f.model, free, options.folds);
      cvs[key] = cv;
      fits[key] = f;
      c.cv_error = cv.mean_error;
      c.cv_error_current = cv_current.mean_error;
      c.cv_p = PairedImprovementP(cv_current.error, cv.error);
      c.significant = c.identifiability == "identified" && c.p_value < bonferroni && c.cv_error < c.cv_error_current;
      rd.candidates.push_back(c);
    }
    // Rank by the relative fall of the held-out error.
    auto gain = [](const CandidateResult& c) {
      return c.fitted && c.cv_error_current > 0 ? (c.cv_error_current - c.cv_error) / c.cv_error_current : -1e300;
    };
    // Significant candidates first; the measurement effect's held-out error is on other data (the
    // marker distance), so among the rest it comes after the contact effects.
    std::stable_sort(rd.candidates.begin(), rd.candidates.end(), [&](const auto& a, const auto& b) {
      if (a.significant != b.significant) return a.significant;
      if (a.measurement_effect != b.measurement_effect) return !a.measurement_effect;
      return gain(a) > gain(b);
    });
    for (std::size_t i = 0; i < rd.candidates.size(); ++i) rd.candidates[i].rank = static_cast<int>(i) + 1;
    const CandidateResult* best = nullptr;
    for (const auto& c : rd.candidates)
      if (c.significant) {
        best = &c;
        break;
      }
    if (!any_significant) {
      rd.decision = best ? "No significant disagreement to explain: nothing added (" + best->name +
                               " would fit a little better, but the residuals are within the measurement's "
                               "limits)."
                         : "No significant disagreement and no candidate improves the fit significantly: "
                           "nothing added.";
      out.rounds.push_back(rd);
      break;
    }
    if (!best) {
      rd.decision = "Significant disagreement, but no candidate of the library explains it significantly.";
      out.rounds.push_back(rd);
      break;
    }
    rd.accepted = best->key;
    // Look-alikes: other significant candidates whose held-out errors are not worse.
    std::vector<std::string> alike;
    for (const auto& c : rd.candidates) {
      if (&c == best || !c.significant || c.measurement_effect != best->measurement_effect) continue;
      const double p = PairedImprovementP(cvs[c.key].error, cvs[best->key].error);
      if (p > 0.05) alike.push_back(c.key);
    }
    // The gap on held-out trials before and after.
    const CrossValidation& before = best->measurement_effect ? cv_tilt_current : cv_current;
    const CrossValidation& after = cvs[best->key];
    double sb = 0, sa = 0;
    int n = 0;
    for (std::size_t i = 0; i < ws.obs.size(); ++i) {
      const Obs& o = ws.obs[i];
      if (!std::isfinite(Rms(before.residual[i])) || !std::isfinite(Rms(after.residual[i]))) continue;
      GapTrial g;
      g.id = o.trial->spec.id;
      g.surface = ws.surfaces[static_cast<std::size_t>(o.surface)];
      g.angle_deg = o.angle_deg;
      g.speed_m_s = o.speed_m_s;
      g.fold = o.fold;
      g.residual_before = before.residual[i];
      g.residual_after = after.residual[i];
      g.gap_before = Rms(g.residual_before);
      g.gap_after = Rms(g.residual_after);
      for (int c = 0; c < kComponents; ++c)
        if (std::isfinite(g.residual_before[c]) && std::isfinite(g.residual_after[c]))
          sb += g.residual_before[c] * g.residual_before[c], sa += g.residual_after[c] * g.residual_after[c], ++n;
      rd.gap.push_back(g);
    }
    rd.gap_before = n ? std::sqrt(sb / n) : kNaN;
    rd.gap_after = n ? std::sqrt(sa / n) : kNaN;
    rd.gap_shrink = rd.gap_before > 0 ? 1 - rd.gap_after / rd.gap_before : kNaN;
    std::ostringstream d;
    d << "Added " << best->name << " (" << best->parameter << " = " << Fmt(best->estimate) << " +- " << Fmt(best->se)
      << UnitSuffix(best->unit) << "): likelihood ratio " << Fmt(best->lr_statistic) << ", p = " << FmtP(best->p_value)
      << "; held-out error " << Fmt(best->cv_error_current) << " -> " << Fmt(best->cv_error)
      << "; held-out gap " << Fmt(100 * rd.gap_before) << " % -> " << Fmt(100 * rd.gap_after) << " % ("
      << Percent(rd.gap_shrink) << " % smaller).";
    if (!alike.empty()) {
      d << " It cannot be told apart from";
      for (std::size_t i = 0; i < alike.size(); ++i) d << (i ? ", " : " ") << Entry(alike[i]).name;
      d << " with these data.";
    }
    rd.decision = d.str();
    say("  accepted " + best->key);
    accepted.push_back(best->key);
    if (best->measurement_effect) {
      tilt_on = true;
      tilt = tilt_fits[best->key];
    } else {
      current = fits[best->key];
    }
    for (const auto& a : alike) {
      Finding f;
      f.key = a;
      const LibraryEntry& e = Entry(a);
      f.name = e.name;
      f.parameter = e.parameter;
      f.unit = e.unit;
      f.status = "indistinguishable";
      for (const auto& c : rd.candidates)
        if (c.key == a) f.estimate = c.estimate, f.se = c.se;
      f.partner = best->name;
      f.separating_measurement = e.separating_measurement + "; " + Entry(best->key).separating_measurement;
      out.findings.push_back(f);
    }
    Finding f;
    f.key = best->key;
    f.name = best->name;
    f.parameter = best->parameter;
    f.unit = best->unit;
    f.status = alike.empty() ? "named" : "indistinguishable";
    f.estimate = best->estimate;
    f.se = best->se;
    if (!alike.empty()) {
      for (const auto& a : alike) f.partner += (f.partner.empty() ? "" : ", ") + Entry(a).name;
      f.separating_measurement = Entry(best->key).separating_measurement;
    }
    f.gap_shrink = rd.gap_shrink;
    out.findings.push_back(f);
    out.rounds.push_back(rd);
  }

  // The final model's remaining disagreement.
  const auto final_residuals = ws.Residuals(current.model, all);
  const auto final_tests = StructureTests(ws, final_residuals, tilt.tilt_rad, options.alpha, options.marker_ratio_tolerance,
                              options.velocity_tolerance);
  for (const auto& t : final_tests)
    if (t.significant) out.remaining.push_back(t);
  out.unexplained = !out.remaining.empty();
  if (out.unexplained)
    for (auto& f : out.findings)
      if (f.status == "named") f.status = "tentative";
  // Candidates that the final model's own parameters absorb: the probes of the last round, which
  // added nothing, were made against the final model.
  const Round* last = !out.rounds.empty() && out.rounds.back().accepted.empty() ? &out.rounds.back() : nullptr;
  if (last)
    for (const auto& c : last->candidates)
      if (c.identifiability.rfind("indistinguishable from", 0) == 0) {
        Finding f;
        f.key = c.key;
        f.name = c.name;
        f.parameter = c.parameter;
        f.unit = c.unit;
        f.status = "indistinguishable";
        f.estimate = c.estimate;
        f.se = c.se;
        f.partner = c.confounded_with;
        f.separating_measurement = Entry(c.key).separating_measurement;
        out.findings.push_back(f);
      }
  out.final_model = SurfaceFits(ws, current);
  for (const auto& [k, v] : current.model.effects) out.effects[k] = v;
  if (tilt_on) out.effects["out_of_plane"] = tilt.tilt_rad * 180 / std::numbers::pi;
  const auto base_residuals = ws.Residuals(out.rounds.empty() ? current.model : [&] {
    Model m;
    for (const auto& s : out.baseline) m.zeta.push_back(s.zeta), m.mu.push_back(std::isfinite(s.mu) ? s.mu : 0.3);
    return m;
  }(), all);
  for (std::size_t i = 0; i < ws.obs.size(); ++i) {
    const Obs& o = ws.obs[i];
    TrialResiduals r;
    r.id = o.trial->spec.id;
    r.surface = ws.surfaces[static_cast<std::size_t>(o.surface)];
    r.angle_deg = o.angle_deg;
    r.speed_m_s = o.speed_m_s;
    r.baseline = base_residuals[i];
    r.final_model = final_residuals[i];
    r.marker_ratio = o.marker_ratio;
    out.residuals.push_back(r);
  }

  // The verdict in words.
  std::ostringstream v;
  v << "Data: " << ws.obs.size() << " measured trial(s) on " << ws.surfaces.size() << " surface(s)";
  if (skipped) v << " (" << skipped << " skipped: not measured or no surface model)";
  v << ". Baseline: the paper's two-phase model with zeta and mu fitted per surface (k is not identified by "
       "velocities and stays the paper's).\n\n";
  const auto& first = out.rounds.front().tests;
  const auto nsig = std::count_if(first.begin(), first.end(), [](auto& t) { return t.significant; });
  if (nsig == 0) {
    v << "The baseline's residuals show no significant structure (" << first.size()
      << " tests, Holm-adjusted at " << options.alpha << ").\n\n";
  } else {
    v << "The baseline disagrees with the measurements significantly in " << nsig << " of " << first.size()
      << " tests (Holm-adjusted at " << options.alpha << "); the strongest:\n";
    std::vector<const StructureTest*> s;
    for (const auto& t : first)
      if (t.significant) s.push_back(&t);
    std::sort(s.begin(), s.end(), [](auto a, auto b) { return a->p < b->p; });
    for (std::size_t i = 0; i < std::min<std::size_t>(3, s.size()); ++i)
      v << "  - " << s[i]->scope << ": " << s[i]->description << " (" << s[i]->test << " = " << Fmt(s[i]->statistic)
        << ", p = " << FmtP(s[i]->p) << ")\n";
    v << "\n";
  }
  bool any_named = false;
  for (const auto& f : out.findings) {
    if (f.status == "named") {
      any_named = true;
      v << "Named: " << f.name << ", " << f.parameter << " = " << Fmt(f.estimate) << " +- " << Fmt(f.se)
        << UnitSuffix(f.unit) << ". Added to the model, it shrinks the disagreement on held-out trials by "
        << Percent(f.gap_shrink) << " %, and no significant disagreement remains.\n";
    } else if (f.status == "tentative") {
      v << "Tentative: " << f.name << ", " << f.parameter << " = " << Fmt(f.estimate) << " +- " << Fmt(f.se)
        << UnitSuffix(f.unit) << ", improves the fit significantly (held-out gap " << Percent(f.gap_shrink)
        << " % smaller) but does not account for all the disagreement.\n";
    } else if (f.status == "indistinguishable") {
      v << "Cannot be told apart with these data: " << f.name << " and " << f.partner
        << ". A measurement that would separate them: " << f.separating_measurement << ".\n";
    }
  }
  if (out.unexplained) {
    v << "\nUnexplained disagreement: with ";
    v << (accepted.empty() ? "the baseline" : "the effects above added");
    v << ", " << out.remaining.size() << " test(s) remain significant, and no effect in the library explains them:\n";
    for (std::size_t i = 0; i < std::min<std::size_t>(3, out.remaining.size()); ++i)
      v << "  - " << out.remaining[i].scope << ": " << out.remaining[i].description << " (p = "
        << FmtP(out.remaining[i].p) << ")\n";
    v << "The model lacks something outside the library; no effect is named with confidence.\n";
  } else if (!any_named) {
    v << (nsig == 0 ? "Nothing is named: the baseline explains these data within their scatter.\n"
                    : "Nothing is named.\n");
  }
  std::vector<std::string> untested;
  for (const auto& c : (last ? *last : out.rounds.front()).candidates)
    if (c.identifiability == "not tested by these data") untested.push_back(c.name);
  if (!untested.empty()) {
    v << "\nNot tested by these data (no trial is sensitive to them): ";
    for (std::size_t i = 0; i < untested.size(); ++i) v << (i ? "; " : "") << untested[i];
    v << ".\n";
  }
  out.verdict = v.str();
  out.simulations = ws.simulations.load();
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.success = true;
  return out;
}

}  // namespace hoof::discovery
