#include "dynamics/contact_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include <ceres/ceres.h>
#include <boost/math/distributions/students_t.hpp>

#include "core/frames.h"
#include "dynamics/impact_simulator.h"

namespace hoof::dynamics {
namespace {

[[noreturn]] void ThrowField(std::string_view field, double value, std::string_view why) {
  std::ostringstream os;
  os << "fit options." << field << " = " << value << " is invalid: " << why;
  throw std::invalid_argument(os.str());
}

/// Tight integration so that numeric derivatives of the residuals are clean.
SimulatorOptions FitSimulatorOptions(double gravity_m_s2) {
  SimulatorOptions o;
  o.relative_tolerance = 1e-10;
  o.gravity_m_s2 = gravity_m_s2;
  return o;
}

/// Post-impact normal speed of C for a normal impact at `v_before` with contact (k, b).
double SimulatedRebound(const SpecimenParameters& specimen, double k, double b, double v_before,
                        double gravity_m_s2) {
  const ImpactSimulator sim(specimen, ContactParameters{k, b, 0.0},
                            FitSimulatorOptions(gravity_m_s2));
  const ImpactResult r = sim.Simulate(ImpactConditions::Paper(v_before, 0.0));
  if (!r.success) throw std::runtime_error("simulation failed in the fit: " + r.message);
  return r.at_separation.v_SC.y();
}

/// Percentage errors of the simulated rebound for all impacts at (k, b).
std::vector<double> PercentErrors(const std::vector<NormalImpact>& impacts,
                                  const SpecimenParameters& specimen, double k, double b,
                                  double g) {
  std::vector<double> out;
  out.reserve(impacts.size());
  for (const auto& imp : impacts) {
    const double v = SimulatedRebound(specimen, k, b, imp.v_before_m_s, g);
    out.push_back(100.0 * (v - imp.v_after_m_s) / imp.v_after_m_s);
  }
  return out;
}

double MeanAbs(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += std::abs(x);
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}

/// Residual of one impact as a function of zeta at fixed k: the percentage error.
struct PercentErrorResidual {
  const SpecimenParameters* specimen;
  NormalImpact impact;
  double k;
  double g;
  bool operator()(const double* zeta, double* residual) const {
    const double b = DampingForRatio(zeta[0], k, specimen->mass_kg);
    const double v = SimulatedRebound(*specimen, k, b, impact.v_before_m_s, g);
    residual[0] = 100.0 * (v - impact.v_after_m_s) / impact.v_after_m_s;
    return true;
  }
};

struct ZetaFit {
  bool ok = false;
  std::string message;
  double zeta = 0.0;
  double jtj = 0.0;  // J^T J of the percentage residuals w.r.t. zeta
  double ssr = 0.0;  // sum of squared percentage residuals
};

/// Least-squares fit of zeta at fixed k with Ceres, starting from the closed form of the mean
/// restitution.
ZetaFit FitZetaAtK(const std::vector<NormalImpact>& impacts, const SpecimenParameters& specimen,
                   double k, double g) {
  double e_mean = 0.0;
  for (const auto& imp : impacts) e_mean += imp.v_after_m_s / imp.v_before_m_s;
  e_mean /= static_cast<double>(impacts.size());
  double zeta = DampingRatioFromRestitution(std::clamp(e_mean, 0.05, 1.0));

  ceres::Problem problem;
  for (const auto& imp : impacts) {
    auto* cost = new ceres::NumericDiffCostFunction<PercentErrorResidual, ceres::CENTRAL, 1, 1>(
        new PercentErrorResidual{&specimen, imp, k, g});
    problem.AddResidualBlock(cost, nullptr, &zeta);
  }
  problem.SetParameterLowerBound(&zeta, 0, 0.0);
  problem.SetParameterUpperBound(&zeta, 0, 5.0);
  ceres::Solver::Options opts;
  opts.linear_solver_type = ceres::DENSE_QR;
  opts.max_num_iterations = 100;
  opts.function_tolerance = 1e-14;
  opts.parameter_tolerance = 1e-12;
  opts.gradient_tolerance = 1e-14;
  opts.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(opts, &problem, &summary);

  ZetaFit fit;
  fit.zeta = zeta;
  if (!summary.IsSolutionUsable()) {
    fit.message = "Ceres did not converge: " + summary.message;
    return fit;
  }
  // Jacobian at the solution, for the standard error.
  ceres::Problem::EvaluateOptions eval;
  double cost = 0.0;
  std::vector<double> residuals;
  ceres::CRSMatrix jac;
  problem.Evaluate(eval, &cost, &residuals, nullptr, &jac);
  for (double v : jac.values) fit.jtj += v * v;
  fit.ssr = 2.0 * cost;
  fit.ok = true;
  return fit;
}

std::vector<double> LogSpace(double lo, double hi, int n) {
  std::vector<double> out(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const double f = n == 1 ? 0.0 : static_cast<double>(i) / (n - 1);
    out[static_cast<std::size_t>(i)] = std::exp(std::log(lo) + f * (std::log(hi) - std::log(lo)));
  }
  out.front() = lo;  // exact ends
  out.back() = hi;
  return out;
}

}  // namespace

void ContactFitOptions::Validate() const {
  if (!(k_min_N_m > 0 && std::isfinite(k_min_N_m))) ThrowField("k_min_N_m", k_min_N_m, "> 0");
  if (!(k_max_N_m > k_min_N_m && std::isfinite(k_max_N_m)))
    ThrowField("k_max_N_m", k_max_N_m, "must be finite and > k_min_N_m");
  if (!(b_min_N_s_m >= 0)) ThrowField("b_min_N_s_m", b_min_N_s_m, "must be >= 0");
  if (!(b_max_N_s_m > b_min_N_s_m && std::isfinite(b_max_N_s_m)))
    ThrowField("b_max_N_s_m", b_max_N_s_m, "must be finite and > b_min_N_s_m");
  if (!(k_reference_N_m > 0 && std::isfinite(k_reference_N_m)))
    ThrowField("k_reference_N_m", k_reference_N_m, "must be finite and > 0");
  if (!(confidence > 0 && confidence < 1))
    ThrowField("confidence", confidence, "must be in (0, 1)");
  if (valley_points < 2) ThrowField("valley_points", valley_points, "must be >= 2");
  if (map_points_k == 1 || map_points_k < 0)
    ThrowField("map_points_k", map_points_k, "must be 0 or >= 2");
  if (map_points_b == 1 || map_points_b < 0)
    ThrowField("map_points_b", map_points_b, "must be 0 or >= 2");
  if (!(gravity_m_s2 >= 0 && std::isfinite(gravity_m_s2)))
    ThrowField("gravity_m_s2", gravity_m_s2, "must be finite and >= 0");
}

namespace {

/// Throws std::invalid_argument naming the first impact whose speeds are not finite and > 0.
void CheckImpacts(const std::vector<NormalImpact>& impacts) {
  for (std::size_t i = 0; i < impacts.size(); ++i) {
    const auto& imp = impacts[i];
    if (!(imp.v_before_m_s > 0 && std::isfinite(imp.v_before_m_s)) ||
        !(imp.v_after_m_s > 0 && std::isfinite(imp.v_after_m_s))) {
      std::ostringstream os;
      os << "normal impact " << i
         << ": speeds must be finite and > 0 (v_before_m_s = " << imp.v_before_m_s
         << ", v_after_m_s = " << imp.v_after_m_s << ")";
      throw std::invalid_argument(os.str());
    }
  }
}

/// zeta at the reference k, its s.e. and confidence interval, and the errors of the fit; false
/// (with the message in `s`) when it fails.
bool FitZetaAtReference(const std::vector<NormalImpact>& impacts,
                        const SpecimenParameters& specimen, const ContactFitOptions& options,
                        ContactFitSummary& s) {
  const double g = options.gravity_m_s2;
  const double m = specimen.mass_kg;
  const ZetaFit ref = FitZetaAtK(impacts, specimen, options.k_reference_N_m, g);
  if (!ref.ok) {
    s.message = ref.message;
    return false;
  }
  s.zeta = ref.zeta;
  s.e_normal = s.zeta < 1.0 ? RestitutionFromDampingRatio(s.zeta) : 0.0;
  const double b_ref = DampingForRatio(s.zeta, options.k_reference_N_m, m);
  const std::vector<double> errs =
      PercentErrors(impacts, specimen, options.k_reference_N_m, b_ref, g);
  s.mpe_percent = MeanAbs(errs);
  s.rms_percent = std::sqrt(ref.ssr / s.n);
  if (s.n >= 2 && ref.jtj > 0) {
    const int dof = s.n - 1;
    s.zeta_se = std::sqrt(ref.ssr / dof / ref.jtj);
    const boost::math::students_t t_dist(dof);
    const double t =
        boost::math::quantile(boost::math::complement(t_dist, (1 - options.confidence) / 2));
    s.zeta_ci_low = std::max(0.0, s.zeta - t * s.zeta_se);
    s.zeta_ci_high = s.zeta + t * s.zeta_se;
  } else {
    s.zeta_se = s.zeta_ci_low = s.zeta_ci_high = core::kNaN;
  }
  return true;
}

/// The valley: the best b at each k of a log-spaced grid, and how little zeta and the error
/// change along it within the bounds of b.
void FitValley(const std::vector<NormalImpact>& impacts, const SpecimenParameters& specimen,
               const ContactFitOptions& options, ContactFitSummary& s) {
  const double g = options.gravity_m_s2;
  const double m = specimen.mass_kg;
  double mean_v = 0.0;
  for (const auto& imp : impacts) mean_v += imp.v_before_m_s;
  mean_v /= s.n;
  double zmin = std::numeric_limits<double>::infinity(), zmax = -zmin;
  double emin = zmin, emax = -zmin;
  s.valley_k_min_N_m = std::numeric_limits<double>::infinity();
  s.valley_k_max_N_m = 0.0;
  for (double k : LogSpace(options.k_min_N_m, options.k_max_N_m, options.valley_points)) {
    const ZetaFit f = FitZetaAtK(impacts, specimen, k, g);
    ValleyPoint p;
    p.k_N_m = k;
    p.zeta = f.zeta;
    p.b_N_s_m = DampingForRatio(f.zeta, k, m);
    p.mpe_percent = MeanAbs(PercentErrors(impacts, specimen, k, p.b_N_s_m, g));
    const ImpactSimulator sim(specimen, ContactParameters{k, p.b_N_s_m, 0.0},
                              FitSimulatorOptions(g));
    p.contact_duration_s = sim.Simulate(ImpactConditions::Paper(mean_v, 0.0)).t_separation_s;
    p.within_bounds = f.ok && p.b_N_s_m >= options.b_min_N_s_m && p.b_N_s_m <= options.b_max_N_s_m;
    if (p.within_bounds) {
      zmin = std::min(zmin, p.zeta);
      zmax = std::max(zmax, p.zeta);
      emin = std::min(emin, p.mpe_percent);
      emax = std::max(emax, p.mpe_percent);
      s.valley_k_min_N_m = std::min(s.valley_k_min_N_m, k);
      s.valley_k_max_N_m = std::max(s.valley_k_max_N_m, k);
    }
    s.valley.push_back(p);
  }
  s.valley_zeta_spread = zmax >= zmin ? zmax - zmin : 0.0;
  s.valley_mpe_spread_percent = emax >= emin ? emax - emin : 0.0;
}

/// The paper's objective (the mean absolute percent error) over the (k, b) box, where asked.
void MapObjective(const std::vector<NormalImpact>& impacts, const SpecimenParameters& specimen,
                  const ContactFitOptions& options, ContactFitSummary& s) {
  const double g = options.gravity_m_s2;
  if (options.map_points_k > 0 && options.map_points_b > 0) {
    s.map_k_N_m = LogSpace(options.k_min_N_m, options.k_max_N_m, options.map_points_k);
    for (int j = 0; j < options.map_points_b; ++j)
      s.map_b_N_s_m.push_back(options.b_min_N_s_m + (options.b_max_N_s_m - options.b_min_N_s_m) *
                                                        j / (options.map_points_b - 1));
    s.map_mpe_percent.resize(options.map_points_k, options.map_points_b);
    for (int i = 0; i < options.map_points_k; ++i)
      for (int j = 0; j < options.map_points_b; ++j)
        s.map_mpe_percent(i, j) =
            MeanAbs(PercentErrors(impacts, specimen, s.map_k_N_m[static_cast<std::size_t>(i)],
                                  s.map_b_N_s_m[static_cast<std::size_t>(j)], g));
  }
}

}  // namespace

ContactFitSummary FitNormalContact(const std::vector<NormalImpact>& impacts,
                                   const SpecimenParameters& specimen,
                                   const ContactFitOptions& options) {
  options.Validate();
  specimen.Validate();
  CheckImpacts(impacts);
  ContactFitSummary s;
  s.n = static_cast<int>(impacts.size());
  if (impacts.empty()) {
    s.message = "no normal impacts to fit";
    return s;
  }
  // 1. zeta, at the reference k.
  if (!FitZetaAtReference(impacts, specimen, options, s)) return s;
  // 2. The valley: the best b at each k.
  FitValley(impacts, specimen, options, s);
  // 3. The paper's objective over the (k, b) box.
  MapObjective(impacts, specimen, options, s);
  s.success = true;
  return s;
}

std::string ContactFitSummary::Explanation() const {
  std::ostringstream os;
  os.precision(4);
  if (!success) return "The contact law could not be fitted: " + message;
  os << "Post-impact velocities determine the damping ratio zeta = b / (2 sqrt(k m)) alone: "
     << "zeta = " << zeta;
  if (std::isfinite(zeta_se))
    os << " (95 % interval " << zeta_ci_low << " to " << zeta_ci_high << ", n = " << n << ")";
  os << ", which gives e = " << e_normal << " for a normal impact without gravity.\n";
  os << "The stiffness k is NOT identified by velocities: along the valley b = 2 zeta sqrt(k m), "
     << "k from " << valley_k_min_N_m << " to " << valley_k_max_N_m
     << " N/m fits equally well (the mean percentage error changes by only "
     << valley_mpe_spread_percent << " percentage points, and zeta by " << valley_zeta_spread
     << "). k sets only the contact duration";
  if (!valley.empty())
    os << " (" << valley.back().contact_duration_s * 1e6 << " us at k = " << valley.back().k_N_m
       << " N/m to " << valley.front().contact_duration_s * 1e6
       << " us at k = " << valley.front().k_N_m << " N/m)";
  os << ", and a contact shorter than a frame period (125 us at 8000 fps) cannot be seen in "
     << "the frames; measuring k needs the contact time (force plate, accelerometer, "
     << "oscilloscope). Any single (k, b) printed from this fit is one point of the valley, "
     << "not a measurement.";
  return os.str();
}

}  // namespace hoof::dynamics
