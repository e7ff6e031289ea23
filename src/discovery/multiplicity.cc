// The naming level of the discovery workflow (docs/discovery.md, "Candidates and the decision"):
// the level at which the smallest likelihood-ratio p of all the hypotheses a round tries stays
// below it with probability alpha when the current model is right. Bonferroni's alpha / hypotheses
// treats the hypotheses as unrelated, but the candidates' changes overlap (Hunt-Crossley, Hertzian
// stiffness and plastic unloading all bend e with speed), and the shared and per-surface forms of
// one candidate are nearly the same test; the min-P level (Westfall and Young) counts them as the
// fewer tests they are.
//
// Under the linearised noise model the whitened residuals are standard normal, so the scores of
// the candidates' changes, after zeta and mu per surface are projected out, are jointly normal
// with the Gram matrix of the projected changes as covariance. The null distribution of the
// smallest p is drawn from that by Monte Carlo (seeded: the same study gives the same level).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/QR>
#include <boost/random/mersenne_twister.hpp>
#include <boost/random/normal_distribution.hpp>
#include <boost/random/uniform_01.hpp>

#include "discovery/internal.h"

namespace hoof::discovery::internal {
namespace {

/// The largest likelihood ratio of a fit with nonnegative coefficients to a normal score `g` of
/// covariance `G` (the columns `cols`): by enumerating the faces of the orthant, each face's
/// unconstrained solution counts when it lies in the orthant.
struct OrthantLr {
  struct Face {
    std::vector<Eigen::Index> cols;
    Eigen::MatrixXd inverse;
  };
  std::vector<Face> faces;

  OrthantLr(const Eigen::MatrixXd& G, const std::vector<Eigen::Index>& cols) {
    const std::size_t n = cols.size();
    for (std::uint32_t mask = 1; mask < (1u << n); ++mask) {
      Face f;
      for (std::size_t j = 0; j < n; ++j)
        if (mask & (1u << j)) f.cols.push_back(cols[j]);
      const auto m = static_cast<Eigen::Index>(f.cols.size());
      Eigen::MatrixXd sub(m, m);
      for (Eigen::Index a = 0; a < m; ++a)
        for (Eigen::Index b = 0; b < m; ++b) sub(a, b) = G(f.cols[a], f.cols[b]);
      const Eigen::FullPivLU<Eigen::MatrixXd> lu(sub);
      if (!lu.isInvertible()) continue;
      f.inverse = lu.inverse();
      faces.push_back(std::move(f));
    }
  }

