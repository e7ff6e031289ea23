#include "kinematics/impact_kinematics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include <Eigen/Dense>
#include <boost/math/distributions/students_t.hpp>

#include "core/frames.h"

namespace hoof::kinematics {
namespace {

/// Slowest normal speed of E (m/s) that counts as coming down onto, or rising from, a surface.
constexpr double kMinImpactSpeed_m_s = 0.05;

Eigen::Vector2d CentreOfMass(const PoseSample& p, double d) {
  return p.p_WE + d * core::BodyRotation(p.theta_W_rad).x_B();
}

/// Weighted-free linear least squares y = a + b tau; returns (a, b), the residual sum of
/// squares, and (X^T X)^-1.
struct LineFit {
  double a = 0, b = 0, ssr = 0;
  Eigen::Matrix2d inv_xtx = Eigen::Matrix2d::Zero();
};
LineFit FitLine(const std::vector<double>& tau, const std::vector<double>& y) {
  Eigen::Matrix2d xtx = Eigen::Matrix2d::Zero();
  Eigen::Vector2d xty = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < tau.size(); ++i) {
    const Eigen::Vector2d x{1.0, tau[i]};
    xtx += x * x.transpose();
    xty += x * y[i];
  }
  LineFit f;
  f.inv_xtx = xtx.inverse();
  const Eigen::Vector2d ab = f.inv_xtx * xty;
  f.a = ab(0);
  f.b = ab(1);
  for (std::size_t i = 0; i < tau.size(); ++i) f.ssr += std::pow(y[i] - f.a - f.b * tau[i], 2);
  return f;
}

/// Fits frames [idx] with the parabola for C and a line for theta, about t_ref.
FlightFit FitFlight(const std::vector<PoseSample>& poses, const std::vector<int>& idx, double t_ref,
                    const core::SpecimenParameters& body, double g) {
  std::vector<double> tau, x, y, th;
  for (int i : idx) {
    const PoseSample& p = poses[static_cast<std::size_t>(i)];
    const double t = p.t_s - t_ref;
    const Eigen::Vector2d c = CentreOfMass(p, body.d_EC_m);
    tau.push_back(t);
    x.push_back(c.x());
    y.push_back(c.y() + 0.5 * g * t * t);  // remove the known gravity term (g along -y)
    th.push_back(p.theta_W_rad);
  }
  // Unwrap the angle.
  for (std::size_t i = 1; i < th.size(); ++i)
    th[i] -= 2 * std::numbers::pi * std::round((th[i] - th[i - 1]) / (2 * std::numbers::pi));
  const LineFit fx = FitLine(tau, x), fy = FitLine(tau, y), ft = FitLine(tau, th);
  const double n = static_cast<double>(idx.size());
  const double s2 = (fx.ssr + fy.ssr) / (2 * n - 4);  // pooled: marker noise is isotropic
  const double s2t = ft.ssr / (n - 2);
  FlightFit f;
  f.first_frame = idx.front();
  f.last_frame = idx.back();
  f.n = static_cast<int>(idx.size());
  f.p_WC = {fx.a, fy.a};
  f.v_WC = {fx.b, fy.b};
  f.cov_v_WC = s2 * fx.inv_xtx(1, 1) * Eigen::Matrix2d::Identity();
  f.theta_W_rad = ft.a;
  f.w_rad_s = ft.b;
  f.w_se_rad_s = std::sqrt(s2t * ft.inv_xtx(1, 1));
  f.theta_se_rad = std::sqrt(s2t * ft.inv_xtx(0, 0));
  f.rms_residual_m = std::sqrt((fx.ssr + fy.ssr) / n);
  f.rms_theta_residual_rad = std::sqrt(ft.ssr / n);
  return f;
}

/// Moves a fit's reference time: v(t) = v(t_ref) + g (t - t_ref), theta and p likewise.
FlightFit Shift(FlightFit f, double dt, double g) {
  f.p_WC += f.v_WC * dt + Eigen::Vector2d(0, -0.5 * g * dt * dt);
  f.v_WC += Eigen::Vector2d(0, -g * dt);
  f.theta_W_rad += f.w_rad_s * dt;
  return f;
}

/// Height of the contact point T above a surface through the origin, along y_S, at time t
/// (relative to the fit's reference time) for a flight fit.
double HeightOfT(const FlightFit& f, double t, const core::SurfaceRotation& S,
                 const core::SpecimenParameters& body, double g) {
  const Eigen::Vector2d c = f.p_WC + f.v_WC * t + Eigen::Vector2d(0, -0.5 * g * t * t);
  const core::BodyRotation R_WB(f.theta_W_rad + f.w_rad_s * t);
  const Eigen::Vector2d e = c - body.d_EC_m * R_WB.x_B();
  return S.y_S().dot(e) - body.end_radius_m;
}

/// Velocity of the body point at T: v_C + w x (p_T - p_C), with p_T = p_E - R y_S.
Eigen::Vector2d ContactPointVelocity(const Eigen::Vector2d& v_WC, double w, double theta,
                                     const core::SurfaceRotation& S,
                                     const core::SpecimenParameters& body) {
  const Eigen::Vector2d r =
      -body.d_EC_m * core::BodyRotation(theta).x_B() - body.end_radius_m * S.y_S();
  return v_WC + w * Eigen::Vector2d(-r.y(), r.x());
}

/// (e, mu_eff) from the parameters (vb_x, vb_y, wb, thb, va_x, va_y, wa, tha) in W.
Eigen::Vector2d Measures(const Eigen::Matrix<double, 8, 1>& q, const core::SurfaceRotation& S,
                         const core::SpecimenParameters& body) {
  const Eigen::Vector2d vb{q(0), q(1)}, va{q(4), q(5)};
  const Eigen::Vector2d tb = ContactPointVelocity(vb, q(2), q(3), S, body);
  const Eigen::Vector2d ta = ContactPointVelocity(va, q(6), q(7), S, body);
  const double e = std::abs(S.y_S().dot(ta) / S.y_S().dot(tb));
  const Eigen::Vector2d dv = S.ToS(va - vb);
  return {e, std::abs(dv.x() / dv.y())};
}

/// Height of E along the surface normal in frame `i`.
double Height(const std::vector<PoseSample>& poses, const core::SurfaceRotation& S, int i) {
  return S.y_S().dot(poses[static_cast<std::size_t>(i)].p_WE);
}

/// Normal velocity of E between frames `a` and `b` (finite difference).
double NormalVelocity(const std::vector<PoseSample>& poses, const core::SurfaceRotation& S, int a,
                      int b) {
  return (Height(poses, S, b) - Height(poses, S, a)) /
         (poses[static_cast<std::size_t>(b)].t_s - poses[static_cast<std::size_t>(a)].t_s);
}

/// The first frame, after the impact at valid[lowest], where the normal velocity reverses
/// suddenly again: a descent (within 3 s.d. of the positions' noise, from their covariance where
/// known) that turns up by more than 0.3 of the impact's `jump` and by more than 3 s.d. of the
/// change: a second bounce; -1 when none.
int SecondBounce(const std::vector<PoseSample>& poses, const std::vector<int>& valid,
                 std::size_t lowest, const core::SurfaceRotation& S, double jump) {
  // The variance of the height in frame i along the normal, from its covariance (0 unknown).
  const auto var_h = [&](int i) {
    const Eigen::Vector2d n = S.y_S();
    return n.dot(poses[static_cast<std::size_t>(i)].cov_p_WE * n);
  };
  const auto dt = [&](int i, int j) {
    return poses[static_cast<std::size_t>(j)].t_s - poses[static_cast<std::size_t>(i)].t_s;
  };
  for (std::size_t j = lowest + 3; j + 1 < valid.size(); ++j) {
    const int a = valid[j - 1], b = valid[j], c = valid[j + 1];
    const double v_in = NormalVelocity(poses, S, a, b);
    const double rise = NormalVelocity(poses, S, b, c) - v_in;
    // The two differences' noise: heights a, b, c with b in both.
    const double h_ab = dt(a, b), h_bc = dt(b, c);
    const double var_in = (var_h(a) + var_h(b)) / (h_ab * h_ab);
    const double var_rise = var_h(a) / (h_ab * h_ab) + var_h(c) / (h_bc * h_bc) +
                            var_h(b) * std::pow(1 / h_ab + 1 / h_bc, 2);
    // A bounce reverses a descent, by more than the noise of the positions.
    if (rise > 0.3 * jump && rise > 3 * std::sqrt(var_rise) && v_in < 3 * std::sqrt(var_in))
      return b;
  }
  return -1;
}

/// The flight fits before and after the impact near frame `i_min` (starting at time `t_imp`),
/// their windows placed about the time where the fits meet, three times. Fills k.before,
/// k.after and the impact time; false with k.message when the frames or the fits do not allow.
/// Only frames after `t_from` may serve before the impact, and only frames before `t_to` after it
/// (the neighbouring impacts' contacts; infinite for a clip's only impact).
bool FitAroundImpact(const std::vector<PoseSample>& poses, const std::vector<int>& valid, int i_min,
                     int bounce_frame, double t_imp, double exposure,
                     const core::SurfaceRotation& S, const core::SpecimenParameters& body,
                     const KinematicsOptions& options, ImpactKinematics& k,
                     double t_from = -std::numeric_limits<double>::infinity(),
                     double t_to = std::numeric_limits<double>::infinity()) {
  const double g = options.gravity_m_s2;
  for (int iteration = 0; iteration < 3; ++iteration) {
    const double excl_lo = t_imp - options.max_contact_s - 0.5 * exposure;
    const double excl_hi = t_imp + options.max_contact_s + 0.5 * exposure;
    std::vector<int> before, after;
    for (int i : valid) {
      const double t = poses[static_cast<std::size_t>(i)].t_s;
      if (t < excl_lo && t > t_from) before.push_back(i);
      if (t > excl_hi && t < t_to && (bounce_frame < 0 || i < bounce_frame - 1)) after.push_back(i);
    }
    if (static_cast<int>(before.size()) > options.fit_frames)
      before.erase(before.begin(), before.end() - options.fit_frames);
    if (static_cast<int>(after.size()) > options.fit_frames)
      after.resize(static_cast<std::size_t>(options.fit_frames));
    if (static_cast<int>(before.size()) < options.min_fit_frames ||
        static_cast<int>(after.size()) < options.min_fit_frames) {
      std::ostringstream os;
      os << "too few free-flight frames around the impact near frame " << i_min << ": "
         << before.size() << " before and " << after.size() << " after (need "
         << options.min_fit_frames << ")";
      k.message = os.str();
      return false;
    }
    k.before = FitFlight(poses, before, t_imp, body, g);
    k.after = FitFlight(poses, after, t_imp, body, g);
    // Bisection for h_before(t) = h_after(t) between the two windows.
    double lo = poses[static_cast<std::size_t>(before.back())].t_s - t_imp;
    double hi = poses[static_cast<std::size_t>(after.front())].t_s - t_imp;
    auto f = [&](double t) {
      return HeightOfT(k.before, t, S, body, g) - HeightOfT(k.after, t, S, body, g);
    };
    if (!(f(lo) > 0 && f(hi) < 0)) {
      k.message = "the fits before and after the impact near frame " + std::to_string(i_min) +
                  " do not cross: the motion is not a single bounce";
      return false;
    }
    for (int it = 0; it < 200 && hi - lo > 1e-12; ++it) {
      const double mid = 0.5 * (lo + hi);
      (f(mid) > 0 ? lo : hi) = mid;
    }
    const double shift = 0.5 * (lo + hi);
    k.before = Shift(k.before, shift, g);
    k.after = Shift(k.after, shift, g);
    t_imp += shift;
  }
  k.impact_time_s = t_imp;
  return true;
}

/// The velocities and spins of k.before and k.after in S, with their standard errors, and
/// the contact point's velocities.
void VelocitiesInS(const core::SurfaceRotation& S, const core::SpecimenParameters& body,
                   ImpactKinematics& k) {
  const Eigen::Matrix2d R_SW = S.R_SW();
  k.v_SC_before = S.ToS(k.before.v_WC);
  k.v_SC_after = S.ToS(k.after.v_WC);
  const Eigen::Matrix2d cb = R_SW * k.before.cov_v_WC * R_SW.transpose();
  const Eigen::Matrix2d ca = R_SW * k.after.cov_v_WC * R_SW.transpose();
  k.v_SC_before_se = cb.diagonal().cwiseSqrt();
  k.v_SC_after_se = ca.diagonal().cwiseSqrt();
  k.w_before_rad_s = k.before.w_rad_s;
  k.w_after_rad_s = k.after.w_rad_s;
  k.w_before_se_rad_s = k.before.w_se_rad_s;
  k.w_after_se_rad_s = k.after.w_se_rad_s;
  k.v_ST_before =
      S.ToS(ContactPointVelocity(k.before.v_WC, k.before.w_rad_s, k.before.theta_W_rad, S, body));
  k.v_ST_after =
      S.ToS(ContactPointVelocity(k.after.v_WC, k.after.w_rad_s, k.after.theta_W_rad, S, body));
}

/// e and mu_eff, with the delta method over the eight fitted quantities, their intervals at
/// `confidence` (Student's t), and the kinetic energies.
void RestitutionAndFriction(const core::SurfaceRotation& S, const core::SpecimenParameters& body,
                            double confidence, ImpactKinematics& k) {
  Eigen::Matrix<double, 8, 1> q;
  q << k.before.v_WC, k.before.w_rad_s, k.before.theta_W_rad, k.after.v_WC, k.after.w_rad_s,
      k.after.theta_W_rad;
  Eigen::Matrix<double, 8, 8> cov = Eigen::Matrix<double, 8, 8>::Zero();
  cov.block<2, 2>(0, 0) = k.before.cov_v_WC;
  cov(2, 2) = std::pow(k.before.w_se_rad_s, 2);
  cov(3, 3) = std::pow(k.before.theta_se_rad, 2);
  cov.block<2, 2>(4, 4) = k.after.cov_v_WC;
  cov(6, 6) = std::pow(k.after.w_se_rad_s, 2);
  cov(7, 7) = std::pow(k.after.theta_se_rad, 2);
  const Eigen::Vector2d m0 = Measures(q, S, body);
  Eigen::Matrix<double, 2, 8> J;
  for (int i = 0; i < 8; ++i) {
    const double h = 1e-6 * std::max(1.0, std::abs(q(i)));
    Eigen::Matrix<double, 8, 1> qp = q, qm = q;
    qp(i) += h;
    qm(i) -= h;
    J.col(i) = (Measures(qp, S, body) - Measures(qm, S, body)) / (2 * h);
  }
  const Eigen::Matrix2d cov_m = J * cov * J.transpose();
  k.e = m0(0);
  k.mu_eff = m0(1);
  k.e_se = std::sqrt(cov_m(0, 0));
  k.mu_eff_se = std::sqrt(cov_m(1, 1));
  const int dof = std::max(1, k.before.n + k.after.n - 4);
  const double t_q = boost::math::quantile(
      boost::math::complement(boost::math::students_t(dof), 0.5 * (1 - confidence)));
  k.e_ci_low = k.e - t_q * k.e_se;
  k.e_ci_high = k.e + t_q * k.e_se;
  k.mu_eff_ci_low = std::max(0.0, k.mu_eff - t_q * k.mu_eff_se);
  k.mu_eff_ci_high = k.mu_eff + t_q * k.mu_eff_se;
  k.kinetic_energy_before_J = 0.5 * body.mass_kg * k.before.v_WC.squaredNorm() +
                              0.5 * body.inertia_kg_m2 * std::pow(k.before.w_rad_s, 2);
  k.kinetic_energy_after_J = 0.5 * body.mass_kg * k.after.v_WC.squaredNorm() +
                             0.5 * body.inertia_kg_m2 * std::pow(k.after.w_rad_s, 2);
}

/// The impact frame, velocities in S, e and mu_eff of k, whose fits FitAroundImpact made.
void Finish(double fps, double surface_angle_deg, const core::SurfaceRotation& S,
            const core::SpecimenParameters& body, const KinematicsOptions& options,
            ImpactKinematics& k) {
  k.impact_frame = static_cast<int>(std::floor(k.impact_time_s * fps));
  k.surface_angle_W_deg = surface_angle_deg;
  k.limits.samples_before = k.before.n;
  k.limits.samples_after = k.after.n;
  VelocitiesInS(S, body, k);
  RestitutionAndFriction(S, body, options.confidence, k);
  // On a level surface (a normal impact) nothing drives the body along it: the change of v_x
  // is the tracker's noise, and their ratio measures no friction. mu_eff is not defined there,
  // and is NaN with its s.e. and interval, as every quantity not measured (the paper measures it
  // on oblique impacts only).
  if (surface_angle_deg == 0.0)
    k.mu_eff = k.mu_eff_se = k.mu_eff_ci_low = k.mu_eff_ci_high = core::kNaN;
  k.success = true;
}

}  // namespace

