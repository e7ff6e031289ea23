#include "kinematics/flight_arcs.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include <Eigen/Dense>
#include <boost/math/distributions/chi_squared.hpp>

namespace hoof::kinematics {
namespace {

/// The median of chi^2 with 2 degrees of freedom (2 ln 2): a robust noise level is the median
/// of squared standardized residuals over this.
constexpr double kChi2MedianOf2 = 1.3862943611198906;

double Median(std::vector<double> v) {
  if (v.empty()) return core::kNaN;
  auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

/// One frame with a position: C, and what whitens its residual (W r has unit covariance up to
/// the fitted factor; the identity without covariances).
struct Sample {
  int frame = -1;
  double t = 0.0;
  Eigen::Vector2d p{0, 0};
  Eigen::Matrix2d cov = Eigen::Matrix2d::Identity();
  Eigen::Matrix2d W = Eigen::Matrix2d::Identity();
  double theta = 0.0;
  double size = core::kNaN;
};

/// The working state of the segmentation: per sample its role and arc, and the contacts (a
/// contact at b lies between samples b and b + 1).
struct State {
  std::vector<Sample> s;
  std::vector<ArcFrameRole> role;
  std::vector<int> arc;
  std::vector<double> chi2;
  std::vector<int> breaks;
  std::vector<double> impulse;  ///< per break, in robust s.d.
  double phi_rad = 0.0;         ///< the surface's angle from gravity's perpendicular
  int Arcs() const { return static_cast<int>(breaks.size()) + 1; }
  void AssignArcs() {
    std::size_t b = 0;
    for (std::size_t j = 0; j < s.size(); ++j) {
      while (b < breaks.size() && breaks[b] < static_cast<int>(j)) ++b;
      arc[j] = static_cast<int>(b);
    }
  }
  bool Used(std::size_t j) const { return role[j] == ArcFrameRole::kArc; }
};

/// A solved joint fit on the samples whose role is kArc (arcs with fewer than min_arc of them
/// are not fitted); `res` and `hat` per sample (zero for samples not used). C = (A^T A)^-1 of
/// the whitened design is kept by its blocks: with R_k, S_k the triangle of arc slot k and its
/// coupling to the acceleration, and R_a the acceleration's triangle, C_aa = R_a^-1 R_a^-T,
/// G_k = R_k^-1 S_k, C_ka = -G_k C_aa and C_kl = [k == l] R_k^-1 R_k^-T + G_k C_aa G_l^T.
struct Fit {
  bool ok = false;
  int arcs_fitted = 0, rows = 0, params = 0;
  std::vector<int> slot;
  std::vector<double> t_ref;
  Eigen::VectorXd x;
  std::vector<Eigen::Matrix4d> R_inv;          ///< per slot, R_k^-1
  std::vector<Eigen::Matrix<double, 4, 2>> G;  ///< per slot, R_k^-1 S_k
  Eigen::Matrix2d C_aa = Eigen::Matrix2d::Zero();
  double ssr = 0.0;
  std::vector<Eigen::Vector2d> res;
  std::vector<Eigen::Matrix2d> hat;

  /// The 6 x 6 block of C over slot sl's four parameters and the acceleration's two.
  Eigen::Matrix<double, 6, 6> ArcCovariance(int sl) const {
    const auto u = static_cast<std::size_t>(sl);
    const Eigen::Matrix<double, 4, 2> C_ka = -G[u] * C_aa;
    Eigen::Matrix<double, 6, 6> C;
    C.topLeftCorner<4, 4>() = R_inv[u] * R_inv[u].transpose() - C_ka * G[u].transpose();
    C.topRightCorner<4, 2>() = C_ka;
    C.bottomLeftCorner<2, 4>() = C_ka.transpose();
    C.bottomRightCorner<2, 2>() = C_aa;
    return C;
  }
  /// C whole (params x params).
  Eigen::MatrixXd Covariance() const {
    Eigen::MatrixXd C(params, params);
    const int ca = params - 2;
    for (int k = 0; k < arcs_fitted; ++k) {
      const auto u = static_cast<std::size_t>(k);
      for (int l = 0; l < arcs_fitted; ++l)
        C.block<4, 4>(4 * k, 4 * l) = G[u] * C_aa * G[static_cast<std::size_t>(l)].transpose();
      C.block<4, 4>(4 * k, 4 * k) += R_inv[u] * R_inv[u].transpose();
      C.block<4, 2>(4 * k, ca) = -G[u] * C_aa;
      C.block<2, 4>(ca, 4 * k) = C.block<4, 2>(4 * k, ca).transpose();
    }
    C.block<2, 2>(ca, ca) = C_aa;
    return C;
  }
};

/// The nonzero columns of the 2 x P design rows of a sample at tau from its arc's reference
/// time, whitened by W: its arc's four (position, velocity) and the shared acceleration's two,
/// which lie at 4 sl and at P - 2 for arc slot sl.
Eigen::Matrix<double, 2, 6> DesignBlock(const Eigen::Matrix2d& W, double tau) {
  Eigen::Matrix<double, 2, 6> M;
  M.leftCols<2>() = W;
  M.middleCols<2>(2) = W * tau;
  M.rightCols<2>() = W * (0.5 * tau * tau);
  return M;
}

Fit JointFit(const State& st, int min_arc) {
  Fit f;
  const int K = st.Arcs();
  std::vector<int> count(static_cast<std::size_t>(K), 0);
  std::vector<double> tsum(static_cast<std::size_t>(K), 0.0);
  for (std::size_t j = 0; j < st.s.size(); ++j)
    if (st.Used(j)) {
      ++count[static_cast<std::size_t>(st.arc[j])];
      tsum[static_cast<std::size_t>(st.arc[j])] += st.s[j].t;
    }
  f.slot.assign(static_cast<std::size_t>(K), -1);
  f.t_ref.assign(static_cast<std::size_t>(K), 0.0);
  for (int k = 0; k < K; ++k) {
    const auto u = static_cast<std::size_t>(k);
    if (count[u] >= min_arc) {
      f.slot[u] = f.arcs_fitted++;
      f.rows += 2 * count[u];
    }
    if (count[u] > 0) f.t_ref[u] = tsum[u] / count[u];
  }
  f.params = 4 * f.arcs_fitted + 2;
  f.res.assign(st.s.size(), Eigen::Vector2d::Zero());
  f.hat.assign(st.s.size(), Eigen::Matrix2d::Zero());
  if (f.arcs_fitted == 0 || f.rows - f.params < 1) return f;
  const int P = f.params;
  std::vector<std::vector<std::size_t>> members(static_cast<std::size_t>(f.arcs_fitted));
  for (std::size_t j = 0; j < st.s.size(); ++j) {
    const int sl = st.Used(j) ? f.slot[static_cast<std::size_t>(st.arc[j])] : -1;
    if (sl >= 0) members[static_cast<std::size_t>(sl)].push_back(j);
  }
  // The design is block-angular: each arc's rows reach its own four columns and the shared
  // acceleration's two. Householder QR of each arc's rows [its four | acceleration | positions]
  // leaves its 4 x 4 triangle, its coupling to the acceleration, and a 2 x 2 remainder that
  // only the acceleration explains; QR of the remainders stacked gives the acceleration's
  // triangle. Together they are the R of the whole design's QR (R^T R = A^T A), at a cost
  // linear in the samples.
  std::vector<Eigen::Matrix4d> R_k(static_cast<std::size_t>(f.arcs_fitted));
  std::vector<Eigen::Matrix<double, 4, 2>> S_k(R_k.size());
  std::vector<Eigen::Vector4d> c_k(R_k.size());
  Eigen::MatrixXd rest(2 * f.arcs_fitted, 3);
  const auto tau_of = [&](std::size_t j) {
    return st.s[j].t - f.t_ref[static_cast<std::size_t>(st.arc[j])];
  };
  for (int sl = 0; sl < f.arcs_fitted; ++sl) {
    const auto u = static_cast<std::size_t>(sl);
    const auto& m = members[u];
    Eigen::MatrixXd Ak(2 * static_cast<Eigen::Index>(m.size()), 7);
    for (std::size_t i = 0; i < m.size(); ++i) {
      const auto r = 2 * static_cast<Eigen::Index>(i);
      Ak.block<2, 6>(r, 0) = DesignBlock(st.s[m[i]].W, tau_of(m[i]));
      Ak.block<2, 1>(r, 6) = st.s[m[i]].W * st.s[m[i]].p;
    }
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(Ak);
    const Eigen::Matrix<double, 6, 7> Rk =
        qr.matrixQR().topRows<6>().triangularView<Eigen::Upper>();
    R_k[u] = Rk.block<4, 4>(0, 0);
    S_k[u] = Rk.block<4, 2>(0, 4);
    c_k[u] = Rk.block<4, 1>(0, 6);
    rest.block<2, 3>(2 * sl, 0) = Rk.block<2, 3>(4, 4);
  }
  const Eigen::HouseholderQR<Eigen::MatrixXd> qa(rest);
  const Eigen::Matrix<double, 2, 3> Ra = qa.matrixQR().topRows<2>().triangularView<Eigen::Upper>();
  // Full rank: every diagonal entry of R above P epsilon of the largest (the threshold that
  // Eigen's ColPivHouseholderQR applies to its pivots).
  double largest = Ra.leftCols<2>().diagonal().cwiseAbs().maxCoeff();
  double smallest = Ra.leftCols<2>().diagonal().cwiseAbs().minCoeff();
  for (const auto& r : R_k) {
    largest = std::max(largest, r.diagonal().cwiseAbs().maxCoeff());
    smallest = std::min(smallest, r.diagonal().cwiseAbs().minCoeff());
  }
  if (!(largest > 0) || !(smallest > largest * P * std::numeric_limits<double>::epsilon()))
    return f;
  const Eigen::Matrix2d R_a = Ra.leftCols<2>();
  const Eigen::Matrix2d R_a_inv =
      R_a.triangularView<Eigen::Upper>().solve(Eigen::Matrix2d::Identity());
  f.C_aa = R_a_inv * R_a_inv.transpose();
  f.x.resize(P);
  f.x.tail<2>() = R_a.triangularView<Eigen::Upper>().solve(Ra.col(2));
  f.R_inv.resize(R_k.size());
  f.G.resize(R_k.size());
  for (int sl = 0; sl < f.arcs_fitted; ++sl) {
    const auto u = static_cast<std::size_t>(sl);
    const auto upper = R_k[u].triangularView<Eigen::Upper>();
    f.R_inv[u] = upper.solve(Eigen::Matrix4d::Identity());
    f.G[u] = upper.solve(S_k[u]);
    f.x.segment<4>(4 * sl) = upper.solve(c_k[u] - S_k[u] * f.x.tail<2>());
  }
  f.ssr = 0.0;
  for (int sl = 0; sl < f.arcs_fitted; ++sl) {
    Eigen::Matrix<double, 6, 1> xk;
    xk << f.x.segment<4>(4 * sl), f.x.tail<2>();
    const Eigen::Matrix<double, 6, 6> Ci = f.ArcCovariance(sl);
    for (std::size_t j : members[static_cast<std::size_t>(sl)]) {
      const Eigen::Matrix<double, 2, 6> D = DesignBlock(st.s[j].W, tau_of(j));
      f.res[j] = st.s[j].W * st.s[j].p - D * xk;
      f.ssr += f.res[j].squaredNorm();
      f.hat[j] = D * Ci * D.transpose();
    }
  }
  f.ok = true;
  return f;
}

/// The squared studentized residual of used sample j (2 dof, unscaled); NaN where the sample
/// fixes its own fit (leverage 1).
double Studentized(const Fit& f, std::size_t j) {
  const Eigen::Matrix2d M = Eigen::Matrix2d::Identity() - f.hat[j];
  if (M.determinant() < 1e-9) return core::kNaN;
  return f.res[j].dot(M.inverse() * f.res[j]);
}

/// The smallest noise variance (whitened units) taken as real: 1e-20 of the largest squared
/// whitened position, so that a noise-free path's rounding is no outlier.
double VarianceFloor(const State& st) {
  double m = 0.0;
  for (const auto& s : st.s) m = std::max(m, (s.W * s.p).squaredNorm());
  return std::max(1e-20 * m, 1e-300);
}

/// The q-quantile of v.
double Quantile(std::vector<double> v, double q) {
  if (v.empty()) return core::kNaN;
  auto it = v.begin() + static_cast<std::ptrdiff_t>(q * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), it, v.end());
  return *it;
}

/// The noise variance factor from the third divided differences of four consecutive samples,
/// which are pure noise on any parabola or straight line (a flight, a held or rolling body)
/// whatever the acceleration: their standardized squares follow chi^2_2 times the factor.
/// Windows that span an interval in `skip` (a contact found) are left out. Without `skip` the
/// lower quartile is used (chi^2_2's is 0.575), as a contact spoils the three windows across
/// it, which can be half of a clip of short arcs.
double ThirdDifferenceNoise(const State& st, const std::vector<int>& skip) {
  std::vector<double> d2;
  for (std::size_t j = 0; j + 3 < st.s.size(); ++j) {
    bool spans = false;
    for (int b : skip) spans |= b >= static_cast<int>(j) && b < static_cast<int>(j) + 3;
    if (spans) continue;
    Eigen::Vector2d D{0, 0};
    Eigen::Matrix2d V = Eigen::Matrix2d::Zero();
    for (std::size_t i = j; i < j + 4; ++i) {
      double w = 1.0;
      for (std::size_t m = j; m < j + 4; ++m)
        if (m != i) w /= st.s[i].t - st.s[m].t;
      D += w * st.s[i].p;
      V += w * w * st.s[i].cov;
    }
    d2.push_back(D.dot(V.inverse() * D));
  }
  if (d2.empty()) return VarianceFloor(st);
  const double f2 =
      skip.empty() ? Quantile(d2, 0.25) / 0.5753641449035618 : Median(d2) / kChi2MedianOf2;
  return std::max(f2, VarianceFloor(st));
}

/// Velocities across the intervals between consecutive samples, with their variance along u.
struct Intervals {
  std::vector<Eigen::Vector2d> v;  ///< interval (j, j + 1)
  std::vector<double> t;           ///< its middle
  std::vector<double> var_u;       ///< of u . v
};
Intervals IntervalsOf(const State& st, const Eigen::Vector2d& u, double f2) {
  Intervals I;
  for (std::size_t j = 0; j + 1 < st.s.size(); ++j) {
    const double h = st.s[j + 1].t - st.s[j].t;
    I.v.push_back((st.s[j + 1].p - st.s[j].p) / h);
    I.t.push_back(0.5 * (st.s[j].t + st.s[j + 1].t));
    I.var_u.push_back(f2 * u.dot((st.s[j].cov + st.s[j + 1].cov) * u) / (h * h));
  }
  return I;
}

/// Candidate contacts: intervals (j, j + 1) across which the velocity along "up" rises (from
/// the interval before to the interval after) by more than impulse_sigmas of its noise, the
/// largest within two intervals. Free flight makes it fall and a hand holding the body keeps
/// it, whatever the acceleration; only a contact raises it.
std::vector<int> RiseCandidates(const State& st, const Eigen::Vector2d& u, double f2,
                                const ArcOptions& o, std::vector<double>& z) {
  const Intervals I = IntervalsOf(st, u, f2);
  const std::size_t n = st.s.size();
  z.assign(n, -1e300);
  for (std::size_t j = 1; j + 2 < n; ++j) {
    const double sd = std::sqrt(I.var_u[j + 1] + I.var_u[j - 1]);
    z[j] = u.dot(I.v[j + 1] - I.v[j - 1]) / std::max(sd, 1e-300);
  }
  std::vector<int> out;
  for (std::size_t j = 1; j + 2 < n; ++j) {
    if (!(z[j] > o.impulse_sigmas)) continue;
    bool peak = true;
    for (std::size_t i = j > 2 ? j - 2 : 0; i <= std::min(n - 1, j + 2); ++i)
      if (i != j && (z[i] > z[j] || (z[i] == z[j] && i < j))) peak = false;
    if (peak) out.push_back(static_cast<int>(j));
  }
  return out;
}

/// The weighted median of `v` (weights w > 0).
double WeightedMedian(std::vector<std::pair<double, double>> v) {
  std::sort(v.begin(), v.end());
  double total = 0;
  for (const auto& [x, w] : v) total += w;
  double acc = 0;
  for (const auto& [x, w] : v) {
    acc += w;
    if (acc >= 0.5 * total) return x;
  }
  return v.empty() ? 0.0 : v.back().first;
}

/// A parabola with its own p, v and a fitted to the samples lo..hi: its acceleration, the
/// variances of its two components (from its own residuals) and its residual variance; false
/// when fewer than four samples or underdetermined.
bool FreeParabola(const State& st, std::size_t lo, std::size_t hi, Eigen::Vector2d& a,
                  Eigen::Vector2d& var_a, double& s2) {
  if (hi + 1 < lo + 4) return false;
  const double t0 = st.s[lo].t;
  Eigen::Matrix<double, 6, 6> N = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> r = Eigen::Matrix<double, 6, 1>::Zero();
  const auto design = [&](std::size_t j) {
    const double tau = st.s[j].t - t0;
    Eigen::Matrix<double, 2, 6> M;
    M << 1, 0, tau, 0, 0.5 * tau * tau, 0, 0, 1, 0, tau, 0, 0.5 * tau * tau;
    return M;
  };
  for (std::size_t j = lo; j <= hi; ++j) {
    const Eigen::Matrix<double, 2, 6> Mw = st.s[j].W * design(j);
    N += Mw.transpose() * Mw;
    r += Mw.transpose() * (st.s[j].W * st.s[j].p);
  }
  const Eigen::FullPivLU<Eigen::Matrix<double, 6, 6>> lu(N);
  if (!lu.isInvertible()) return false;
  const Eigen::Matrix<double, 6, 6> C = lu.inverse();
  const Eigen::Matrix<double, 6, 1> q = C * r;
  double ssr = 0;
  for (std::size_t j = lo; j <= hi; ++j)
    ssr += (st.s[j].W * (st.s[j].p - design(j) * q)).squaredNorm();
  s2 = std::max(ssr / (2.0 * static_cast<double>(hi + 1 - lo) - 6), VarianceFloor(st));
  a = q.tail<2>();
  var_a = {s2 * C(4, 4), s2 * C(5, 5)};
  return true;
}

/// The acceleration of the flights between the candidate contacts: each run of four or more
/// samples fitted with its own p, v and a, and the median of the a's weighted by their
/// precision (from each run's own residuals), so that a run that is no free flight (a hand, a
/// ball rolling) counts little. Zero when no run has four samples.
Eigen::Vector2d RunAcceleration(const State& st, const std::vector<int>& breaks,
                                std::vector<Eigen::Vector2d>* runs = nullptr) {
  std::vector<std::pair<double, double>> ax, ay;
  std::size_t lo = 0;
  for (std::size_t b = 0; b <= breaks.size(); ++b) {
    const std::size_t hi =
        b < breaks.size() ? static_cast<std::size_t>(breaks[b]) : st.s.size() - 1;
    Eigen::Vector2d a, var;
    double s2 = 0;
    if (FreeParabola(st, lo, hi, a, var, s2)) {
      ax.emplace_back(a.x(), 1 / std::max(var.x(), 1e-300));
      ay.emplace_back(a.y(), 1 / std::max(var.y(), 1e-300));
      if (runs) runs->push_back(a);
    }
    lo = hi + 1;
  }
  if (ax.empty()) return Eigen::Vector2d::Zero();
  return {WeightedMedian(ax), WeightedMedian(ay)};
}

/// Accelerations of short windows (eight samples, half overlapping) that fit a parabola within
/// their noise (`f2`, third differences), grouped where within 10 % of each other: the centre
/// of each group, the largest groups first (at most `keep`). Windows within one flight agree
/// on gravity, whatever the rest of the clip holds (a long hand-held stretch, many bounces).
std::vector<Eigen::Vector2d> WindowAccelerations(const State& st, double f2, std::size_t keep) {
  std::vector<Eigen::Vector2d> all;
  const std::size_t w = 8;
  for (std::size_t lo = 0; lo + w <= st.s.size(); lo += w / 2) {
    Eigen::Vector2d a, var;
    double s2 = 0;
    if (FreeParabola(st, lo, lo + w - 1, a, var, s2) && s2 < 3 * f2 && a.norm() > 0)
      all.push_back(a);
  }
  std::vector<std::pair<std::size_t, Eigen::Vector2d>> groups;
  std::vector<bool> used(all.size(), false);
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (used[i]) continue;
    std::vector<double> gx, gy;
    for (std::size_t j = i; j < all.size(); ++j)
      if (!used[j] && (all[j] - all[i]).norm() < 0.1 * all[i].norm()) {
        used[j] = true;
        gx.push_back(all[j].x());
        gy.push_back(all[j].y());
      }
    groups.emplace_back(gx.size(), Eigen::Vector2d(Median(gx), Median(gy)));
  }
  std::stable_sort(groups.begin(), groups.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<Eigen::Vector2d> out;
  for (std::size_t i = 0; i < groups.size() && i < keep; ++i) out.push_back(groups[i].second);
  return out;
}

/// The surface's outward normal for gravity along `a` (up = -a / |a|, or y_W when a is zero):
/// up turned by the surface angle phi toward gravity's perpendicular (core/frames.h's y_S).
Eigen::Vector2d NormalOf(const Eigen::Vector2d& a, double phi_rad) {
  const Eigen::Vector2d up = a.norm() > 0 ? Eigen::Vector2d(-a / a.norm()) : Eigen::Vector2d(0, 1);
  const Eigen::Vector2d x(up.y(), -up.x());
  return std::sin(phi_rad) * x + std::cos(phi_rad) * up;
}

/// The contacts, the first acceleration a0 and the noise factor f2. Candidates are found with
/// "up" along y_W (the frame upright within some tens of degrees), the noise from the third
/// differences away from them, a0 from the runs between them, and again along -a0; a candidate
/// is a contact where the motion along "up" reverses: down before and up after, the velocities
/// beside the interval carried to its middle along a0, each by more than reversal_sigmas.
void FindContacts(State& st, const ArcOptions& o, Eigen::Vector2d& a0, double& f2,
                  std::vector<Eigen::Vector2d>& runs) {
  a0 = Eigen::Vector2d::Zero();
  f2 = ThirdDifferenceNoise(st, {});
  if (st.s.size() < 4) return;
  std::vector<double> z;
  Eigen::Vector2d u = NormalOf(Eigen::Vector2d::Zero(), st.phi_rad);
  std::vector<int> cand = RiseCandidates(st, u, f2, o, z);
  f2 = ThirdDifferenceNoise(st, cand);
  for (int pass = 0; pass < 2; ++pass) {
    cand = RiseCandidates(st, u, f2, o, z);
    runs.clear();
    a0 = RunAcceleration(st, cand, &runs);
    u = NormalOf(a0, st.phi_rad);
  }
  const Intervals I = IntervalsOf(st, u, f2);
  for (int j : cand) {
    const auto i = static_cast<std::size_t>(j);
    const double vb = u.dot(I.v[i - 1] + a0 * (I.t[i] - I.t[i - 1]));
    const double va = u.dot(I.v[i + 1] - a0 * (I.t[i + 1] - I.t[i]));
    if (vb < -o.reversal_sigmas * std::sqrt(I.var_u[i - 1]) &&
        va > o.reversal_sigmas * std::sqrt(I.var_u[i + 1])) {
      st.breaks.push_back(j);
      st.impulse.push_back(z[i]);
    }
  }
}

/// Fits p and v of one arc to the samples `idx` with the acceleration `a` fixed; returns the
/// parameters (p, v at t_ref) and their unscaled covariance, false when underdetermined.
bool FitFixedA(const State& st, const std::vector<std::size_t>& idx, const Eigen::Vector2d& a,
               double t_ref, Eigen::Vector4d& q, Eigen::Matrix4d& C, double& ssr) {
  if (idx.size() < 2) return false;
  Eigen::Matrix4d N = Eigen::Matrix4d::Zero();
  Eigen::Vector4d rhs = Eigen::Vector4d::Zero();
  for (std::size_t j : idx) {
    const Sample& s = st.s[j];
    const double tau = s.t - t_ref;
    Eigen::Matrix<double, 2, 4> M;
    M << 1, 0, tau, 0, 0, 1, 0, tau;
    const Eigen::Matrix<double, 2, 4> Mw = s.W * M;
    N += Mw.transpose() * Mw;
    rhs += Mw.transpose() * (s.W * (s.p - 0.5 * a * tau * tau));
  }
  const Eigen::FullPivLU<Eigen::Matrix4d> lu(N);
  if (!lu.isInvertible()) return false;
  C = lu.inverse();
  q = C * rhs;
  ssr = 0.0;
  for (std::size_t j : idx) {
    const Sample& s = st.s[j];
    const double tau = s.t - t_ref;
    const Eigen::Vector2d pred = q.head<2>() + q.tail<2>() * tau + 0.5 * a * tau * tau;
    ssr += (s.W * (s.p - pred)).squaredNorm();
  }
  return true;
}

/// The squared standardized prediction error of sample j from a fixed-a fit of `idx`.
double PredictionChi2(const State& st, const std::vector<std::size_t>& idx, std::size_t j,
                      const Eigen::Vector2d& a, double f2) {
  const double t_ref = st.s[idx.front()].t;
  Eigen::Vector4d q;
  Eigen::Matrix4d C;
  double ssr = 0.0;
  if (!FitFixedA(st, idx, a, t_ref, q, C, ssr)) return core::kNaN;
  const Sample& s = st.s[j];
  const double tau = s.t - t_ref;
  Eigen::Matrix<double, 2, 4> M;
  M << 1, 0, tau, 0, 0, 1, 0, tau;
  const Eigen::Vector2d r = s.W * (s.p - (M * q + 0.5 * a * tau * tau));
  const Eigen::Matrix<double, 2, 4> Mw = s.W * M;
  const Eigen::Matrix2d V = Eigen::Matrix2d::Identity() + Mw * C * Mw.transpose();
  return r.dot(V.inverse() * r) / f2;
}

/// The velocity along u at time t of a fixed-a fit of `idx`, and its s.d.
void VelocityAlong(const State& st, const std::vector<std::size_t>& idx, const Eigen::Vector2d& a,
                   double f2, const Eigen::Vector2d& u, double t, double& v, double& sd) {
  const double t_ref = st.s[idx.front()].t;
  Eigen::Vector4d q;
  Eigen::Matrix4d C;
  double ssr = 0.0;
  if (!FitFixedA(st, idx, a, t_ref, q, C, ssr)) {
    v = 0.0;
    sd = 1e300;
    return;
  }
  v = u.dot(q.tail<2>() + a * (t - t_ref));
  Eigen::Vector4d g;
  g << 0, 0, u;
  sd = std::sqrt(f2 * g.dot(C * g));
}

/// The sweep that assigns samples to arcs (docs/tracking.md, "Joint arcs"). From a contact
/// (`anchor`: between samples anchor and anchor + 1; -1 for none, the sweep then starts at the
/// first sample) it walks forward and backward. Each arc starts from a core of min_arc_frames
/// samples that fits an arc with the acceleration a (up to two samples skipped beside a
/// contact: contact frames), and grows one sample at a time while each fits the arc through
/// the ones before it (one or two that do not, followed by one that does, are outliers). Where
/// the arc stops, a new arc starts if a core up to two samples on fits and meets it as a bounce
/// does (down before, up after, each by reversal_sigmas, meeting between their samples): a
/// contact; otherwise the samples from there on are not in flight (held, rolling, caught).
class Sweep {
 public:
  Sweep(State& st, const Eigen::Vector2d& a, double f2, const ArcOptions& o)
      : st_(st), a_(a), f2_(f2), o_(o), u_(NormalOf(a, st.phi_rad)) {}

