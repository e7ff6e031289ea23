#include "kinematics/gravity_scale.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <Eigen/Dense>

namespace hoof::kinematics {
namespace {

double Median(std::vector<double> v) {
  if (v.empty()) return core::kNaN;
  auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

void Validate(const GravityScaleOptions& o, double fps) {
  if (!(o.gravity_m_s2 > 0)) throw std::invalid_argument("gravity scale: gravity_m_s2 must be > 0");
  if (!(o.contact_sigmas > 0))
    throw std::invalid_argument("gravity scale: contact_sigmas must be > 0");
  if (o.contact_margin_frames < 0)
    throw std::invalid_argument("gravity scale: contact_margin_frames must be >= 0");
  if (o.min_arc_frames < 3)
    throw std::invalid_argument("gravity scale: min_arc_frames must be >= 3");
  if (!(o.min_significance > 0))
    throw std::invalid_argument("gravity scale: min_significance must be > 0");
  if (!(fps > 0) || !std::isfinite(fps))
    throw std::invalid_argument("gravity scale: fps must be > 0");
}

}  // namespace

GravityScale EstimateGravityScale(const std::vector<std::optional<Eigen::Vector2d>>& p_px,
                                  double fps, const Eigen::Vector2d& gravity_dir,
                                  const GravityScaleOptions& options) {
  Validate(options, fps);
  GravityScale out;
  const int n_frames = static_cast<int>(p_px.size());
  const Eigen::Vector2d g_dir =
      gravity_dir.norm() > 0 ? gravity_dir.normalized() : Eigen::Vector2d(0, 1);
  auto valid = [&](int f) { return f >= 0 && f < n_frames && p_px[static_cast<std::size_t>(f)]; };
  auto s = [&](int f) { return p_px[static_cast<std::size_t>(f)]->dot(g_dir); };

  // Contacts: a free flight's second difference along gravity is a / fps^2 in every frame; a
  // contact turns the motion back and makes it strongly negative (the body decelerates while
  // gravity would speed it up). The median and a robust spread of all second differences set
  // the threshold, so contacts (a few frames) do not move it.
  std::vector<double> dd(static_cast<std::size_t>(n_frames), core::kNaN);
  std::vector<double> all;
  for (int f = 1; f + 1 < n_frames; ++f)
    if (valid(f - 1) && valid(f) && valid(f + 1)) {
      dd[static_cast<std::size_t>(f)] = s(f + 1) - 2 * s(f) + s(f - 1);
      all.push_back(dd[static_cast<std::size_t>(f)]);
    }
  const double med = Median(all);
  std::vector<double> dev;
  for (double x : all) dev.push_back(std::abs(x - med));
  const double spread = 1.4826 * Median(dev);
  std::vector<bool> excluded(static_cast<std::size_t>(n_frames), false);
  // At least a tiny floor, so a noise-free clip does not call every rounding a contact.
  const double threshold =
      med - std::max(options.contact_sigmas * spread, 1e-6 + 0.5 * std::abs(med));
  if (!all.empty()) {
    for (int f = 1; f + 1 < n_frames; ++f) {
      const double x = dd[static_cast<std::size_t>(f)];
      if (!(x < threshold)) continue;
      out.contact_frames.push_back(f);
      for (int g = f - options.contact_margin_frames; g <= f + options.contact_margin_frames; ++g)
        if (g >= 0 && g < n_frames) excluded[static_cast<std::size_t>(g)] = true;
    }
  }
  // A contact the tracker could not follow (the body lost in the frames that show it: a surface
  // joining its silhouette) leaves a gap instead: a run of missing frames across which the body
  // slows along gravity as no free flight does: the velocity along gravity after it minus the
  // velocity before it (px per frame) is below the contact threshold of the second differences.
  // Its frames and `contact_margin_frames` on each side are left out, and its first frame is
  // listed as a contact.
  for (int a = 2; a + 2 < n_frames;) {
    if (valid(a)) {
      ++a;
      continue;
    }
    int b = a;
    while (b + 1 < n_frames && !valid(b + 1)) ++b;
    if (!all.empty() && valid(a - 1) && valid(a - 2) && valid(b + 1) && valid(b + 2) &&
        (s(b + 2) - s(b + 1)) - (s(a - 1) - s(a - 2)) < threshold) {
      out.contact_frames.push_back(a);
      for (int g = a - options.contact_margin_frames; g <= b + options.contact_margin_frames; ++g)
        if (g >= 0 && g < n_frames) excluded[static_cast<std::size_t>(g)] = true;
    }
    a = b + 1;
  }
  std::sort(out.contact_frames.begin(), out.contact_frames.end());
  // A contact between frames f and f + 1 makes both their second differences negative; those
  // frames and `contact_margin_frames` on each side are left out, and the arcs are cut there.
  for (int f = 0; f < n_frames;) {
    if (!valid(f) || excluded[static_cast<std::size_t>(f)]) {
      ++f;
      continue;
    }
    GravityArc arc;
    arc.first_frame = f;
    int last = f, n = 0;
    for (; f < n_frames && !excluded[static_cast<std::size_t>(f)]; ++f)
      if (valid(f)) {
        last = f;
        ++n;
      }
    arc.last_frame = last;
    arc.n = n;
    if (n >= options.min_arc_frames) out.arcs.push_back(arc);
  }

  // One linear least-squares problem: per arc an offset and a velocity in x and y, and one
  // acceleration (a_x, a_y) for all. Time in frames about each arc's mean, for conditioning.
  const int k_arcs = static_cast<int>(out.arcs.size());
  for (const auto& a : out.arcs) out.frames_used += a.n;
  const int unknowns = 4 * k_arcs + 2;
  const int rows = 2 * out.frames_used;
  if (k_arcs == 0 || rows - unknowns < 2) {
    std::ostringstream os;
    os << "the scale from gravity needs a free-flight arc of " << options.min_arc_frames
       << " or more frames (found " << k_arcs << " usable arcs, " << out.frames_used << " frames)";
    out.message = os.str();
    return out;
  }
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(rows, unknowns);
  Eigen::VectorXd b(rows);
  int r = 0;
  for (int k = 0; k < k_arcs; ++k) {
    const auto& arc = out.arcs[static_cast<std::size_t>(k)];
    double t_mean = 0;
    for (int f = arc.first_frame; f <= arc.last_frame; ++f)
      if (valid(f)) t_mean += f / static_cast<double>(arc.n);
    for (int f = arc.first_frame; f <= arc.last_frame; ++f) {
      if (!valid(f)) continue;
      const double t = f - t_mean;
      const Eigen::Vector2d& p = *p_px[static_cast<std::size_t>(f)];
      for (int c = 0; c < 2; ++c, ++r) {
        A(r, 4 * k + c) = 1.0;
        A(r, 4 * k + 2 + c) = t;
        A(r, 4 * k_arcs + c) = 0.5 * t * t;
        b(r) = p(c);
      }
    }
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  if (qr.rank() < unknowns) {
    out.message = "the scale from gravity: the arcs do not determine a curvature";
    return out;
  }
  const Eigen::VectorXd x = qr.solve(b);
  const Eigen::VectorXd res = A * x - b;
  const double s2 = res.squaredNorm() / (rows - unknowns);
  out.rms_residual_px = std::sqrt(res.squaredNorm() / out.frames_used);
  const Eigen::MatrixXd cov = s2 * (A.transpose() * A).inverse();
  const double fps2 = fps * fps;
  out.a_px_s2 = x.tail<2>() * fps2;
  out.cov_a = cov.bottomRightCorner<2, 2>() * fps2 * fps2;
  out.a_norm_px_s2 = out.a_px_s2.norm();
  if (out.a_norm_px_s2 > 0) {
    const Eigen::Vector2d u = out.a_px_s2 / out.a_norm_px_s2;
    out.a_norm_se_px_s2 = std::sqrt(u.dot(out.cov_a * u));
    out.direction_error_deg =
        std::atan2(g_dir.x() * u.y() - g_dir.y() * u.x(), g_dir.dot(u)) * 180 / M_PI;
    out.m_per_px = options.gravity_m_s2 / out.a_norm_px_s2;
    out.m_per_px_se = out.m_per_px * out.a_norm_se_px_s2 / out.a_norm_px_s2;
  }
  std::ostringstream os;
  if (!(out.a_norm_px_s2 > options.min_significance * out.a_norm_se_px_s2)) {
    os << "the scale from gravity is not measured: the fitted acceleration, " << out.a_norm_px_s2
       << " px/s^2 with a standard error of " << out.a_norm_se_px_s2 << " over " << out.frames_used
       << " frames, is within " << options.min_significance
       << " standard errors of zero (the flight is too short or too few pixels long)";
    out.message = os.str();
    return out;
  }
  if (out.a_px_s2.dot(g_dir) <= 0) {
    os << "the scale from gravity is not measured: the fitted acceleration points "
       << out.direction_error_deg << " deg from the stated gravity direction";
    out.message = os.str();
    return out;
  }
  out.measured = true;
  return out;
}

void AddScaleUncertainty(double rel_se, double surface_angle_deg,
                         const core::SpecimenParameters& body, ImpactKinematics& k) {
  if (!std::isfinite(rel_se) || rel_se < 0) rel_se = 0;
  // S as the measurement built it (the joint arcs turn it with gravity's fitted roll).
  const auto S = core::SurfaceRotation::FromDegrees(
      std::isfinite(k.surface_angle_W_deg) ? k.surface_angle_W_deg : surface_angle_deg);
  const Eigen::Matrix2d R_SW = S.R_SW();
  for (FlightFit* fit : {&k.before, &k.after})
    fit->cov_v_WC += rel_se * rel_se * fit->v_WC * fit->v_WC.transpose();
  const Eigen::Matrix2d cb = R_SW * k.before.cov_v_WC * R_SW.transpose();
  const Eigen::Matrix2d ca = R_SW * k.after.cov_v_WC * R_SW.transpose();
  k.v_SC_before_se = cb.diagonal().cwiseSqrt();
  k.v_SC_after_se = ca.diagonal().cwiseSqrt();
  // KE = m |v|^2 / 2 + I w^2 / 2: d KE / d v = m v, d KE / d w = I w (the spin's error is
  // independent of the velocity's; the scale is already in cov_v_WC).
  auto ke_se = [&](const FlightFit& f) {
    const Eigen::Vector2d gv = body.mass_kg * f.v_WC;
    const double gw = body.inertia_kg_m2 * f.w_rad_s;
    return std::sqrt(gv.dot(f.cov_v_WC * gv) + gw * gw * f.w_se_rad_s * f.w_se_rad_s);
  };
  k.kinetic_energy_before_se_J = ke_se(k.before);
  k.kinetic_energy_after_se_J = ke_se(k.after);
}

GravityScale GravityScaleFromArcs(const std::vector<std::optional<Eigen::Vector2d>>& p_px,
                                  double fps, const GravityScaleOptions& options) {
  if (!(fps > 0)) throw std::invalid_argument("GravityScaleFromArcs: fps must be > 0");
  std::vector<PoseSample> poses(p_px.size());
  for (std::size_t i = 0; i < p_px.size(); ++i) {
    poses[i].t_s = static_cast<double>(i) / fps;
    if (!p_px[i]) continue;
    if (i > 0 && p_px[i - 1] && (*p_px[i] - *p_px[i - 1]).norm() < 1e-9) {
      poses[i].repeated = true;
      continue;
    }
    poses[i].valid = true;
    poses[i].p_WE = *p_px[i];
  }
  GravityScale out;
  const FlightArcs arcs = FitFlightArcs(poses, 0.0, 0.0);
  if (arcs.status != ArcFitStatus::kFitted || !(arcs.a_norm > 0)) {
    out.message = "the joint flight arcs were not fitted (" + arcs.message + ")";
    return out;
  }
  out.a_px_s2 = arcs.a_W;
  out.cov_a = arcs.cov_a_W;
  out.a_norm_px_s2 = arcs.a_norm;
  out.a_norm_se_px_s2 = arcs.a_norm_se;
  out.frames_used = arcs.samples_used;
  out.rms_residual_px = arcs.sigma;
  for (const auto& a : arcs.arcs)
    if (a.fitted) out.arcs.push_back({a.first_frame, a.last_frame, a.n});
  for (std::size_t i = 0; i < arcs.frames.size(); ++i)
    if (arcs.frames[i].role == ArcFrameRole::kContact)
      out.contact_frames.push_back(static_cast<int>(i));
  if (!(arcs.a_norm > options.min_significance * arcs.a_norm_se)) {
    std::ostringstream os;
    os << "the scale from gravity is not measured: the joint flight arcs' acceleration, "
       << arcs.a_norm << " px/s^2 with a standard error of " << arcs.a_norm_se << ", is within "
       << options.min_significance << " standard errors of zero";
    out.message = os.str();
    return out;
  }
  out.measured = true;
  out.m_per_px = options.gravity_m_s2 / arcs.a_norm;
  out.m_per_px_se = out.m_per_px * arcs.a_norm_se / arcs.a_norm;
  out.message = "from the joint flight arcs (" + std::to_string(out.arcs.size()) + " arcs)";
  return out;
}

}  // namespace hoof::kinematics