const char* KinematicsMethodName(KinematicsMethod m) {
  switch (m) {
    case KinematicsMethod::kAuto:
      return "auto";
    case KinematicsMethod::kWindows:
      return "windows";
    case KinematicsMethod::kArcs:
      return "arcs";
  }
  return "?";
}

KinematicsMethod ParseKinematicsMethod(const std::string& name) {
  for (auto m : {KinematicsMethod::kAuto, KinematicsMethod::kWindows, KinematicsMethod::kArcs})
    if (name == KinematicsMethodName(m)) return m;
  throw std::invalid_argument("kinematics method \"" + name +
                              "\" is invalid: auto, windows or arcs");
}

void KinematicsOptions::Validate() const {
  if (fit_frames < 3) throw std::invalid_argument("kinematics fit_frames must be >= 3");
  if (min_fit_frames < 3) throw std::invalid_argument("kinematics min_fit_frames must be >= 3");
  if (fit_frames > 100000) throw std::invalid_argument("kinematics fit_frames must be <= 100000");
  if (!(max_contact_s >= 0 && max_contact_s <= 1))
    throw std::invalid_argument("kinematics max_contact_s must be in [0, 1] s");
  if (!(std::isfinite(exposure_s) && exposure_s <= 1))
    throw std::invalid_argument("kinematics exposure_s must be <= 1 s (< 0: one frame period)");
  if (!(gravity_m_s2 >= 0)) throw std::invalid_argument("kinematics gravity_m_s2 must be >= 0");
  if (!(confidence > 0 && confidence < 1))
    throw std::invalid_argument("kinematics confidence must be in (0, 1)");
  arcs.Validate();
}