  void Run(int anchor) {
    st_.breaks.clear();
    st_.impulse.clear();
    std::fill(st_.role.begin(), st_.role.end(), ArcFrameRole::kArc);
    std::fill(st_.chi2.begin(), st_.chi2.end(), core::kNaN);
    std::vector<std::size_t> fwd, bwd;
    for (std::size_t j = static_cast<std::size_t>(anchor + 1); j < st_.s.size(); ++j)
      fwd.push_back(j);
    for (int j = anchor; j >= 0; --j) bwd.push_back(static_cast<std::size_t>(j));
    if (anchor >= 0) {
      st_.breaks.push_back(anchor);
      st_.impulse.push_back(anchor_impulse_);
    }
    Walk(fwd, +1);
    Walk(bwd, -1);
    std::vector<std::pair<int, double>> b;
    for (std::size_t i = 0; i < st_.breaks.size(); ++i)
      b.emplace_back(st_.breaks[i], st_.impulse[i]);
    std::sort(b.begin(), b.end());
    st_.breaks.clear();
    st_.impulse.clear();
    for (const auto& [x, z] : b) {
      st_.breaks.push_back(x);
      st_.impulse.push_back(z);
    }
    st_.AssignArcs();
  }
  double anchor_impulse_ = core::kNaN;
  /// The contacts found from the motion (FindContacts): where no arc follows a flight, one of
  /// these still makes a contact (the flight after it too short to fit).
  std::vector<std::pair<int, double>> detected_;

