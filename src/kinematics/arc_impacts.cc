#include "kinematics/arc_impacts.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/Dense>
#include <boost/math/distributions/students_t.hpp>

namespace hoof::kinematics {
namespace {

/// The values computed for one impact from the parameters, in this order.
enum Value : int {
  kT = 0,     ///< t*
  kVbS = 1,   ///< v_SC before (2)
  kVaS = 3,   ///< v_SC after (2)
  kVTbS = 5,  ///< v_ST before (2)
  kVTaS = 7,  ///< v_ST after (2)
  kE = 9,
  kMu = 10,
  kPT = 11,   ///< p_WT (2)
  kGap = 13,  ///< the arcs' distance along the surface at t*
  kVbW = 14,  ///< v_WC before (2)
  kVaW = 16,  ///< v_WC after (2)
  kPC = 18,   ///< p_WC at t* (2)
  kThB = 20,
  kThA = 21,
  kWB = 22,
  kWA = 23,
  kValues = 24
};

/// What the values of the impacts depend on besides the parameters q = [x; theta_k, w_k of
/// each fitted arc].
struct Context {
  const FlightArcs& arcs;
  int P = 0;  ///< parameters in x
  double phi_rad = 0.0;
  double d = 0.0, R = 0.0;
  bool fitted_up = true;  ///< gravity's direction from the fitted acceleration, else y_W
};

/// S at the stated angle from gravity's perpendicular, gravity the fitted acceleration (or W's
/// -y where its direction is not measured).
core::SurfaceRotation SurfaceOf(const Context& c, const Eigen::Vector2d& a) {
  const Eigen::Vector2d up =
      c.fitted_up && a.norm() > 0 ? Eigen::Vector2d(-a / a.norm()) : Eigen::Vector2d(0, 1);
  return core::SurfaceRotation(c.phi_rad + std::atan2(up.x(), up.y()));
}

/// Velocity of the body point at T: v_C + w x (p_T - p_C), p_T = p_C - d x_B - R y_S.
Eigen::Vector2d PointVelocity(const Context& c, const Eigen::Vector2d& v, double w, double theta,
                              const Eigen::Vector2d& n) {
  const Eigen::Vector2d r = -c.d * core::BodyRotation(theta).x_B() - c.R * n;
  return v + w * Eigen::Vector2d(-r.y(), r.x());
}

/// The values of the impact between arcs k and k + 1, about the time t_m between them.
Eigen::VectorXd ImpactValues(const Context& c, const Eigen::VectorXd& q, int k, double t_m) {
  const Eigen::VectorXd x = q.head(c.P);
  const core::SurfaceRotation S = SurfaceOf(c, x.tail<2>());
  const Eigen::Vector2d n = S.y_S(), ts = S.x_S();
  const FlightArcs& A = c.arcs;
  const Eigen::Vector2d dp = ArcPosition(A, x, k + 1, t_m) - ArcPosition(A, x, k, t_m);
  const Eigen::Vector2d dv = ArcVelocity(A, x, k + 1, t_m) - ArcVelocity(A, x, k, t_m);
  const double t = t_m - n.dot(dp) / n.dot(dv);
  const Eigen::Vector2d pb = ArcPosition(A, x, k, t), pa = ArcPosition(A, x, k + 1, t);
  const Eigen::Vector2d vb = ArcVelocity(A, x, k, t), va = ArcVelocity(A, x, k + 1, t);
  const auto angle = [&](int arc, double& theta, double& w) {
    const int sl = A.slot[static_cast<std::size_t>(arc)];
    w = q(c.P + 2 * sl + 1);
    theta = q(c.P + 2 * sl) + w * (t - A.arcs[static_cast<std::size_t>(arc)].t_ref_s);
  };
  double thb = 0, wb = 0, tha = 0, wa = 0;
  angle(k, thb, wb);
  angle(k + 1, tha, wa);
  const Eigen::Vector2d vtb = PointVelocity(c, vb, wb, thb, n);
  const Eigen::Vector2d vta = PointVelocity(c, va, wa, tha, n);
  const Eigen::Vector2d pc = 0.5 * (pb + pa);
  Eigen::VectorXd out(kValues);
  out(kT) = t;
  out.segment<2>(kVbS) = S.ToS(vb);
  out.segment<2>(kVaS) = S.ToS(va);
  out.segment<2>(kVTbS) = S.ToS(vtb);
  out.segment<2>(kVTaS) = S.ToS(vta);
  out(kE) = -n.dot(vta) / n.dot(vtb);
  out(kMu) = std::abs(ts.dot(va - vb) / n.dot(va - vb));
  out.segment<2>(kPT) = pc - c.d * core::BodyRotation(thb).x_B() - c.R * n;
  out(kGap) = ts.dot(pa - pb);
  out.segment<2>(kVbW) = vb;
  out.segment<2>(kVaW) = va;
  out.segment<2>(kPC) = pc;
  out(kThB) = thb;
  out(kThA) = tha;
  out(kWB) = wb;
  out(kWA) = wa;
  return out;
}

/// J cov J^T for the function f at q (central differences, each step a thousandth of the
/// parameter's s.d.; parameters known exactly are skipped).
template <class F>
Eigen::MatrixXd DeltaCovariance(const F& f, const Eigen::VectorXd& q, const Eigen::MatrixXd& cov) {
  const Eigen::VectorXd f0 = f(q);
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(f0.size(), q.size());
  for (Eigen::Index i = 0; i < q.size(); ++i) {
    const double sd = std::sqrt(std::max(cov(i, i), 0.0));
    if (!(sd > 0)) continue;
    const double h = 1e-3 * sd;
    Eigen::VectorXd qp = q, qm = q;
    qp(i) += h;
    qm(i) -= h;
    J.col(i) = (f(qp) - f(qm)) / (2 * h);
  }
  return J * cov * J.transpose();
}

/// The parameters q (x and the arcs' angles) and their covariance.
void Parameters(const FlightArcs& A, Eigen::VectorXd& q, Eigen::MatrixXd& cov) {
  const auto P = A.x.size();
  int fitted = 0;
  for (int sl : A.slot) fitted += sl >= 0;
  q = Eigen::VectorXd::Zero(P + 2 * fitted);
  cov = Eigen::MatrixXd::Zero(q.size(), q.size());
  q.head(P) = A.x;
  cov.topLeftCorner(P, P) = A.cov_x;
  for (std::size_t k = 0; k < A.arcs.size(); ++k) {
    const int sl = A.slot[k];
    if (sl < 0) continue;
    q(P + 2 * sl) = A.arcs[k].theta_W_rad;
    q(P + 2 * sl + 1) = A.arcs[k].w_rad_s;
    cov(P + 2 * sl, P + 2 * sl) = std::pow(A.arcs[k].theta_se_rad, 2);
    cov(P + 2 * sl + 1, P + 2 * sl + 1) = std::pow(A.arcs[k].w_se_rad_s, 2);
  }
}

/// f at q with x replaced by `x`.
Eigen::VectorXd WithX(const Eigen::VectorXd& q, const Eigen::VectorXd& x) {
  Eigen::VectorXd out = q;
  out.head(x.size()) = x;
  return out;
}

/// The frames of `arcs` with role `role` and arc k or k + 1 (contact frames: only those on
/// the side of the contact between them).
std::vector<int> FramesOf(const FlightArcs& arcs, int k, ArcFrameRole role) {
  std::vector<int> out;
  const FlightArc &b = arcs.arcs[static_cast<std::size_t>(k)],
                  &a = arcs.arcs[static_cast<std::size_t>(k + 1)];
  for (std::size_t f = 0; f < arcs.frames.size(); ++f) {
    const ArcFrame& fr = arcs.frames[f];
    if (fr.role != role || (fr.arc != k && fr.arc != k + 1)) continue;
    const int i = static_cast<int>(f);
    if (role == ArcFrameRole::kContact &&
        !((fr.arc == k && i > b.last_frame) || (fr.arc == k + 1 && i < a.first_frame)))
      continue;
    out.push_back(i);
  }
  return out;
}

/// The limits of the impact after arc k that do not need its measurement.
ImpactLimits LimitsOf(const FlightArcs& arcs, const ArcContact& c, int min_arc) {
  const int k = c.before;
  ImpactLimits L;
  const FlightArc &b = arcs.arcs[static_cast<std::size_t>(k)],
                  &a = arcs.arcs[static_cast<std::size_t>(k + 1)];
  L.samples_before = b.n;
  L.samples_after = a.n;
  L.short_arc = b.n < min_arc || a.n < min_arc;
  L.contact_frames = FramesOf(arcs, k, ArcFrameRole::kContact);
  L.outlier_frames = FramesOf(arcs, k, ArcFrameRole::kOutlier);
  L.not_in_flight_frames = FramesOf(arcs, k, ArcFrameRole::kNotInFlight);
  const int lo = b.first_frame >= 0 ? b.first_frame : c.last_frame_before;
  const int hi = a.last_frame >= 0 ? a.last_frame : c.first_frame_after;
  for (int f = lo; f <= hi; ++f) {
    const ArcFrameRole r = arcs.frames[static_cast<std::size_t>(f)].role;
    if (r == ArcFrameRole::kNoSample) L.missing_frames.push_back(f);
    if (r == ArcFrameRole::kRepeated) L.repeated_frames.push_back(f);
  }
  L.depth_rate_before_per_s = b.depth_rate_per_s;
  L.depth_rate_after_per_s = a.depth_rate_per_s;
  return L;
}

/// The frame nearest the contact `c` lowest along "up" (C's height), between the frames
/// either side of its velocity change.
int LowestFrame(const std::vector<PoseSample>& poses, const FlightArcs& arcs, const ArcContact& c,
                double d) {
  const Eigen::Vector2d up =
      arcs.a_norm > 0 ? Eigen::Vector2d(-arcs.a_W / arcs.a_norm) : Eigen::Vector2d(0, 1);
  int best = c.last_frame_before;
  double h_best = 0;
  for (int f = c.last_frame_before; f <= c.first_frame_after; ++f) {
    const PoseSample& p = poses[static_cast<std::size_t>(f)];
    if (!p.valid) continue;
    const double h = up.dot(p.p_WE + d * core::BodyRotation(p.theta_W_rad).x_B());
    if (f == c.last_frame_before || h < h_best) {
      best = f;
      h_best = h;
    }
  }
  return best;
}

/// The time between the two arcs' nearest fitted samples, the origin of t* (any time gives the
/// same t*; this one keeps the arithmetic well conditioned).
double MidTime(const std::vector<PoseSample>& poses, const FlightArcs& arcs, int k) {
  return 0.5 *
         (poses[static_cast<std::size_t>(arcs.arcs[static_cast<std::size_t>(k)].last_frame)].t_s +
          poses[static_cast<std::size_t>(arcs.arcs[static_cast<std::size_t>(k + 1)].first_frame)]
              .t_s);
}

/// Why the impact after arc k cannot be measured from its values `v`; empty when it can.
std::string Unmeasurable(const std::vector<PoseSample>& poses, const FlightArcs& arcs, int k,
                         const Eigen::VectorXd& v, double t_se) {
  std::ostringstream os;
  const PoseSample& before =
      poses[static_cast<std::size_t>(arcs.arcs[static_cast<std::size_t>(k)].last_frame)];
  const PoseSample& after =
      poses[static_cast<std::size_t>(arcs.arcs[static_cast<std::size_t>(k + 1)].first_frame)];
  const double t_lo = before.t_s, t_hi = after.t_s;
  // The frames' own times are uncertain too where the clip knows its captures' times only to
  // within a frame period (PoseSample::t_sd_s).
  const double lo_se = std::hypot(t_se, before.t_sd_s), hi_se = std::hypot(t_se, after.t_sd_s);
  if (!v.allFinite()) {
    os << "the arcs on either side do not meet";
  } else if (!(v(kVTbS + 1) < 0 && v(kVTaS + 1) > 0)) {
    os << "the arcs on either side meet without the body coming down onto the surface and "
          "rising from it (normal velocities "
       << v(kVTbS + 1) << " and " << v(kVTaS + 1) << ")";
  } else if (v(kT) < t_lo - 3 * lo_se || v(kT) > t_hi + 3 * hi_se) {
    os << "the arcs on either side meet at " << v(kT) << " s, outside the time between their "
       << "frames (" << t_lo << " to " << t_hi << " s)";
  }
  return os.str();
}

/// The measured impact after arc k from its values and their covariance.
void Fill(const FlightArcs& arcs, int k, const Eigen::VectorXd& v, const Eigen::MatrixXd& cv,
          double surface_angle_deg, bool fitted_up, const core::SpecimenParameters& body,
          const KinematicsOptions& o, ImpactKinematics& im) {
  const auto se = [&](int i) { return std::sqrt(std::max(cv(i, i), 0.0)); };
  const auto se2 = [&](int i) { return Eigen::Vector2d(se(i), se(i + 1)); };
  im.success = true;
  im.impact_time_s = v(kT);
  im.impact_time_se_s = se(kT);
  im.surface_angle_W_deg = surface_angle_deg + (fitted_up ? arcs.roll_deg : 0.0);
  im.v_SC_before = v.segment<2>(kVbS);
  im.v_SC_after = v.segment<2>(kVaS);
  im.v_SC_before_se = se2(kVbS);
  im.v_SC_after_se = se2(kVaS);
  im.v_ST_before = v.segment<2>(kVTbS);
  im.v_ST_after = v.segment<2>(kVTaS);
  im.w_before_rad_s = v(kWB);
  im.w_after_rad_s = v(kWA);
  im.w_before_se_rad_s = se(kWB);
  im.w_after_se_rad_s = se(kWA);
  const double t_q = boost::math::quantile(boost::math::complement(
      boost::math::students_t(std::max(1, arcs.dof)), 0.5 * (1 - o.confidence)));
  im.e = v(kE);
  im.e_se = se(kE);
  im.e_ci_low = im.e - t_q * im.e_se;
  im.e_ci_high = im.e + t_q * im.e_se;
  // mu_eff where the body moves along the surface: an inclined one, or a level one crossed
  // sideways (3 s.e. and min_sideways_ratio of the normal speed).
  const double vt = std::abs(im.v_SC_before.x());
  const bool sideways =
      surface_angle_deg != 0.0 || (vt > 3 * im.v_SC_before_se.x() &&
                                   vt > o.arcs.min_sideways_ratio * std::abs(im.v_SC_before.y()));
  im.mu_eff = sideways ? v(kMu) : core::kNaN;
  im.mu_eff_se = sideways ? se(kMu) : core::kNaN;
  im.mu_eff_ci_low = sideways ? std::max(0.0, im.mu_eff - t_q * im.mu_eff_se) : core::kNaN;
  im.mu_eff_ci_high = sideways ? im.mu_eff + t_q * im.mu_eff_se : core::kNaN;
  im.p_WT = v.segment<2>(kPT);
  im.cov_p_WT = cv.block<2, 2>(kPT, kPT);
  im.limits.meeting_gap_m = v(kGap);
  im.limits.meeting_gap_se_m = se(kGap);
  const auto fit = [&](int arc, int vel, int th, int w, FlightFit& f) {
    const FlightArc& a = arcs.arcs[static_cast<std::size_t>(arc)];
    f.first_frame = a.first_frame;
    f.last_frame = a.last_frame;
    f.n = a.n;
    f.p_WC = v.segment<2>(kPC);
    f.v_WC = v.segment<2>(vel);
    f.cov_v_WC = cv.block<2, 2>(vel, vel);
    f.theta_W_rad = v(th);
    f.theta_se_rad = se(th);
    f.w_rad_s = v(w);
    f.w_se_rad_s = se(w);
    f.rms_residual_m = a.rms_residual;
  };
  fit(k, kVbW, kThB, kWB, im.before);
  fit(k + 1, kVaW, kThA, kWA, im.after);
  im.kinetic_energy_before_J = 0.5 * body.mass_kg * im.before.v_WC.squaredNorm() +
                               0.5 * body.inertia_kg_m2 * std::pow(im.w_before_rad_s, 2);
  im.kinetic_energy_after_J = 0.5 * body.mass_kg * im.after.v_WC.squaredNorm() +
                              0.5 * body.inertia_kg_m2 * std::pow(im.w_after_rad_s, 2);
}

/// Warnings and flags of a measured impact: the arcs apart where they meet, the depth motion.
void Remarks(ImpactKinematics& im) {
  std::ostringstream os;
  const ImpactLimits& L = im.limits;
  if (std::abs(L.meeting_gap_m) > 4 * L.meeting_gap_se_m) {
    os << "impact " << im.index << ": the arcs before and after it are " << L.meeting_gap_m
       << " apart along the surface where they meet (" << L.meeting_gap_m / L.meeting_gap_se_m
       << " s.e.): a contact that lasts, or frames of another motion in an arc";
    im.warnings.push_back(os.str());
    im.flags.push_back("arcs_apart");
    os.str("");
  }
  if (std::isfinite(L.e_depth_shift)) {
    os << "impact " << im.index << ": the apparent size changes (depth rate "
       << L.depth_rate_before_per_s << " and " << L.depth_rate_after_per_s << " per s); "
       << (L.depth_corrected ? "corrected for it, e moved by "
                             : "corrected for it, e would move by ")
       << L.e_depth_shift;
    im.warnings.push_back(os.str());
    im.flags.push_back("depth_motion");
  }
}

/// The contact line through the measured impacts' contact points (values `v` per impact,
/// their covariance as one function of q).
ContactLine Line(const Context& c, const Eigen::VectorXd& q, const Eigen::MatrixXd& cov,
                 const std::vector<std::pair<int, double>>& measured,
                 const std::vector<Eigen::Matrix2d>& cov_pt) {
  ContactLine L;
  L.impacts = static_cast<int>(measured.size());
  if (measured.empty()) {
    L.message = "no impact was measured";
    return L;
  }
  const Eigen::Vector2d up = -q.segment<2>(c.P - 2).normalized();
  const Eigen::Vector2d xg(up.y(), -up.x());
  // Points in gravity's frame: along its perpendicular, and height.
  const auto points = [&](const Eigen::VectorXd& qq, std::vector<Eigen::Vector2d>& pts) {
    const Eigen::Vector2d u = -qq.segment<2>(c.P - 2).normalized(), x(u.y(), -u.x());
    pts.clear();
    for (const auto& [k, t_m] : measured) {
      const Eigen::Vector2d p = ImpactValues(c, qq, k, t_m).segment<2>(kPT);
      pts.emplace_back(x.dot(p), u.dot(p));
    }
  };
  std::vector<Eigen::Vector2d> pts;
  points(q, pts);
  double lo = pts[0].x(), hi = pts[0].x(), pos_se = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    lo = std::min(lo, pts[i].x());
    hi = std::max(hi, pts[i].x());
    pos_se = std::max(pos_se, std::sqrt(std::max(xg.dot(cov_pt[i] * xg), 0.0)));
  }
  L.angle_measured = pts.size() >= 2 && hi - lo > 10 * pos_se;
  // [mean along, level, angle (rad), p_W x, p_W y]
  const auto f = [&](const Eigen::VectorXd& qq) {
    std::vector<Eigen::Vector2d> p;
    points(qq, p);
    const double n = static_cast<double>(p.size());
    Eigen::Vector2d m{0, 0};
    for (const auto& x : p) m += x / n;
    double sxx = 0, sxy = 0;
    for (const auto& x : p) {
      sxx += (x.x() - m.x()) * (x.x() - m.x());
      sxy += (x.x() - m.x()) * (x.y() - m.y());
    }
    const Eigen::Vector2d u = -qq.segment<2>(c.P - 2).normalized(), xa(u.y(), -u.x());
    Eigen::VectorXd out(5);
    out << m.x(), m.y(), sxx > 0 ? std::atan(-sxy / sxx) : 0.0, (xa * m.x() + u * m.y());
    return out;
  };
  const Eigen::VectorXd v = f(q);
  const Eigen::MatrixXd cv = DeltaCovariance(f, q, cov);
  L.measured = true;
  L.p_W = v.tail<2>();
  L.level_m = v(1);
  L.level_se_m = std::sqrt(std::max(cv(1, 1), 0.0));
  const double slope = L.angle_measured ? std::tan(-v(2)) : -std::tan(c.phi_rad);
  if (L.angle_measured) {
    L.angle_deg = core::RadToDeg(v(2));
    L.angle_se_deg = core::RadToDeg(std::sqrt(std::max(cv(2, 2), 0.0)));
  }
  const std::size_t need = L.angle_measured ? 3 : 2;
  if (pts.size() >= need) {
    double ss = 0;
    for (const auto& p : pts) ss += std::pow(p.y() - v(1) - slope * (p.x() - v(0)), 2);
    L.rms_residual_m = std::sqrt(ss / static_cast<double>(pts.size()));
  }
  return L;
}

}  // namespace