ImpactKinematics MeasureImpact(const std::vector<PoseSample>& poses, double fps,
                               double surface_angle_deg, const core::SpecimenParameters& body,
                               const KinematicsOptions& options) {
  options.Validate();
  if (!(fps > 0)) throw std::invalid_argument("fps must be > 0");
  ImpactKinematics k;
  const auto S = core::SurfaceRotation::FromDegrees(surface_angle_deg);
  const double dt = 1.0 / fps;
  const double exposure = options.exposure_s < 0 ? dt : options.exposure_s;

  // The frames with a pose, and the lowest of them along the surface normal.
  std::vector<int> valid;
  for (std::size_t i = 0; i < poses.size(); ++i)
    if (poses[i].valid) valid.push_back(static_cast<int>(i));
  if (static_cast<int>(valid.size()) < 2 * options.min_fit_frames + 1) {
    k.message = "too few frames with a body pose (" + std::to_string(valid.size()) + ")";
    return k;
  }
  std::size_t lowest = 0;
  for (std::size_t j = 1; j < valid.size(); ++j)
    if (Height(poses, S, valid[j]) < Height(poses, S, valid[lowest])) lowest = j;
  const int i_min = valid[lowest];
  const int frames_before = static_cast<int>(lowest);
  const int frames_after = static_cast<int>(valid.size() - 1 - lowest);
  // A real impact: the end comes down before the lowest frame and goes back up after it.
  const double v_down =
      frames_before >= 2 ? NormalVelocity(poses, S, valid[lowest - 2], valid[lowest]) : 0.0;
  const double v_up =
      frames_after >= 2 ? NormalVelocity(poses, S, valid[lowest], valid[lowest + 2]) : 0.0;
  if (frames_before < options.min_fit_frames || frames_after < options.min_fit_frames ||
      !(v_down < -kMinImpactSpeed_m_s) || !(v_up > kMinImpactSpeed_m_s)) {
    std::ostringstream os;
    os << "no impact found: the body comes nearest the surface at frame " << i_min << " of "
       << poses.size() << ", and it does not come down before it and rebound after it with "
       << options.min_fit_frames << " or more frames on each side";
    k.message = os.str();
    k.no_impact = true;
    return k;
  }
  k.lowest_frame = i_min;
  const int bounce_frame = SecondBounce(poses, valid, lowest, S, v_up - v_down);
  if (bounce_frame >= 0) {
    k.flags.push_back("second_bounce");
    k.warnings.push_back("a second bounce near frame " + std::to_string(bounce_frame) +
                         "; frames from there on are left out of the fit after the impact");
  }
  if (!FitAroundImpact(poses, valid, i_min, bounce_frame,
                       poses[static_cast<std::size_t>(i_min)].t_s, exposure, S, body, options, k))
    return k;
  Finish(fps, surface_angle_deg, S, body, options, k);
  return k;
}