 private:
  bool Fits(const std::vector<std::size_t>& in, std::size_t j) {
    const double c = PredictionChi2(st_, in, j, a_, f2_);
    st_.chi2[j] = c;
    return !(c > o_.outlier_chi2);
  }
  bool CoreFits(const std::vector<std::size_t>& core) {
    Eigen::Vector4d q;
    Eigen::Matrix4d C;
    double ssr = 0.0;
    return FitFixedA(st_, core, a_, st_.s[core.front()].t, q, C, ssr) &&
           ssr / f2_ < o_.outlier_chi2;
  }
  std::vector<std::size_t> Slice(const std::vector<std::size_t>& order, std::size_t from,
                                 std::size_t n) {
    return {order.begin() + static_cast<std::ptrdiff_t>(from),
            order.begin() + static_cast<std::ptrdiff_t>(std::min(order.size(), from + n))};
  }

  /// Whether `earlier` and `later` (arcs in time order) meet as a bounce; sets z, the rise of
  /// the velocity along up in s.d.
  bool Bounce(const std::vector<std::size_t>& earlier, const std::vector<std::size_t>& later,
              double& z) {
    double t_e = -1e300, t_l = 1e300;
    for (std::size_t j : earlier) t_e = std::max(t_e, st_.s[j].t);
    for (std::size_t j : later) t_l = std::min(t_l, st_.s[j].t);
    const double t_j = 0.5 * (t_e + t_l);
    double vb = 0, sb = 0, va = 0, sa = 0;
    VelocityAlong(st_, earlier, a_, f2_, u_, t_j, vb, sb);
    VelocityAlong(st_, later, a_, f2_, u_, t_j, va, sa);
    z = (va - vb) / std::hypot(sb, sa);
    if (!(vb < -o_.reversal_sigmas * sb && va > o_.reversal_sigmas * sa)) return false;
    // Where their heights meet (linear in t with a shared a): between their samples, give or
    // take one spacing.
    const auto height = [&](const std::vector<std::size_t>& idx, double t) {
      const double t_ref = st_.s[idx.front()].t;
      Eigen::Vector4d q;
      Eigen::Matrix4d C;
      double ssr = 0.0;
      FitFixedA(st_, idx, a_, t_ref, q, C, ssr);
      const double tau = t - t_ref;
      return u_.dot(q.head<2>() + q.tail<2>() * tau + 0.5 * a_ * tau * tau);
    };
    const double d0 = height(later, t_j) - height(earlier, t_j);
    const double t_star = t_j - d0 / (va - vb);
    const double gap = t_l - t_e;
    return t_star > t_e - gap && t_star < t_l + gap;
  }

