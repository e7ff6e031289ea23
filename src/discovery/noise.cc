// The noise model of the discovery workflow (docs/discovery.md, "Noise model"): each trial's
// contact coefficients scatter about the surface's (zeta and mu, per surface), and each
// measured velocity carries its own random error (the per-trial fits' s.e.) plus a systematic
// error per component. To first order in the scatter, a trial's residual vector r has the
// covariance
//
//   V = sd_zeta^2 J_zeta J_zeta^T + sd_mu^2 J_mu J_mu^T + diag(se^2 + sd_sys^2),
//
// with J the derivatives of the prediction by zeta and mu at the fitted model. Nothing here
// needs repeated trials of one condition.
#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>
#include <boost/math/tools/minima.hpp>

#include "discovery/internal.h"

namespace hoof::discovery::internal {

TrialCovariance Covariance(const Workspace& ws, const Obs& o, const Sensitivity& s,
                           const Noise& noise) {
  TrialCovariance t;
  for (int c = 0; c < kComponents; ++c)
    if (o.used[static_cast<std::size_t>(c)]) t.components.push_back(c);
  const auto n = static_cast<Eigen::Index>(t.components.size());
  const auto surface = static_cast<std::size_t>(o.surface);
  const double vz = noise.zeta_sd[surface] * noise.zeta_sd[surface];
  const double vm = ws.has_oblique[surface] ? noise.mu_sd[surface] * noise.mu_sd[surface] : 0.0;
  t.cov.resize(n, n);
  for (Eigen::Index a = 0; a < n; ++a)
    for (Eigen::Index b = 0; b < n; ++b) {
      const int ca = t.components[static_cast<std::size_t>(a)],
                cb = t.components[static_cast<std::size_t>(b)];
      t.cov(a, b) = vz * s(ca, 0) * s(cb, 0) + vm * s(ca, 1) * s(cb, 1);
      if (a == b)
        t.cov(a, b) += o.measurement_var[ca] +
                       noise.systematic_sd[surface][ca] * noise.systematic_sd[surface][ca] + 1e-16;
    }
  const Eigen::LLT<SmallMatrix> llt(t.cov);
  const SmallMatrix L = llt.matrixL();
  t.whiten = L.triangularView<Eigen::Lower>().solve(SmallMatrix::Identity(n, n));
  t.log_det = 0.0;
  for (Eigen::Index a = 0; a < n; ++a) t.log_det += 2 * std::log(L(a, a));
  return t;
}

std::vector<TrialCovariance> Covariances(const Workspace& ws, const std::vector<Sensitivity>& sens,
                                         const Noise& noise) {
  std::vector<TrialCovariance> c;
  c.reserve(ws.obs.size());
  for (std::size_t i = 0; i < ws.obs.size(); ++i)
    c.push_back(Covariance(ws, ws.obs[i], sens[i], noise));
  return c;
}

namespace {

double TrialLogLikelihood(const Workspace& ws, const Obs& o, const Eigen::Vector3d& r,
                          const Sensitivity& s, const Noise& noise) {
  const TrialCovariance t = Covariance(ws, o, s, noise);
  SmallVector v(static_cast<Eigen::Index>(t.components.size()));
  for (std::size_t a = 0; a < t.components.size(); ++a)
    v[static_cast<Eigen::Index>(a)] = r[t.components[a]];
  return -0.5 * (t.log_det + (t.whiten * v).squaredNorm());
}

}  // namespace

double LogLikelihood(const Workspace& ws, const std::vector<int>& which,
                     const std::vector<Eigen::Vector3d>& r, const std::vector<Sensitivity>& s,
                     const Noise& noise) {
  double ll = 0.0;
  for (std::size_t i = 0; i < which.size(); ++i)
    ll += TrialLogLikelihood(ws, ws.obs[static_cast<std::size_t>(which[i])], r[i], s[i], noise);
  return ll;
}

Noise InitialNoise(const Workspace& ws) {
  Noise n;
  n.zeta_sd.assign(ws.surfaces.size(), 0.02);
  n.mu_sd.assign(ws.surfaces.size(), 0.02);
  n.systematic_sd.assign(ws.surfaces.size(),
                         Eigen::Vector3d::Constant(std::max(ws.measurement_floor, 1e-3)));
  return n;
}

namespace {

/// EstimateNoise from one start.
Noise EstimateNoiseFrom(const Workspace& ws, const std::vector<int>& which,
                        const std::vector<Eigen::Vector3d>& r, const std::vector<Sensitivity>& s,
                        const Noise& start) {
  Noise n = start;
  const std::size_t S = ws.surfaces.size();
  // The trials of each surface (a surface's scatter only moves its own trials' likelihood).
  std::vector<std::vector<std::size_t>> of_surface(S);
  std::vector<std::array<bool, kComponents>> component_used(S, {false, false, false});
  std::vector<bool> surface_oblique(S, false);
  for (std::size_t i = 0; i < which.size(); ++i) {
    const Obs& o = ws.obs[static_cast<std::size_t>(which[i])];
    const auto surface = static_cast<std::size_t>(o.surface);
    of_surface[surface].push_back(i);
    for (int c = 0; c < kComponents; ++c)
      component_used[surface][static_cast<std::size_t>(c)] |= o.used[static_cast<std::size_t>(c)];
    if (!o.normal) surface_oblique[surface] = true;
  }
  if (n.systematic_sd.size() != S)
    n.systematic_sd.assign(S, Eigen::Vector3d::Constant(std::max(ws.measurement_floor, 1e-3)));
  auto ll_of = [&](const std::vector<std::size_t>& idx) {
    double ll = 0.0;
    for (std::size_t i : idx)
      ll += TrialLogLikelihood(ws, ws.obs[static_cast<std::size_t>(which[i])], r[i], s[i], n);
    return ll;
  };
  std::vector<std::size_t> all(which.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
  // One coordinate: Brent's search on log(sd) in [lo, hi], the others held.
  auto search = [&](double& sd, double lo, double hi, const std::vector<std::size_t>& idx) {
    if (idx.empty()) return;
    const auto f = [&](double log_sd) {
      sd = std::exp(log_sd);
      return -ll_of(idx);
    };
    boost::uintmax_t iterations = 60;
    const auto best =
        boost::math::tools::brent_find_minima(f, std::log(lo), std::log(hi), 24, iterations);
    sd = std::exp(best.first);
  };
  const double floor = std::max(ws.measurement_floor, 1e-7);
  // v_y's systematic error is one for all surfaces: on a surface's own trials it is confounded
  // with the scatter of zeta (both spread v_y alone in a normal impact), and a search per surface
  // wandered along that ridge (0.066 of the impact speed on one surface of a null study).
  double shared_v_y = n.systematic_sd.empty() ? floor : n.systematic_sd.front()[1];
  const auto set_v_y = [&] {
    for (auto& sd : n.systematic_sd) sd[1] = shared_v_y;
  };
  set_v_y();
  for (int sweep = 0; sweep < 3; ++sweep) {
    for (std::size_t surface = 0; surface < S; ++surface) {
      search(n.zeta_sd[surface], 1e-6, 2.0, of_surface[surface]);
      if (surface_oblique[surface]) search(n.mu_sd[surface], 1e-6, 1.0, of_surface[surface]);
      for (int c : {0, 2})
        if (component_used[surface][static_cast<std::size_t>(c)])
          search(n.systematic_sd[surface][c], floor, 0.1, of_surface[surface]);
    }
    {
      const auto f = [&](double log_sd) {
        shared_v_y = std::exp(log_sd);
        set_v_y();
        return -ll_of(all);
      };
      boost::uintmax_t iterations = 60;
      shared_v_y = std::exp(
          boost::math::tools::brent_find_minima(f, std::log(floor), std::log(0.1), 24, iterations)
              .first);
      set_v_y();
    }
  }
  return n;
}

}  // namespace

Noise EstimateNoise(const Workspace& ws, const std::vector<int>& which,
                    const std::vector<Eigen::Vector3d>& r, const std::vector<Sensitivity>& s,
                    const Noise& start) {
  // From the start given (the last estimate, in a fit's alternation) and from the initial noise
  // model, the better of the two: a misfit of the moment (a candidate far from its optimum) can
  // raise an s.d. to where the search from it stays, and a fit alternating with it stays too.
  // The two searches are independent, and each is the same on any thread.
  Noise a, b;
  ws.ParallelFor(2, [&](std::size_t k) {
    if (k == 0)
      a = EstimateNoiseFrom(ws, which, r, s, start);
    else
      b = EstimateNoiseFrom(ws, which, r, s, InitialNoise(ws));
  });
  return LogLikelihood(ws, which, r, s, b) > LogLikelihood(ws, which, r, s, a) ? b : a;
}

}  // namespace hoof::discovery::internal