namespace {

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

/// The noise s.d. of E's height (m), from the second differences over runs of consecutive
/// frames: robust (median absolute deviation about their median, which is gravity's), and for
/// white noise of s.d. sigma they have s.d. sqrt(6) sigma. 0 when there are fewer than 5.
double HeightNoise(const std::vector<int>& valid, const std::vector<double>& h) {
  std::vector<double> d2;
  for (std::size_t j = 1; j + 1 < valid.size(); ++j)
    if (valid[j] - valid[j - 1] == 1 && valid[j + 1] - valid[j] == 1)
      d2.push_back(h[j + 1] - 2 * h[j] + h[j - 1]);
  if (d2.size() < 5) return 0.0;
  const double m = Median(d2);
  for (double& x : d2) x = std::abs(x - m);
  return 1.4826 * Median(d2) / std::sqrt(6.0);
}

/// The impacts of a clip, as positions j in `valid` (frames with a pose) of their lowest
/// frames, in time order. A candidate is a frame lower than the one before and not higher than
/// the one after. Candidates with no rise of more than 6 noise s.d. between them are one contact
/// (the lowest is kept). A candidate is an impact when E comes down onto it and rises from it
/// faster than kMinImpactSpeed_m_s (from one or two frames each side, not reaching past a
/// neighbouring candidate), and lies no higher above the clip's lowest frame than E moves over
/// those frames and a contact's time, plus 6 noise s.d.: that leaves out the wobbles of
/// noise at an arc's apex, however many frames the arc has.
std::vector<std::size_t> FindImpacts(const std::vector<PoseSample>& poses,
                                     const std::vector<int>& valid, const std::vector<double>& h,
                                     double max_contact_s) {
  const std::size_t n = valid.size();
  const double sigma = HeightNoise(valid, h);
  const double h_min = *std::min_element(h.begin(), h.end());
  std::vector<std::size_t> c;
  for (std::size_t j = 1; j + 1 < n; ++j) {
    if (!(h[j] < h[j - 1] && h[j] <= h[j + 1])) continue;
    if (!c.empty()) {
      const double rise = *std::max_element(h.begin() + static_cast<std::ptrdiff_t>(c.back()),
                                            h.begin() + static_cast<std::ptrdiff_t>(j) + 1) -
                          std::max(h[c.back()], h[j]);
      if (rise <= 6 * sigma) {
        if (h[j] < h[c.back()]) c.back() = j;
        continue;
      }
    }
    c.push_back(j);
  }
  const auto t = [&](std::size_t j) { return poses[static_cast<std::size_t>(valid[j])].t_s; };
  std::vector<std::size_t> impacts;
  for (std::size_t m = 0; m < c.size(); ++m) {
    const std::size_t j = c[m];
    const std::size_t prev = m > 0 ? c[m - 1] : 0, next = m + 1 < c.size() ? c[m + 1] : n - 1;
    const std::size_t a = j - std::min<std::size_t>(2, j - prev);
    const std::size_t b = j + std::min<std::size_t>(2, next - j);
    if (a == j || b == j) continue;
    // The steepest descent onto it and rise from it (one frame or two: the lowest frame may lie
    // just before or after the touch, where E moves slowly on one side).
    double v_down = 0, v_up = 0;
    for (std::size_t i = a; i < j; ++i) v_down = std::min(v_down, (h[j] - h[i]) / (t(j) - t(i)));
    for (std::size_t i = j + 1; i <= b; ++i) v_up = std::max(v_up, (h[i] - h[j]) / (t(i) - t(j)));
    if (!(v_down < -kMinImpactSpeed_m_s && v_up > kMinImpactSpeed_m_s)) continue;
    const double reach = (-v_down + v_up) * (t(b) - t(a) + max_contact_s) + 6 * sigma;
    if (h[j] - h_min <= reach) impacts.push_back(j);
  }
  return impacts;
}

}  // namespace