  /// A new arc after `cur` in the walk's direction, from order[m] on: its samples and its
  /// position in `order`; empty when none.
  std::vector<std::size_t> NewArc(const std::vector<std::size_t>& order, std::size_t m,
                                  const std::vector<std::size_t>& cur, int dir, std::size_t& at,
                                  double& z) {
    const auto core = static_cast<std::size_t>(o_.min_arc_frames);
    for (std::size_t off = 0; off <= 2 && m + off + core <= order.size(); ++off) {
      std::vector<std::size_t> c = Slice(order, m + off, core);
      if (!CoreFits(c)) continue;
      // A short core may not show the reversal clearly: it grows (up to 8 samples) while it
      // fits, and the meeting is tested at each size.
      for (;;) {
        const bool ok = dir > 0 ? Bounce(cur, c, z) : Bounce(c, cur, z);
        if (ok) {
          at = m + off;
          return c;
        }
        const std::size_t next = m + off + c.size();
        if (c.size() >= 8 || next >= order.size() || !Fits(c, order[next])) break;
        c.push_back(order[next]);
      }
    }
    return {};
  }

  /// The first contact found from the motion (detected_) between samples `from` and `to`
  /// (break indices, inclusive); -1 when none.
  int Detected(int from, int to, double& z) const {
    for (const auto& [d, dz] : detected_)
      if (d >= from && d <= to) {
        z = dz;
        return d;
      }
    return -1;
  }

  /// The length of the run of samples from order[m] on (3 to max_outlier_run of them) after
  /// which two samples in a row fit the arc `cur`, the first its prediction and the second the
  /// arc through it; 0 when none.
  std::size_t OutlierRun(const std::vector<std::size_t>& cur, const std::vector<std::size_t>& order,
                         std::size_t m) {
    const auto most = static_cast<std::size_t>(o_.max_outlier_run);
    for (std::size_t run = 3; run <= most && m + run + 1 < order.size(); ++run) {
      if (!Fits(cur, order[m + run])) continue;
      std::vector<std::size_t> with = cur;
      with.push_back(order[m + run]);
      if (Fits(with, order[m + run + 1])) return run;
    }
    return 0;
  }

  /// Walks `order` (samples from a contact outward; dir +1 forward in time, -1 backward).
  void Walk(const std::vector<std::size_t>& order, int dir) {
    const auto core = static_cast<std::size_t>(o_.min_arc_frames);
    const auto pos = [&](int sample) {  // its place in a forward order
      return static_cast<std::size_t>(sample) - order.front();
    };
    std::size_t m = 0;
    while (m < order.size()) {
      // An arc starts from a core (up to two samples skipped beside the contact).
      std::vector<std::size_t> cur;
      for (std::size_t off = 0; off <= 2 && m + off + core <= order.size(); ++off)
        if (CoreFits(Slice(order, m + off, core))) {
          cur = Slice(order, m + off, core);
          for (std::size_t i = m; i < m + off; ++i) st_.role[order[i]] = ArcFrameRole::kContact;
          m += off + core;
          break;
        }
      double z = 0;
      if (cur.empty()) {
        // A flight too short to fit, up to the next contact found from the motion: its
        // samples are a short arc (its impacts found, not measured).
        const int d =
            dir > 0 ? Detected(static_cast<int>(order[m]), static_cast<int>(order.back()) - 1, z)
                    : -1;
        if (d >= 0) {
          st_.breaks.push_back(d);
          st_.impulse.push_back(z);
          m = pos(d + 1);
          continue;
        }
        // Nothing fits: the first flight beside the anchor is left to the joint fit's tests;
        // after a contact, the samples too few for a core are its flight (a short arc), and
        // those after them are not in flight.
        if (m > 0)
          for (std::size_t i = m + core - 1; i < order.size(); ++i)
            st_.role[order[i]] = ArcFrameRole::kNotInFlight;
        return;
      }
      // The arc grows while each sample fits it.
      bool next_arc = false;
      while (m < order.size() && !next_arc) {
        if (Fits(cur, order[m])) {
          cur.push_back(order[m++]);
          continue;
        }
        if (m + 1 < order.size() && Fits(cur, order[m + 1])) {
          st_.role[order[m]] = ArcFrameRole::kOutlier;
          ++m;
          continue;
        }
        std::size_t at = 0;
        std::vector<std::size_t> next = NewArc(order, m, cur, dir, at, z);
        if (!next.empty()) {
          for (std::size_t i = m; i < at; ++i) st_.role[order[i]] = ArcFrameRole::kContact;
          // The contact frames skipped belong to the arc they follow in the walk (beside the
          // contact on its side).
          const int b = dir > 0 ? static_cast<int>(order[at]) - 1 : static_cast<int>(order[at]);
          st_.breaks.push_back(b);
          st_.impulse.push_back(z);
          cur = next;
          m = at + next.size();
          continue;
        }
        if (m + 2 < order.size() && Fits(cur, order[m + 2])) {
          st_.role[order[m]] = st_.role[order[m + 1]] = ArcFrameRole::kOutlier;
          m += 2;
          continue;
        }
        // No arc follows here; a contact found from the motion may still (a short flight).
        const int last = static_cast<int>(*std::max_element(cur.begin(), cur.end()));
        const int d =
            dir > 0 ? Detected(last, static_cast<int>(order[std::min(m + 1, order.size() - 1)]), z)
                    : -1;
        if (d >= 0) {
          for (std::size_t i = m; i < pos(d + 1); ++i) st_.role[order[i]] = ArcFrameRole::kContact;
          st_.breaks.push_back(d);
          st_.impulse.push_back(z);
          m = pos(d + 1);
          next_arc = true;
          continue;
        }
        // A longer run off the arc, followed by two samples on it: outliers too (the ball cut
        // by the frame's edge, half hidden or smeared, for a few frames of one flight).
        const std::size_t run = OutlierRun(cur, order, m);
        if (run > 0) {
          for (std::size_t i = m; i < m + run; ++i) st_.role[order[i]] = ArcFrameRole::kOutlier;
          m += run;
          continue;
        }
        for (std::size_t i = m; i < order.size(); ++i)
          st_.role[order[i]] = ArcFrameRole::kNotInFlight;
        return;
      }
    }
  }

  State& st_;
  Eigen::Vector2d a_;
  double f2_;
  const ArcOptions& o_;
  Eigen::Vector2d u_;
};

/// The samples of arc k, in time order.
std::vector<std::size_t> SamplesOf(const State& st, int k) {
  std::vector<std::size_t> v;
  for (std::size_t j = 0; j < st.s.size(); ++j)
    if (st.arc[j] == k) v.push_back(j);
  return v;
}

/// Which used samples lie beside a contact: those with no other used sample of their arc
/// between them and a contact on one of its sides (the first used sample of an arc after a
/// contact, the last before one). Holds for the roles as they were when it was made.
class BesideContact {
 public:
  explicit BesideContact(const State& st)
      : st_(st),
        first_(static_cast<std::size_t>(st.Arcs()), st.s.size()),
        last_(static_cast<std::size_t>(st.Arcs()), st.s.size()) {
    for (std::size_t j = 0; j < st.s.size(); ++j) {
      if (!st.Used(j)) continue;
      const auto k = static_cast<std::size_t>(st.arc[j]);
      if (first_[k] == st.s.size()) first_[k] = j;
      last_[k] = j;
    }
  }
  /// For a used sample j.
  bool operator()(std::size_t j) const {
    const int k = st_.arc[j];
    const auto u = static_cast<std::size_t>(k);
    return (k > 0 && first_[u] == j) || (k + 1 < st_.Arcs() && last_[u] == j);
  }