  double operator()(const Eigen::VectorXd& g) const {
    double best = 0.0;
    for (const Face& f : faces) {
      const auto m = static_cast<Eigen::Index>(f.cols.size());
      Eigen::VectorXd gf(m);
      for (Eigen::Index a = 0; a < m; ++a) gf[a] = g[f.cols[a]];
      const Eigen::VectorXd beta = f.inverse * gf;
      if ((beta.array() >= 0).all()) best = std::max(best, gf.dot(beta));
    }
    return best;
  }
};

/// The candidates' changes as unit columns of the whitened design, zeta and mu projected out:
/// each candidate's change restricted to each surface's trials (column k S + s), then each
/// candidate's further rays, whole. Each column to unit length: the tests do not depend on the
/// effect's unit, and the units' scales (Hunt-Crossley per N s/m^2, Hertz per unit exponent)
/// differ by ten orders of magnitude, which no eigen-decomposition of the raw Gram matrix would
/// survive. A column that zeta and mu take up entirely carries no test (not informative, zero).
struct UnitColumns {
  Eigen::MatrixXd D;
  Eigen::VectorXd length;  ///< each column's length before it was scaled to 1
  std::vector<bool> informative;
  std::vector<std::vector<Eigen::Index>> ray_cols;  ///< per candidate, its rays' columns
  std::vector<const LadderRay*> ray_of;             ///< per ray column, from changes.size() S on
};

UnitColumns UnitColumnsOf(const Workspace& ws,
                          const std::vector<std::vector<Eigen::Vector3d>>& changes,
                          const std::vector<Sensitivity>& sens,
                          const std::vector<TrialCovariance>& ref,
                          const std::vector<std::vector<LadderRay>>& rays) {
  const std::size_t S = ws.surfaces.size();
  UnitColumns u;
  const WhitenedDesign w = Whiten(ws, sens, ref);
  const Eigen::Index rows = w.X.rows();
  std::size_t n_rays = 0;
  for (const auto& r : rays) n_rays += r.size();
  u.D = Eigen::MatrixXd::Zero(rows, static_cast<Eigen::Index>(changes.size() * S + n_rays));
  for (std::size_t k = 0; k < changes.size(); ++k) {
    const Eigen::VectorXd d = WhitenChange(ws, changes[k], ref, w);
    for (std::size_t i = 0; i < ws.obs.size(); ++i) {
      const Eigen::Index col = static_cast<Eigen::Index>(k * S) + ws.obs[i].surface;
      u.D.col(col).segment(w.first[i], w.first[i + 1] - w.first[i]) =
          d.segment(w.first[i], w.first[i + 1] - w.first[i]);
    }
  }
  u.ray_cols.resize(changes.size());
  auto col = static_cast<Eigen::Index>(changes.size() * S);
  for (std::size_t k = 0; k < rays.size() && k < changes.size(); ++k)
    for (const auto& ray : rays[k]) {
      u.D.col(col) = WhitenChange(ws, ray.change, ref, w);
      u.ray_cols[k].push_back(col++);
      u.ray_of.push_back(&ray);
    }
  const Eigen::VectorXd before = u.D.colwise().norm();
  u.D = ProfileOut(w)(u.D);
  u.informative.assign(static_cast<std::size_t>(u.D.cols()), false);
  u.length = u.D.colwise().norm();
  for (Eigen::Index c = 0; c < u.D.cols(); ++c) {
    if (before[c] > 0 && u.length[c] > 1e-6 * before[c]) {
      u.D.col(c) /= u.length[c];
      u.informative[static_cast<std::size_t>(c)] = true;
    } else {
      u.D.col(c).setZero();
    }
  }
  return u;
}

/// One hypothesis of the round: a candidate's shared form, or its per-surface form.
struct Hypothesis {
  std::vector<Eigen::Index> cols;
  std::vector<double> weight;  // shared form: the score is sum weight[j] g[cols[j]]
  double shared_var = 0.0;     // > 0 for the shared form
  // Shared form: the unit columns of its changes at other sizes, and the stretch of each that
  // the sizes reach, in units of the score.
  std::vector<Eigen::Index> rays;
  std::vector<double> ray_low, ray_high;
  int df = 1;
  std::unique_ptr<OrthantLr> orthant;