std::vector<ImpactKinematics> MeasureImpacts(const std::vector<PoseSample>& poses, double fps,
                                             double surface_angle_deg,
                                             const core::SpecimenParameters& body,
                                             const KinematicsOptions& options) {
  options.Validate();
  if (!(fps > 0)) throw std::invalid_argument("fps must be > 0");
  const auto S = core::SurfaceRotation::FromDegrees(surface_angle_deg);
  const double exposure = options.exposure_s < 0 ? 1.0 / fps : options.exposure_s;
  const double margin = options.max_contact_s + 0.5 * exposure;
  std::vector<int> valid;
  for (std::size_t i = 0; i < poses.size(); ++i)
    if (poses[i].valid) valid.push_back(static_cast<int>(i));
  if (valid.size() < 3) return {};
  std::vector<double> h;
  for (int i : valid) h.push_back(Height(poses, S, i));
  const std::vector<std::size_t> found = FindImpacts(poses, valid, h, options.max_contact_s);
  const auto t_of = [&](int i) { return poses[static_cast<std::size_t>(i)].t_s; };

  std::vector<ImpactKinematics> out(found.size());
  // Each impact's fits may not reach into its neighbours' contacts. First those lie somewhere
  // between the frames either side of a neighbour's lowest frame; once the neighbours are
  // measured, about their impact times, as each impact leaves out frames about its own.
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<double> t_from(found.size(), -kInf), t_to(found.size(), kInf);
  for (std::size_t m = 0; m < found.size(); ++m) {
    if (m > 0) t_from[m] = t_of(valid[found[m - 1] + 1]) + margin;
    if (m + 1 < found.size()) t_to[m] = t_of(valid[found[m + 1] - 1]) - margin;
  }
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t m = 0; m < found.size(); ++m) {
      ImpactKinematics k;
      const int i_min = valid[found[m]];
      k.index = static_cast<int>(m);
      k.lowest_frame = i_min;
      if (FitAroundImpact(poses, valid, i_min, -1, t_of(i_min), exposure, S, body, options, k,
                          t_from[m], t_to[m])) {
        Finish(fps, surface_angle_deg, S, body, options, k);
      } else {
        k.impact_time_s = t_of(i_min);
        k.impact_frame = i_min;
        k.before = k.after = FlightFit{};
      }
      out[m] = k;
    }
    for (std::size_t m = 0; m < found.size(); ++m) {
      if (m > 0 && out[m - 1].success) t_from[m] = out[m - 1].impact_time_s + margin;
      if (m + 1 < found.size() && out[m + 1].success) t_to[m] = out[m + 1].impact_time_s - margin;
    }
  }
  return out;
}

}  // namespace hoof::kinematics