 private:
  const State& st_;
  std::vector<std::size_t> first_, last_;
};

/// Leaves out, one at a time, the used sample with the largest squared studentized residual
/// over the robust noise level while it exceeds outlier_chi2 (at most max_excluded_fraction of
/// the samples in all): a contact frame when it is the last of its arc toward a contact, else
/// an outlier. Returns the last fit.
Fit ExcludeOutliers(State& st, const ArcOptions& o) {
  const double floor = VarianceFloor(st);
  const auto excluded = [&] {
    return std::count_if(st.role.begin(), st.role.end(), [](ArcFrameRole r) {
      return r == ArcFrameRole::kContact || r == ArcFrameRole::kOutlier;
    });
  };
  const double cap = o.max_excluded_fraction * static_cast<double>(st.s.size());
  for (;;) {
    Fit f = JointFit(st, o.min_arc_frames);
    if (!f.ok) return f;
    std::vector<double> d2(st.s.size(), core::kNaN), all;
    for (std::size_t j = 0; j < st.s.size(); ++j)
      if (st.Used(j) && f.slot[static_cast<std::size_t>(st.arc[j])] >= 0) {
        d2[j] = Studentized(f, j);
        if (std::isfinite(d2[j])) all.push_back(d2[j]);
      }
    const double s2 = std::max(all.empty() ? 0.0 : Median(all) / kChi2MedianOf2, floor);
    // The worst against its threshold: contact_chi2 beside a contact, outlier_chi2 elsewhere.
    std::size_t worst = st.s.size();
    double worst_ratio = 0;
    const BesideContact beside(st);
    for (std::size_t j = 0; j < st.s.size(); ++j) {
      if (!std::isfinite(d2[j])) continue;
      st.chi2[j] = d2[j] / s2;
      const double ratio = st.chi2[j] / (beside(j) ? o.contact_chi2 : o.outlier_chi2);
      if (worst == st.s.size() || ratio > worst_ratio) {
        worst = j;
        worst_ratio = ratio;
      }
    }
    if (worst == st.s.size() || !(worst_ratio > 1) || static_cast<double>(excluded() + 1) > cap)
      return f;
    st.role[worst] = beside(worst) ? ArcFrameRole::kContact : ArcFrameRole::kOutlier;
  }
}

/// The contacts whose arcs, once fitted, do not reverse along "up" (down before the meeting,
/// up after it, each by 3 s.e.) are not contacts: the first such is removed (its arcs merged,
/// the contact frames beside it given back); false when every contact holds.
bool MergeFalseContact(State& st, const Fit& f) {
  const int P = f.params;
  const Eigen::Vector2d a = f.x.tail<2>();
  const Eigen::Vector2d u = NormalOf(a, st.phi_rad);
  const double s2 = f.ssr / (f.rows - P);
  for (std::size_t b = 0; b < st.breaks.size(); ++b) {
    const int s0 = f.slot[b], s1 = f.slot[b + 1];
    if (s0 < 0 || s1 < 0) continue;
    const double t0 = f.t_ref[b], t1 = f.t_ref[b + 1];
    // Heights along u: h_k(t) = u.(p_k + v_k (t - t_k) + a (t - t_k)^2 / 2); their difference is
    // linear in t.
    const Eigen::Vector2d p0 = f.x.segment<2>(4 * s0), v0 = f.x.segment<2>(4 * s0 + 2);
    const Eigen::Vector2d p1 = f.x.segment<2>(4 * s1), v1 = f.x.segment<2>(4 * s1 + 2);
    const auto c0 = [&](const Eigen::Vector2d& p, const Eigen::Vector2d& v, double tk) {
      return Eigen::Vector2d(p - v * tk + 0.5 * a * tk * tk);
    };
    const double alpha = u.dot(c0(p1, v1, t1) - c0(p0, v0, t0));
    const double beta = u.dot((v1 - a * t1) - (v0 - a * t0));
    const double t_star = beta != 0 ? -alpha / beta : 0.5 * (t0 + t1);
    const auto sd = [&](int sl, double tk) {
      Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
      g.segment<2>(2) = u;
      g.tail<2>() = u * (t_star - tk);
      return std::sqrt(s2 * g.dot(f.ArcCovariance(sl) * g));
    };
    const double vb = u.dot(v0 + a * (t_star - t0)), va = u.dot(v1 + a * (t_star - t1));
    if (vb < -3 * sd(s0, t0) && va > 3 * sd(s1, t1)) continue;
    st.breaks.erase(st.breaks.begin() + static_cast<std::ptrdiff_t>(b));
    st.impulse.erase(st.impulse.begin() + static_cast<std::ptrdiff_t>(b));
    st.AssignArcs();
    for (std::size_t j = 0; j < st.s.size(); ++j)
      if (st.role[j] == ArcFrameRole::kContact || st.role[j] == ArcFrameRole::kShortArc)
        st.role[j] = ArcFrameRole::kArc;
    return true;
  }
  return false;
}

/// Samples of arcs with fewer than min_arc used samples are kShortArc (and back to kArc when
/// their arc has enough again).
void MarkShortArcs(State& st, int min_arc) {
  for (int k = 0; k < st.Arcs(); ++k) {
    const auto idx = SamplesOf(st, k);
    int used = 0;
    for (std::size_t j : idx)
      if (st.role[j] == ArcFrameRole::kArc || st.role[j] == ArcFrameRole::kShortArc) ++used;
    for (std::size_t j : idx) {
      if (used < min_arc && st.role[j] == ArcFrameRole::kArc) st.role[j] = ArcFrameRole::kShortArc;
      if (used >= min_arc && st.role[j] == ArcFrameRole::kShortArc) st.role[j] = ArcFrameRole::kArc;
    }
  }
}

/// Each contact's place between its two arcs, by maximum likelihood: the break moved by up to
/// two samples either way (each arc keeping min_arc_frames samples) to where the joint fit's
/// residual sum of squares is least. A sample within a frame of a contact lies near both arcs,
/// and the test that grew the arc may have taken it into the wrong one. Then each contact
/// frame is given back to its arc when it fits it (prediction chi^2 within outlier_chi2).
/// True when something moved.
bool RefineBoundaries(State& st, Fit& f, const ArcOptions& o) {
  bool moved = false;
  for (std::size_t b = 0; b < st.breaks.size(); ++b) {
    const int lo = b > 0 ? st.breaks[b - 1] + 1 : 0;
    const int hi =
        b + 1 < st.breaks.size() ? st.breaks[b + 1] - 1 : static_cast<int>(st.s.size()) - 2;
    const int b0 = st.breaks[b];
    int best = b0;
    double best_ssr = f.ssr;
    for (int x = std::max(lo, b0 - 2); x <= std::min(hi, b0 + 2); ++x) {
      if (x == b0) continue;
      st.breaks[b] = x;
      st.AssignArcs();
      bool enough = true;
      for (int k : {static_cast<int>(b), static_cast<int>(b) + 1}) {
        int used = 0;
        for (std::size_t j : SamplesOf(st, k)) used += st.Used(j);
        enough &= used >= o.min_arc_frames;
      }
      if (!enough) continue;
      const Fit g = JointFit(st, o.min_arc_frames);
      if (g.ok && g.rows == f.rows && g.ssr < best_ssr) {
        best = x;
        best_ssr = g.ssr;
      }
    }
    st.breaks[b] = best;
    st.AssignArcs();
    if (best != b0) {
      moved = true;
      f = JointFit(st, o.min_arc_frames);
      if (!f.ok) return moved;
    }
  }
  // Contact frames that fit their arc after all.
  const double s2 = std::max(f.ssr / (f.rows - f.params), VarianceFloor(st));
  for (std::size_t j = 0; j < st.s.size(); ++j) {
    if (st.role[j] != ArcFrameRole::kContact) continue;
    std::vector<std::size_t> in;
    for (std::size_t i : SamplesOf(st, st.arc[j]))
      if (st.Used(i)) in.push_back(i);
    if (static_cast<int>(in.size()) < o.min_arc_frames) continue;
    const double c = PredictionChi2(st, in, j, f.x.tail<2>(), s2);
    st.chi2[j] = c;
    if (c < o.outlier_chi2) {
      st.role[j] = ArcFrameRole::kArc;
      moved = true;
    }
  }
  if (moved) f = JointFit(st, o.min_arc_frames);
  return moved;
}

/// The first and last arcs end where the clip's flight does (a hand, a ball rolling or
/// caught): their outer samples each passed the test that grew the arc, but the arc as a whole
/// may still not fit (the sum of its squared residuals over the noise beyond chi^2's 1 - 1e-3
/// quantile for its degrees of freedom). Its outermost samples are then not in flight, one at
/// a time, until it fits or holds min_arc_frames. True when a sample was dropped.
bool TrimOpenEnds(State& st, Fit& f, const ArcOptions& o) {
  bool dropped = false;
  for (int end = 0; end < 2 && f.ok; ++end) {
    const int k = end == 0 ? 0 : st.Arcs() - 1;
    if (st.breaks.empty()) break;
    for (;;) {
      const double s2 = std::max(f.ssr / (f.rows - f.params), VarianceFloor(st));
      std::vector<std::size_t> used;
      double ssr = 0;
      for (std::size_t j : SamplesOf(st, k))
        if (st.Used(j)) {
          used.push_back(j);
          ssr += f.res[j].squaredNorm();
        }
      if (static_cast<int>(used.size()) <= o.min_arc_frames ||
          f.slot[static_cast<std::size_t>(k)] < 0)
        break;
      const double dof = 2.0 * static_cast<double>(used.size()) - 4;
      const double limit = boost::math::quantile(boost::math::chi_squared(dof), 1 - 1e-3);
      if (ssr / s2 <= limit) break;
      st.role[end == 0 ? used.front() : used.back()] = ArcFrameRole::kNotInFlight;
      dropped = true;
      f = JointFit(st, o.min_arc_frames);
    }
  }
  return dropped;
}

/// The segmentation and the fit from the acceleration `a` and the contact `anchor`: sweep,
/// outliers, false contacts, open ends and boundaries, repeated with the fitted acceleration
/// and noise until the samples' roles settle.
Fit Settle(State& st, const ArcOptions& o, Eigen::Vector2d a, double f2, int anchor,
           double anchor_z, const std::vector<std::pair<int, double>>& detected) {
  Fit f;
  const auto exclude = [&] {
    MarkShortArcs(st, o.min_arc_frames);
    f = ExcludeOutliers(st, o);
    if (!f.ok) return false;
    MarkShortArcs(st, o.min_arc_frames);
    f = JointFit(st, o.min_arc_frames);
    return f.ok;
  };
  for (int round = 0; round < 6; ++round) {
    const std::vector<ArcFrameRole> roles = st.role;
    const std::vector<int> breaks = st.breaks;
    Sweep sweep(st, a, f2, o);
    sweep.anchor_impulse_ = anchor_z;
    sweep.detected_ = detected;
    sweep.Run(anchor);
    if (!exclude()) return f;
    while (MergeFalseContact(st, f))
      if (!exclude()) return f;
    if (TrimOpenEnds(st, f, o) && !exclude()) return f;
    for (int pass = 0; pass < 3 && RefineBoundaries(st, f, o); ++pass)
      if (!f.ok || !exclude()) return f;
    anchor = st.breaks.empty() ? -1 : st.breaks.front();
    anchor_z = st.impulse.empty() ? core::kNaN : st.impulse.front();
    a = f.x.tail<2>();
    f2 = std::max(f.ssr / (f.rows - f.params), VarianceFloor(st));
    if (round > 0 && st.role == roles && st.breaks == breaks) break;
  }
  return f;
}

/// The contacts found from the motion, then the segmentation settled from the first
/// acceleration (the runs' weighted median), from each run's own and from the largest groups
/// of short windows' (WindowAccelerations), keeping the one of least
/// cost: the squared residuals of the samples fitted over the noise of the third differences
/// (the same for every candidate), outlier_chi2 for each sample left out, and ln(samples) per
/// parameter (the Bayesian information criterion's). A run that is no flight (a hand carrying
/// the body in a straight line, a near zero) can outweigh the others in the median but
/// explains only itself; a wrong acceleration leaves samples out or cuts flights into arcs.
Fit Segment(State& st, const ArcOptions& o) {
  Eigen::Vector2d a0;
  double f2 = 0.0;
  std::vector<Eigen::Vector2d> runs;
  FindContacts(st, o, a0, f2, runs);
  const int anchor = st.breaks.empty() ? -1 : st.breaks.front();
  const double anchor_z = st.impulse.empty() ? core::kNaN : st.impulse.front();
  std::vector<std::pair<int, double>> detected;
  for (std::size_t i = 0; i < st.breaks.size(); ++i)
    detected.emplace_back(st.breaks[i], st.impulse[i]);
  std::vector<Eigen::Vector2d> tried;
  std::vector<Eigen::Vector2d> cands{a0};
  cands.insert(cands.end(), runs.begin(), runs.end());
  for (const auto& a : WindowAccelerations(st, f2, 4)) cands.push_back(a);
  State best = st;
  Fit best_fit;
  double best_cost = std::numeric_limits<double>::infinity();
  const double n = static_cast<double>(st.s.size());
  for (const auto& a : cands) {
    bool near = false;
    for (const auto& t : tried) near |= (a - t).norm() < 0.05 * std::max(a.norm(), t.norm());
    if (near || !(a.norm() > 0)) continue;
    tried.push_back(a);
    State trial = st;
    const Fit f = Settle(trial, o, a, f2, anchor, anchor_z, detected);
    if (!f.ok) continue;
    // The noise of the fit: the third differences' where the arcs fit within it, else the
    // fit's own (a drift along the flights that the third differences do not see), at the
    // price of the log of its ratio per coordinate (the profile likelihood's).
    const double f2_fit = std::max(f2, f.ssr / std::max(f.rows - f.params, 1));
    const double cost = f.ssr / f2_fit + f.rows * std::log(f2_fit / f2) +
                        o.outlier_chi2 * (n - f.rows / 2.0) + std::log(n) * f.params;
    if (cost < best_cost) {
      best_cost = cost;
      best = std::move(trial);
      best_fit = f;
    }
  }
  st = std::move(best);
  return best_fit;
}

/// The straight line theta = theta_k + w (t - t_k) of each fitted arc (unwrapped), with
/// standard errors from its residuals.
void FitAngles(const State& st, const Fit& f, std::vector<FlightArc>& arcs) {
  for (int k = 0; k < st.Arcs(); ++k) {
    if (f.slot[static_cast<std::size_t>(k)] < 0) continue;
    std::vector<double> tau, th;
    for (std::size_t j : SamplesOf(st, k)) {
      if (!st.Used(j)) continue;
      tau.push_back(st.s[j].t - f.t_ref[static_cast<std::size_t>(k)]);
      double x = st.s[j].theta;
      if (!th.empty())
        x -= 2 * std::numbers::pi * std::round((x - th.back()) / (2 * std::numbers::pi));
      th.push_back(x);
    }
    const double n = static_cast<double>(tau.size());
    double mt = 0, my = 0;
    for (std::size_t i = 0; i < tau.size(); ++i) {
      mt += tau[i] / n;
      my += th[i] / n;
    }
    double stt = 0, sty = 0;
    for (std::size_t i = 0; i < tau.size(); ++i) {
      stt += (tau[i] - mt) * (tau[i] - mt);
      sty += (tau[i] - mt) * (th[i] - my);
    }
    FlightArc& arc = arcs[static_cast<std::size_t>(k)];
    arc.w_rad_s = stt > 0 ? sty / stt : 0.0;
    arc.theta_W_rad = my - arc.w_rad_s * mt;
    double ssr = 0;
    for (std::size_t i = 0; i < tau.size(); ++i)
      ssr += std::pow(th[i] - arc.theta_W_rad - arc.w_rad_s * tau[i], 2);
    const double s2 = n > 2 ? ssr / (n - 2) : 0.0;
    arc.w_se_rad_s = stt > 0 ? std::sqrt(s2 / stt) : 0.0;
    arc.theta_se_rad = std::sqrt(s2 * (1 / n + mt * mt / std::max(stt, 1e-300)));
  }
}

/// A depth line per fitted arc: z = s_ref / size = z0 + z1 (t - t_k), with standard errors;
/// false when some fitted arc has fewer than 3 sizes.
struct DepthLine {
  double z0 = 1, z1 = 0, se0 = 0, se1 = 0;
};
bool FitDepthLines(const State& st, const Fit& f, std::vector<DepthLine>& lines) {
  std::vector<double> all;
  for (std::size_t j = 0; j < st.s.size(); ++j)
    if (st.Used(j) && std::isfinite(st.s[j].size) && st.s[j].size > 0) all.push_back(st.s[j].size);
  const double s_ref = Median(all);
  lines.assign(static_cast<std::size_t>(st.Arcs()), DepthLine{});
  for (int k = 0; k < st.Arcs(); ++k) {
    if (f.slot[static_cast<std::size_t>(k)] < 0) continue;
    std::vector<double> tau, z;
    for (std::size_t j : SamplesOf(st, k))
      if (st.Used(j) && std::isfinite(st.s[j].size) && st.s[j].size > 0) {
        tau.push_back(st.s[j].t - f.t_ref[static_cast<std::size_t>(k)]);
        z.push_back(s_ref / st.s[j].size);
      }
    if (tau.size() < 3) return false;
    const double n = static_cast<double>(tau.size());
    double mt = 0, mz = 0;
    for (std::size_t i = 0; i < tau.size(); ++i) {
      mt += tau[i] / n;
      mz += z[i] / n;
    }
    double stt = 0, stz = 0;
    for (std::size_t i = 0; i < tau.size(); ++i) {
      stt += (tau[i] - mt) * (tau[i] - mt);
      stz += (tau[i] - mt) * (z[i] - mz);
    }
    DepthLine& L = lines[static_cast<std::size_t>(k)];
    L.z1 = stt > 0 ? stz / stt : 0.0;
    L.z0 = mz - L.z1 * mt;  // at t_k (tau = 0); mt is 0 when every sample has a size
    double ssr = 0;
    for (std::size_t i = 0; i < tau.size(); ++i) ssr += std::pow(z[i] - L.z0 - L.z1 * tau[i], 2);
    const double s2 = ssr / (n - 2);
    L.se1 = stt > 0 ? std::sqrt(s2 / stt) : 0.0;
    L.se0 = std::sqrt(s2 * (1 / n + mt * mt / std::max(stt, 1e-300)));
  }
  return true;
}

/// The state with every used sample's position moved to where the body would be seen at the
/// reference depth: c + (p - c) z(t) (a pinhole camera: image offsets from the principal point
/// scale as 1 / depth).
State Corrected(const State& st, const Fit& f, const std::vector<DepthLine>& lines,
                const Eigen::Vector2d& c) {
  State out = st;
  for (std::size_t j = 0; j < st.s.size(); ++j) {
    const auto k = static_cast<std::size_t>(st.arc[j]);
    if (!st.Used(j) || f.slot[k] < 0) continue;
    const double z = lines[k].z0 + lines[k].z1 * (st.s[j].t - f.t_ref[k]);
    out.s[j].p = c + (st.s[j].p - c) * z;
    out.s[j].cov = st.s[j].cov * z * z;
    out.s[j].W = st.s[j].W / z;
  }
  return out;
}

/// The depth correction (FlightArcs::depth_*): measured when some arc's depth rate exceeds 3
/// s.e.; applied when asked, then `f` becomes the corrected fit.
void DepthCorrection(State& st, const ArcOptions& o, Fit& f, FlightArcs& out) {
  std::vector<DepthLine> lines;
  if (!FitDepthLines(st, f, lines)) return;
  bool significant = false;
  for (int k = 0; k < st.Arcs(); ++k) {
    const DepthLine& L = lines[static_cast<std::size_t>(k)];
    FlightArc& arc = out.arcs[static_cast<std::size_t>(k)];
    if (f.slot[static_cast<std::size_t>(k)] < 0) continue;
    arc.depth_rate_per_s = L.z1 / L.z0;
    arc.depth_rate_se_per_s = L.se1 / L.z0;
    if (std::abs(L.z1) > 3 * L.se1) significant = true;
  }
  if (!significant || !o.principal_point_W) return;
  const Eigen::Vector2d c = *o.principal_point_W;
  const Fit g = JointFit(Corrected(st, f, lines, c), o.min_arc_frames);
  if (!g.ok) return;
  out.depth_measured = true;
  if (!o.correct_depth) {
    out.x_other = g.x;
    return;
  }
  out.depth_applied = true;
  out.x_other = f.x;
  for (int k = 0; k < st.Arcs(); ++k) {
    for (int which = 0; which < 2; ++which) {
      std::vector<DepthLine> moved = lines;
      DepthLine& L = moved[static_cast<std::size_t>(k)];
      (which == 0 ? L.z0 : L.z1) += which == 0 ? L.se0 : L.se1;
      const Fit h = JointFit(Corrected(st, f, moved, c), o.min_arc_frames);
      out.x_depth_perturbed.push_back(h.ok ? h.x : g.x);
    }
  }
  st = Corrected(st, f, lines, c);
  f = g;
}

/// For finding the arcs of a body that moves in depth: every position moved to the reference
/// depth, c + (p - c) z, with z = reference size / apparent size smoothed by a straight line
/// through the seven samples about each (no arcs needed yet). True when done: when every
/// sample has a size and z changes over the clip by 1 % or more and 10 times its scatter.
bool PreCorrectDepth(State& st, const Eigen::Vector2d& c) {
  const std::size_t n = st.s.size();
  std::vector<double> sizes;
  for (const auto& s : st.s) {
    if (!(std::isfinite(s.size) && s.size > 0)) return false;
    sizes.push_back(s.size);
  }
  if (n < 7) return false;
  const double s_ref = Median(sizes);
  std::vector<double> z(n), zs(n), dev;
  for (std::size_t j = 0; j < n; ++j) z[j] = s_ref / st.s[j].size;
  for (std::size_t j = 0; j < n; ++j) {
    const std::size_t lo = j >= 3 ? std::min(j - 3, n - 7) : 0, hi = lo + 7;
    double mt = 0, mz = 0;
    for (std::size_t i = lo; i < hi; ++i) {
      mt += st.s[i].t / 7;
      mz += z[i] / 7;
    }
    double stt = 0, stz = 0;
    for (std::size_t i = lo; i < hi; ++i) {
      stt += (st.s[i].t - mt) * (st.s[i].t - mt);
      stz += (st.s[i].t - mt) * (z[i] - mz);
    }
    zs[j] = mz + (stt > 0 ? stz / stt : 0.0) * (st.s[j].t - mt);
    dev.push_back(std::abs(z[j] - zs[j]));
  }
  const auto [lo, hi] = std::minmax_element(zs.begin(), zs.end());
  if (!(*hi - *lo > std::max(0.01, 10 * 1.4826 * Median(dev)))) return false;
  for (std::size_t j = 0; j < n; ++j) {
    st.s[j].p = c + (st.s[j].p - c) * zs[j];
    st.s[j].cov *= zs[j] * zs[j];
    st.s[j].W /= zs[j];
  }
  return true;
}

/// The plane's perspective (FlightArcs::perspective_*): a body that moves in one plane seen by a
/// pinhole camera is at a depth Z with 1 / Z affine in its image offset u = p - c from the
/// principal point, Z proportional to 1 / (1 - h . u). Its positions moved to one depth,
/// c + u z with z = Z / Z_anchor, are then an affine image of the plane: parabolas that share
/// one acceleration. The apparent size moves with them (size z: the size at the anchor's depth).
/// False where some sample's 1 - h . u is below a half of the anchor's (a depth beyond twice
/// the anchor's: no plane seen from in front of it).
bool Rectify(const State& in, const Eigen::Vector2d& c, const Eigen::Vector2d& h,
             const Eigen::Vector2d& anchor, State& out) {
  out = in;
  const double w_anchor = 1 - h.dot(anchor - c);
  if (!(w_anchor > 0)) return false;
  for (auto& s : out.s) {
    const double w = 1 - h.dot(s.p - c);
    if (!(w > 0.5 * w_anchor)) return false;
    const double z = w_anchor / w;
    s.p = c + (s.p - c) * z;
    s.cov *= z * z;
    s.W /= z;
    s.size *= z;
  }
  return true;
}

/// The used samples' whitened residuals of the joint fit of `st` rectified by h, in sample
/// order; empty where the rectification or the fit fails.
Eigen::VectorXd RectifiedResiduals(const State& st, const Eigen::Vector2d& c,
                                   const Eigen::Vector2d& h, const Eigen::Vector2d& anchor,
                                   int min_arc, Fit* fit = nullptr) {
  State r;
  if (!Rectify(st, c, h, anchor, r)) return {};
  Fit f = JointFit(r, min_arc);
  if (!f.ok) return {};
  Eigen::VectorXd out(f.rows);
  int i = 0;
  for (std::size_t j = 0; j < st.s.size(); ++j)
    if (st.Used(j) && f.slot[static_cast<std::size_t>(st.arc[j])] >= 0) {
      out.segment<2>(i) = f.res[j];
      i += 2;
    }
  if (fit) *fit = std::move(f);
  return out;
}

/// h of the plane's perspective fitted to the settled roles of `st` (its samples as given), by
/// Levenberg-Marquardt on the joint fit's whitened residuals, with its covariance and the drop
/// of the residuals' chi^2 it makes (in units of the fitted noise). h is fitted along "up"
/// (the fitted acceleration's opposite) alone: a camera tilted toward the floor sees the depth
/// change with the height, and the component across it is not told from the arcs' own
/// parameters where the body moves mostly up and down (a fit of both put it at 25 times the
/// camera's on rendered drops).
struct Perspective {
  bool fitted = false;
  Eigen::Vector2d h{0, 0}, anchor{0, 0};
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  double chi2_drop = 0.0;
  double depth_range = 0.0;  ///< the largest minus the smallest relative depth z of the samples
};
Perspective FitPerspective(const State& st, const Fit& f0, const Eigen::Vector2d& c, int min_arc) {
  Perspective P;
  if (!f0.ok || f0.rows - f0.params < 3) return P;
  // The anchor: the lowest sample (along the fitted acceleration), where the contacts are.
  const Eigen::Vector2d down = f0.x.tail<2>().normalized(), up = -down;
  double lowest = -std::numeric_limits<double>::infinity(), reach = 0;
  for (std::size_t j = 0; j < st.s.size(); ++j) {
    if (!st.Used(j)) continue;
    reach = std::max(reach, std::abs((st.s[j].p - c).dot(up)));
    if (st.s[j].p.dot(down) > lowest) {
      lowest = st.s[j].p.dot(down);
      P.anchor = st.s[j].p;
    }
  }
  if (!(reach > 0)) return P;
  const auto residuals = [&](double eta) {
    return RectifiedResiduals(st, c, eta * up, P.anchor, min_arc);
  };
  double eta = 0;
  Eigen::VectorXd r = residuals(eta);
  if (r.size() == 0) return P;
  const double ssr0 = r.squaredNorm();
  double ssr = ssr0, lambda = 1e-3, jtj = 0;
  const double step = 1e-4 / reach;
  for (int iter = 0; iter < 30; ++iter) {
    const Eigen::VectorXd rp = residuals(eta + step), rm = residuals(eta - step);
    if (rp.size() != r.size() || rm.size() != r.size()) return P;
    const Eigen::VectorXd J = (rp - rm) / (2 * step);
    jtj = J.squaredNorm();
    const double g = J.dot(r);
    if (!(jtj > 0)) return P;
    bool improved = false, small = false;
    for (int tries = 0; tries < 12 && !improved; ++tries) {
      const double d = -g / (jtj * (1 + lambda));
      const Eigen::VectorXd rn = residuals(eta + d);
      if (rn.size() == r.size() && rn.squaredNorm() < ssr) {
        small = ssr - rn.squaredNorm() < 1e-10 * ssr;
        eta += d;
        r = rn;
        ssr = rn.squaredNorm();
        lambda = std::max(lambda / 10, 1e-9);
        improved = true;
      } else {
        lambda *= 10;
      }
    }
    if (!improved || small) break;
  }
  const int dof = f0.rows - f0.params - 1;
  const double s2 = ssr / dof;
  if (!(s2 > 0) || !(jtj > 0)) return P;
  P.h = eta * up;
  P.cov = (s2 / jtj) * up * up.transpose();
  P.chi2_drop = (ssr0 - ssr) / s2;
  double zmin = std::numeric_limits<double>::infinity(), zmax = -zmin;
  const double w_anchor = 1 - P.h.dot(P.anchor - c);
  for (std::size_t j = 0; j < st.s.size(); ++j) {
    if (!st.Used(j)) continue;
    const double z = w_anchor / (1 - P.h.dot(st.s[j].p - c));
    zmin = std::min(zmin, z);
    zmax = std::max(zmax, z);
  }
  P.depth_range = zmax - zmin;
  P.fitted = true;
  return P;
}

/// The samples of `poses` (C of each valid pose), whitened by their covariances when every one
/// has a positive-definite covariance.
State Prepare(const std::vector<PoseSample>& poses, double d_EC_m, bool& weighted) {
  State st;
  weighted = true;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const PoseSample& p = poses[i];
    if (!p.valid) continue;
    Sample s;
    s.frame = static_cast<int>(i);
    s.t = p.t_s;
    s.p = p.p_WE + d_EC_m * core::BodyRotation(p.theta_W_rad).x_B();
    s.theta = p.theta_W_rad;
    s.size = p.apparent_size;
    s.cov = p.cov_p_WE;
    const Eigen::LLT<Eigen::Matrix2d> llt(p.cov_p_WE);
    if (!(llt.info() == Eigen::Success && p.cov_p_WE.allFinite() && p.cov_p_WE.determinant() > 0))
      weighted = false;
    st.s.push_back(s);
  }
  for (auto& s : st.s) {
    if (weighted) {
      const Eigen::Matrix2d L = Eigen::LLT<Eigen::Matrix2d>(s.cov).matrixL();
      s.W = L.inverse();
    } else {
      s.cov = Eigen::Matrix2d::Identity();
      s.W = Eigen::Matrix2d::Identity();
    }
  }
  // Time order (frames are in order; a caller's times could repeat a frame's slot).
  std::stable_sort(st.s.begin(), st.s.end(),
                   [](const Sample& a, const Sample& b) { return a.t < b.t; });
  st.role.assign(st.s.size(), ArcFrameRole::kArc);
  st.arc.assign(st.s.size(), 0);
  st.chi2.assign(st.s.size(), core::kNaN);
  return st;
}

/// The result from the settled state and its fit.
void Report(const State& st, const Fit& f, const std::vector<PoseSample>& poses, FlightArcs& out) {
  out.frames.assign(poses.size(), ArcFrame{});
  for (std::size_t i = 0; i < poses.size(); ++i)
    out.frames[i].role = poses[i].repeated ? ArcFrameRole::kRepeated : ArcFrameRole::kNoSample;
  out.arcs.assign(static_cast<std::size_t>(st.Arcs()), FlightArc{});
  for (std::size_t j = 0; j < st.s.size(); ++j) {
    ArcFrame& fr = out.frames[static_cast<std::size_t>(st.s[j].frame)];
    fr.role = st.role[j];
    fr.arc = st.arc[j];
    fr.residual_chi2 = st.chi2[j];
    FlightArc& arc = out.arcs[static_cast<std::size_t>(st.arc[j])];
    if (st.role[j] != ArcFrameRole::kArc && st.role[j] != ArcFrameRole::kShortArc) continue;
    if (arc.first_frame < 0) arc.first_frame = st.s[j].frame;
    arc.last_frame = st.s[j].frame;
    ++arc.n;
  }
  for (std::size_t b = 0; b < st.breaks.size(); ++b) {
    ArcContact c;
    c.before = static_cast<int>(b);
    c.last_frame_before = st.s[static_cast<std::size_t>(st.breaks[b])].frame;
    c.first_frame_after = st.s[static_cast<std::size_t>(st.breaks[b]) + 1].frame;
    c.impulse_sigmas = st.impulse[b];
    out.contacts.push_back(c);
  }
  out.slot = f.slot;
  for (int k = 0; k < st.Arcs(); ++k) {
    FlightArc& arc = out.arcs[static_cast<std::size_t>(k)];
    arc.t_ref_s = f.t_ref[static_cast<std::size_t>(k)];
    arc.fitted = f.slot[static_cast<std::size_t>(k)] >= 0;
  }
}

/// The fitted parameters, their covariance and what follows from them.
void Parameters(const State& st, const Fit& f, FlightArcs& out) {
  const double s2 = f.ssr / (f.rows - f.params);
  out.x = f.x;
  out.cov_x = s2 * f.Covariance();
  out.dof = f.rows - f.params;
  out.samples_used = f.rows / 2;
  out.sigma = std::sqrt(s2);
  out.a_W = f.x.tail<2>();
  out.cov_a_W = out.cov_x.bottomRightCorner<2, 2>();
  out.a_norm = out.a_W.norm();
  const Eigen::Vector2d ua = out.a_W / out.a_norm, perp(-ua.y(), ua.x());
  out.a_norm_se = std::sqrt(ua.dot(out.cov_a_W * ua));
  const Eigen::Vector2d up = -ua;
  out.roll_deg = core::RadToDeg(std::atan2(up.x(), up.y()));
  out.roll_se_deg = core::RadToDeg(std::sqrt(perp.dot(out.cov_a_W * perp)) / out.a_norm);
  for (int k = 0; k < st.Arcs(); ++k) {
    FlightArc& arc = out.arcs[static_cast<std::size_t>(k)];
    const int sl = f.slot[static_cast<std::size_t>(k)];
    if (sl < 0) continue;
    arc.p_W = f.x.segment<2>(4 * sl);
    arc.v_W = f.x.segment<2>(4 * sl + 2);
    double ss = 0;
    for (std::size_t j : SamplesOf(st, k))
      if (st.Used(j)) ss += (st.s[j].p - ArcPosition(out, f.x, k, st.s[j].t)).squaredNorm();
    arc.rms_residual = std::sqrt(ss / arc.n);
  }
}

/// The segmentation is found on up to four versions of the samples: corrected to the
/// reference depth (a body moving in depth, where its sizes say so) or as given, each weighted
/// by the covariances or with equal weights. A tracker's covariances leave out the errors that
/// change slowly along a flight (a blurred ball's centre moves toward the light, by 0.2 px at
/// rest to 2 px at 1200 px/s): where they are small, such a drift can stop an arc at its
/// apex, and where the blur shrinks a ball's apparent size it reads as motion in depth. The
/// version whose arcs take the most samples is kept (the first of those equal, in the order
/// above). Returns the fit on the positions as given, with their weights, and in `chosen` the
/// roles and contacts found on those positions.
Fit SegmentBest(const State& st, const ArcOptions& o, bool weighted, State& chosen) {
  std::vector<State> versions;
  {
    State depth = st;
    if (o.principal_point_W && PreCorrectDepth(depth, *o.principal_point_W))
      versions.push_back(std::move(depth));
  }
  versions.push_back(st);
  if (weighted) {
    const std::size_t given = versions.size();
    for (std::size_t v = 0; v < given; ++v) {
      State equal = versions[v];
      for (auto& s : equal.s) {
        s.cov = Eigen::Matrix2d::Identity();
        s.W = Eigen::Matrix2d::Identity();
      }
      versions.push_back(std::move(equal));
    }
  }
  Fit f;
  chosen = st;
  int most_rows = -1;
  for (std::size_t v = 0; v < versions.size(); ++v) {
    State& seg = versions[v];
    const Fit sf = Segment(seg, o);
    if (v == 0) {  // where none is fitted, the first says why (its roles and contacts)
      chosen = seg;
      for (std::size_t j = 0; j < st.s.size(); ++j) chosen.s[j] = st.s[j];
    }
    if (!sf.ok || sf.rows <= most_rows) continue;
    // The roles and contacts found, on the samples as given.
    State fitted = std::move(seg);
    for (std::size_t j = 0; j < st.s.size(); ++j) fitted.s[j] = st.s[j];
    const Fit ff = JointFit(fitted, o.min_arc_frames);
    if (!ff.ok) continue;
    most_rows = sf.rows;
    f = ff;
    chosen = std::move(fitted);
  }
  return f;
}

/// The plane's perspective, fitted to the segmentation `chosen` (FitPerspective) and applied
/// where it lowers the residuals' chi^2 by more than ArcOptions::perspective_chi2: the
/// segmentation is then found again on the rectified samples (a slanted view bends the arcs
/// apart, so the first may stop short) and h fitted again on it, while the arcs take more
/// samples; `chosen` becomes the rectified state. Returns the fit to report.
Fit PerspectiveCorrection(const State& st, const ArcOptions& o, State& chosen, const Fit& f,
                          FlightArcs& out) {
  const Eigen::Vector2d c = *o.principal_point_W;
  Perspective P = FitPerspective(chosen, f, c, o.min_arc_frames);
  if (!P.fitted || !(P.chi2_drop > o.perspective_chi2)) return f;
  int rows = f.rows;
  for (int round = 0; round < 8; ++round) {
    State rect;
    if (!Rectify(st, c, P.h, P.anchor, rect)) break;
    State again;
    const Fit fa = SegmentBest(rect, o, out.weighted, again);
    if (!fa.ok) break;
    again.s = st.s;
    const Fit fg = JointFit(again, o.min_arc_frames);
    if (!fg.ok) break;
    const Perspective Q = FitPerspective(again, fg, c, o.min_arc_frames);
    if (!Q.fitted || !(Q.chi2_drop > o.perspective_chi2) || fg.rows < rows) break;
    const bool grew = fg.rows > rows;
    P = Q;
    chosen = std::move(again);
    rows = fg.rows;
    if (!grew) break;
  }
  State applied;
  if (!Rectify(chosen, c, P.h, P.anchor, applied)) return f;
  const Fit g = JointFit(applied, o.min_arc_frames);
  const Fit plain = JointFit(chosen, o.min_arc_frames);
  if (!g.ok || !plain.ok) return f;
  out.perspective_applied = true;
  out.perspective_h = P.h;
  out.perspective_cov_h = P.cov;
  out.perspective_chi2_drop = P.chi2_drop;
  out.perspective_depth_range = P.depth_range;
  out.x_unrectified = plain.x;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(P.cov);
  for (int k = 0; k < 2; ++k) {
    if (!(eig.eigenvalues()(k) > 0)) continue;
    const Eigen::Vector2d dh = std::sqrt(eig.eigenvalues()(k)) * eig.eigenvectors().col(k);
    State moved;
    const Fit h =
        Rectify(chosen, c, P.h + dh, P.anchor, moved) ? JointFit(moved, o.min_arc_frames) : Fit{};
    out.x_perspective_perturbed.push_back(h.ok ? h.x : g.x);
  }
  chosen = std::move(applied);
  return g;
}

}  // namespace