ArcImpacts MeasureArcImpacts(const std::vector<PoseSample>& poses, double surface_angle_deg,
                             const core::SpecimenParameters& body,
                             const KinematicsOptions& options) {
  options.Validate();
  ArcImpacts out;
  out.arcs = FitFlightArcs(poses, body.d_EC_m, surface_angle_deg, options.arcs);
  const FlightArcs& A = out.arcs;
  const bool fitted_up =
      A.status == ArcFitStatus::kFitted && A.roll_se_deg <= options.arcs.max_roll_se_deg;
  const Context c{A,
                  static_cast<int>(A.x.size()),
                  core::DegToRad(surface_angle_deg),
                  body.d_EC_m,
                  body.end_radius_m,
                  fitted_up};
  Eigen::VectorXd q;
  Eigen::MatrixXd cov;
  if (A.status == ArcFitStatus::kFitted) Parameters(A, q, cov);
  std::vector<std::pair<int, double>> measured;
  std::vector<Eigen::Matrix2d> cov_pt;
  for (std::size_t i = 0; i < A.contacts.size(); ++i) {
    const ArcContact& ct = A.contacts[i];
    const int k = ct.before;
    ImpactKinematics im;
    im.method = KinematicsMethod::kArcs;
    im.index = static_cast<int>(i);
    im.lowest_frame = LowestFrame(poses, A, ct, body.d_EC_m);
    im.impact_frame = im.lowest_frame;
    im.impact_time_s = poses[static_cast<std::size_t>(im.lowest_frame)].t_s;
    im.limits = LimitsOf(A, ct, options.arcs.min_arc_frames);
    std::ostringstream why;
    if (A.status != ArcFitStatus::kFitted) {
      why << A.message;
    } else if (im.limits.short_arc) {
      why << "the flight "
          << (im.limits.samples_before < options.arcs.min_arc_frames ? "before" : "after")
          << " it holds " << std::min(im.limits.samples_before, im.limits.samples_after)
          << " frames with a position on the arc (need " << options.arcs.min_arc_frames << ")";
    }
    if (why.str().empty()) {
      const double t_m = MidTime(poses, A, k);
      const auto f = [&](const Eigen::VectorXd& qq) { return ImpactValues(c, qq, k, t_m); };
      const Eigen::VectorXd v = f(q);
      Eigen::MatrixXd cv = DeltaCovariance(f, q, cov);
      for (const auto& xp : A.x_perspective_perturbed) {
        const Eigen::VectorXd d = f(WithX(q, xp)) - v;
        cv += d * d.transpose();
      }
      for (const auto& xp : A.x_depth_perturbed) {
        const Eigen::VectorXd d = f(WithX(q, xp)) - v;
        cv += d * d.transpose();
      }
      why << Unmeasurable(poses, A, k, v, std::sqrt(std::max(cv(kT, kT), 0.0)));
      if (why.str().empty()) {
        Fill(A, k, v, cv, surface_angle_deg, fitted_up, body, options, im);
        if (!fitted_up) {
          std::ostringstream os;
          os << "impact " << i << ": gravity's direction is not measured from the arcs (its s.e. "
             << A.roll_se_deg << " deg is over " << options.arcs.max_roll_se_deg
             << "): S is built on trial.json's gravity";
          im.warnings.push_back(os.str());
          im.flags.push_back("gravity_direction_stated");
        }
        if (A.perspective_applied)
          im.limits.e_perspective_shift = im.e - f(WithX(q, A.x_unrectified))(kE);
        if (A.depth_measured) {
          const double e_other = f(WithX(q, A.x_other))(kE);
          im.limits.depth_corrected = A.depth_applied;
          im.limits.e_depth_shift = A.depth_applied ? im.e - e_other : e_other - im.e;
        }
        im.impact_frame = im.lowest_frame;
        for (std::size_t fr = 0; fr < poses.size(); ++fr)
          if (poses[fr].t_s <= im.impact_time_s) im.impact_frame = static_cast<int>(fr);
        Remarks(im);
        measured.emplace_back(k, t_m);
        cov_pt.push_back(im.cov_p_WT);
      }
    }
    if (!im.success) im.message = "impact " + std::to_string(i) + ": " + why.str();
    out.impacts.push_back(std::move(im));
  }
  if (A.status == ArcFitStatus::kFitted) {
    out.contact_line = Line(c, q, cov, measured, cov_pt);
  } else {
    out.contact_line.message = A.message;
  }
  return out;
}

}  // namespace hoof::kinematics