  /// The likelihood-ratio statistic of scores `g` (standard normal under the current model,
  /// with Gram matrix G).
  double Lr(const Eigen::VectorXd& g) const {
    if (orthant) return (*orthant)(g);
    double u = 0.0;
    for (std::size_t j = 0; j < cols.size(); ++j) u += weight[j] * g[cols[j]];
    double lr = u > 0 ? u * u / shared_var : 0.0;
    // Along a ray the change at scale t gains 2 t g - t^2, largest at t = g within the
    // stretch, else at its nearer end.
    for (std::size_t j = 0; j < rays.size(); ++j) {
      const double t = std::clamp(g[rays[j]], ray_low[j], ray_high[j]);
      lr = std::max(lr, 2 * t * g[rays[j]] - t * t);
    }
    return lr;
  }
};

/// The hypotheses: per candidate with any information, its shared form and (`forms`: with two
/// or more surfaces) its per-surface form over the surfaces it changes.
std::vector<Hypothesis> HypothesesOf(const UnitColumns& u, const Eigen::MatrixXd& G,
                                     std::size_t candidates, std::size_t S, bool forms) {
  std::vector<Hypothesis> hyps;
  for (std::size_t k = 0; k < candidates; ++k) {
    std::vector<Eigen::Index> cols;
    for (std::size_t s = 0; s < S; ++s)
      if (u.informative[k * S + s]) cols.push_back(static_cast<Eigen::Index>(k * S + s));
    if (cols.empty()) continue;
    // The shared form's score is the sum of the surfaces' raw scores: with unit columns, each
    // weighted by its length.
    Hypothesis shared;
    shared.cols = cols;
    for (auto a : cols) shared.weight.push_back(u.length[a]);
    for (std::size_t a = 0; a < cols.size(); ++a)
      for (std::size_t b = 0; b < cols.size(); ++b)
        shared.shared_var += shared.weight[a] * shared.weight[b] * G(cols[a], cols[b]);
    for (auto c : u.ray_cols[k])
      if (u.informative[static_cast<std::size_t>(c)]) {
        const LadderRay& ray = *u.ray_of[static_cast<std::size_t>(c) - candidates * S];
        shared.rays.push_back(c);
        shared.ray_low.push_back(ray.low * u.length[c]);
        shared.ray_high.push_back(ray.high * u.length[c]);
      }
    if (shared.shared_var > 0) hyps.push_back(std::move(shared));
    if (forms && cols.size() <= 8) {
      Hypothesis ps;
      ps.cols = cols;
      ps.df = static_cast<int>(S);
      ps.orthant = std::make_unique<OrthantLr>(G, cols);
      hyps.push_back(std::move(ps));
    }
  }
  return hyps;
}

/// The alpha quantile of the smallest p over `hyps` and `independent` uniform p-values, from
/// `draws` scores g = L xi with L L^T = G (eigen-decomposition: G may be singular), seeded.
double MinPQuantile(const Eigen::MatrixXd& G, const std::vector<Hypothesis>& hyps, int independent,
                    double alpha, int draws) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(G);
  const Eigen::MatrixXd L =
      eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
  boost::random::mt19937 rng(20261122u);
  boost::random::normal_distribution<double> normal;
  boost::random::uniform_01<double> uniform;
  std::vector<double> min_p(static_cast<std::size_t>(draws));
  Eigen::VectorXd xi(G.rows());
  for (auto& mp : min_p) {
    for (Eigen::Index a = 0; a < xi.size(); ++a) xi[a] = normal(rng);
    const Eigen::VectorXd g = L * xi;
    double p = 1.0;
    for (const Hypothesis& h : hyps) {
      const double lr = h.Lr(g);
      if (lr > 0) p = std::min(p, ChiBarSquareUpperTail(lr, h.df));
    }
    for (int j = 0; j < independent; ++j) p = std::min(p, uniform(rng));
    mp = p;
  }
  const auto q = static_cast<std::size_t>(std::floor(alpha * draws));
  std::nth_element(min_p.begin(), min_p.begin() + static_cast<std::ptrdiff_t>(q), min_p.end());
  return min_p[q];
}

}  // namespace

NamingLevel CalibrateNamingLevel(const Workspace& ws,
                                 const std::vector<std::vector<Eigen::Vector3d>>& changes,
                                 const std::vector<Sensitivity>& sens,
                                 const std::vector<TrialCovariance>& ref, bool per_surface,
                                 int independent, double alpha, int draws,
                                 const std::vector<std::vector<LadderRay>>& rays) {
  const std::size_t S = ws.surfaces.size();
  NamingLevel out;
  const UnitColumns u = UnitColumnsOf(ws, changes, sens, ref, rays);
  const Eigen::MatrixXd G = u.D.transpose() * u.D;
  const std::vector<Hypothesis> hyps = HypothesesOf(u, G, changes.size(), S, per_surface && S > 1);
  out.hypotheses = static_cast<int>(hyps.size()) + independent;
  // Bonferroni counts each ray as a test of its own: a fit that searches the sizes tries them.
  int tests = out.hypotheses;
  for (const Hypothesis& h : hyps) tests += static_cast<int>(h.rays.size());
  out.bonferroni = alpha / std::max(1, tests);
  out.level = out.bonferroni;
  if (tests <= 1 || draws < 100) return out;
  out.level = std::max(out.bonferroni, MinPQuantile(G, hyps, independent, alpha, draws));
  out.draws = draws;
  return out;
}

}  // namespace hoof::discovery::internal