void ArcOptions::Validate() const {
  if (min_arc_frames < 3) throw std::invalid_argument("arcs min_arc_frames must be >= 3");
  if (!(impulse_sigmas > 0)) throw std::invalid_argument("arcs impulse_sigmas must be > 0");
  if (!(reversal_sigmas > 0)) throw std::invalid_argument("arcs reversal_sigmas must be > 0");
  if (!(outlier_chi2 > 0)) throw std::invalid_argument("arcs outlier_chi2 must be > 0");
  if (!(contact_chi2 > 0)) throw std::invalid_argument("arcs contact_chi2 must be > 0");
  if (max_outlier_run < 2) throw std::invalid_argument("arcs max_outlier_run must be >= 2");
  if (!(max_excluded_fraction > 0 && max_excluded_fraction < 1))
    throw std::invalid_argument("arcs max_excluded_fraction must be in (0, 1)");
  if (!(max_roll_se_deg > 0)) throw std::invalid_argument("arcs max_roll_se_deg must be > 0");
  if (!(min_sideways_ratio >= 0))
    throw std::invalid_argument("arcs min_sideways_ratio must be >= 0");
  if (!(perspective_chi2 > 0)) throw std::invalid_argument("arcs perspective_chi2 must be > 0");
  if (principal_point_W && !principal_point_W->allFinite())
    throw std::invalid_argument("arcs principal_point_W must be finite");
}

const char* ArcFrameRoleName(ArcFrameRole role) {
  switch (role) {
    case ArcFrameRole::kArc:
      return "arc";
    case ArcFrameRole::kNoSample:
      return "no_sample";
    case ArcFrameRole::kRepeated:
      return "repeated";
    case ArcFrameRole::kContact:
      return "contact";
    case ArcFrameRole::kOutlier:
      return "outlier";
    case ArcFrameRole::kNotInFlight:
      return "not_in_flight";
    case ArcFrameRole::kShortArc:
      return "short_arc";
  }
  return "?";
}

Eigen::Vector2d ArcPosition(const FlightArcs& arcs, const Eigen::VectorXd& x, int k, double t_s) {
  const int sl = arcs.slot[static_cast<std::size_t>(k)];
  const double tau = t_s - arcs.arcs[static_cast<std::size_t>(k)].t_ref_s;
  return x.segment<2>(4 * sl) + x.segment<2>(4 * sl + 2) * tau + 0.5 * x.tail<2>() * tau * tau;
}

Eigen::Vector2d ArcVelocity(const FlightArcs& arcs, const Eigen::VectorXd& x, int k, double t_s) {
  const int sl = arcs.slot[static_cast<std::size_t>(k)];
  const double tau = t_s - arcs.arcs[static_cast<std::size_t>(k)].t_ref_s;
  return x.segment<2>(4 * sl + 2) + x.tail<2>() * tau;
}

FlightArcs FitFlightArcs(const std::vector<PoseSample>& poses, double d_EC_m,
                         double surface_angle_deg, const ArcOptions& options) {
  options.Validate();
  FlightArcs out;
  State st = Prepare(poses, d_EC_m, out.weighted);
  st.phi_rad = core::DegToRad(surface_angle_deg);
  const auto too_few = [&](const std::string& why) {
    out.status = ArcFitStatus::kTooFewFrames;
    out.message = why;
    Fit none;
    none.slot.assign(static_cast<std::size_t>(st.Arcs()), -1);
    none.t_ref.assign(static_cast<std::size_t>(st.Arcs()), 0.0);
    Report(st, none, poses, out);
    return out;
  };
  if (static_cast<int>(st.s.size()) < options.min_arc_frames + 1)
    return too_few("the joint arc fit needs " + std::to_string(options.min_arc_frames + 1) +
                   " or more frames with a position (found " + std::to_string(st.s.size()) + ")");
  State chosen;
  Fit f = SegmentBest(st, options, out.weighted, chosen);
  if (f.ok && options.correct_perspective && options.principal_point_W)
    f = PerspectiveCorrection(st, options, chosen, f, out);
  st = std::move(chosen);
  if (!f.ok) {
    std::ostringstream os;
    os << "the joint arc fit found no flight arc of " << options.min_arc_frames
       << " or more frames with a position that it could fit and check (" << st.s.size()
       << " frames with a position, " << st.breaks.size() << " contacts)";
    return too_few(os.str());
  }
  Report(st, f, poses, out);
  DepthCorrection(st, options, f, out);
  Parameters(st, f, out);
  FitAngles(st, f, out.arcs);
  out.status = ArcFitStatus::kFitted;
  return out;
}

}  // namespace hoof::kinematics
