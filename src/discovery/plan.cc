// Detection limits and plans of the discovery workflow (docs/discovery.md, "Detection limits
// and plans"): the Fisher information about an effect that a study holds once zeta and mu per
// surface are profiled out, the smallest size it detects with 80 % power (from the noncentrality
// of the study's expected data with the effect added, zeta and mu refitted), and how many trials,
// and of which conditions, would detect a given size.
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>
#include <tuple>

#include <Eigen/QR>
#include <boost/math/distributions/normal.hpp>

#include "discovery/internal.h"
#include "stats/distributions.h"

namespace hoof::discovery {
namespace internal {

WhitenedDesign Whiten(const Workspace& ws, const std::vector<Sensitivity>& sens,
                      const std::vector<TrialCovariance>& ref) {
  const auto S = static_cast<Eigen::Index>(ws.surfaces.size());
  WhitenedDesign w;
  w.first.assign(ws.obs.size() + 1, 0);
  for (std::size_t i = 0; i < ws.obs.size(); ++i)
    w.first[i + 1] = w.first[i] + static_cast<Eigen::Index>(ref[i].components.size());
  w.X = Eigen::MatrixXd::Zero(w.first.back(), 2 * S);
  for (std::size_t i = 0; i < ws.obs.size(); ++i) {
    const auto& t = ref[i];
    const auto n = static_cast<Eigen::Index>(t.components.size());
    Eigen::MatrixXd J(n, 2);
    for (Eigen::Index a = 0; a < n; ++a)
      J.row(a) = sens[i].row(t.components[static_cast<std::size_t>(a)]);
    w.X.block(w.first[i], 2 * ws.obs[i].surface, n, 2) = t.whiten * J;
  }
  return w;
}

Eigen::VectorXd WhitenChange(const Workspace& ws, const std::vector<Eigen::Vector3d>& d_r,
                             const std::vector<TrialCovariance>& ref, const WhitenedDesign& w) {
  Eigen::VectorXd d = Eigen::VectorXd::Zero(w.first.back());
  for (std::size_t i = 0; i < ws.obs.size(); ++i) {
    const auto& t = ref[i];
    const auto n = static_cast<Eigen::Index>(t.components.size());
    Eigen::VectorXd v(n);
    for (Eigen::Index a = 0; a < n; ++a) {
      const int c = t.components[static_cast<std::size_t>(a)];
      v[a] = std::isfinite(d_r[i][c]) ? d_r[i][c] : 0.0;
    }
    d.segment(w.first[i], n) = t.whiten * v;
  }
  return d;
}

std::vector<double> ProfiledInformation(const Workspace& ws,
                                        const std::vector<Eigen::Vector3d>& d_r,
                                        const std::vector<Sensitivity>& sens,
                                        const std::vector<TrialCovariance>& ref) {
  const WhitenedDesign w = Whiten(ws, sens, ref);
  const Eigen::VectorXd d = WhitenChange(ws, d_r, ref, w);
  // What zeta and mu can take up of the effect's change is projected out.
  const Eigen::VectorXd coef = w.X.completeOrthogonalDecomposition().solve(d);
  const Eigen::VectorXd left = d - w.X * coef;
  std::vector<double> info(ws.obs.size(), 0.0);
  for (std::size_t i = 0; i < ws.obs.size(); ++i)
    info[i] = left.segment(w.first[i], w.first[i + 1] - w.first[i]).squaredNorm();
  return info;
}

ProfileOut::ProfileOut(const WhitenedDesign& w) {
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(w.X);
  q_ = qr.householderQ() * Eigen::MatrixXd::Identity(w.X.rows(), qr.rank());
}

namespace {

/// The root of the noncentrality at which a one-sided test at `level` has 80 % power:
/// z_(1-level) + z_0.8.
double RootForEightyPercent(double level) {
  const boost::math::normal z;
  return boost::math::quantile(boost::math::complement(z, level)) + boost::math::quantile(z, 0.8);
}

}  // namespace

double DetectionLimit(const std::vector<double>& information, double level) {
  const double info = std::accumulate(information.begin(), information.end(), 0.0);
  if (!(info > 0)) return kNaN;
  return RootForEightyPercent(level) / std::sqrt(info);
}

SizeLadder Ladder(const Workspace& ws, const Model& current, const std::string& key,
                  const std::vector<Eigen::Vector3d>& r_current,
                  const std::vector<Sensitivity>& sens, const std::vector<TrialCovariance>& ref) {
  const LibraryEntry& e = Entry(key);
  const double lo = e.smallest > 0 ? e.smallest : 1e-3 * e.probe;
  const int n =
      std::max(2, static_cast<int>(std::ceil(std::log10(e.upper / lo) * e.ladder_per_decade)) + 1);
  const WhitenedDesign w = Whiten(ws, sens, ref);
  const ProfileOut profile(w);
  const std::vector<int> all = ws.All();
  SizeLadder ladder;
  ladder.smallest = e.smallest;
  ladder.current = profile(WhitenChange(ws, r_current, ref, w));
  for (int k = 0; k < n; ++k) {
    const double size = lo * std::pow(e.upper / lo, static_cast<double>(k) / (n - 1));
    Model m = current;
    m.effects[key] = {EffectForm::kShared, {size}};
    const auto r = ws.Residuals(m, all);
    std::vector<Eigen::Vector3d> change(ws.obs.size());
    for (std::size_t i = 0; i < ws.obs.size(); ++i) change[i] = r_current[i] - r[i];
    ladder.size.push_back(size);
    ladder.projected.push_back(profile(WhitenChange(ws, change, ref, w)));
    ladder.change.push_back(std::move(change));
  }
  return ladder;
}

std::vector<double> LadderStarts(const SizeLadder& ladder, std::size_t most) {
  const std::size_t n = ladder.size.size();
  std::vector<double> gain(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::VectorXd& b = ladder.projected[k];
    gain[k] = 2 * ladder.current.dot(b) - b.squaredNorm();
  }
  std::vector<std::size_t> peaks;
  for (std::size_t k = 0; k < n; ++k)
    if (gain[k] > 0 && (k == 0 || gain[k] >= gain[k - 1]) && (k + 1 == n || gain[k] > gain[k + 1]))
      peaks.push_back(k);
  std::stable_sort(peaks.begin(), peaks.end(),
                   [&](std::size_t a, std::size_t b) { return gain[a] > gain[b]; });
  if (peaks.size() > most) peaks.resize(most);
  std::vector<double> sizes;
  for (std::size_t k : peaks) sizes.push_back(ladder.size[k]);
  return sizes;
}

double LadderDetectionLimit(const SizeLadder& ladder, double level) {
  const std::size_t n = ladder.size.size();
  if (n == 0) return kNaN;
  const double root_target = RootForEightyPercent(level);
  std::vector<double> root(n);
  for (std::size_t k = 0; k < n; ++k) root[k] = ladder.projected[k].norm();
  if (!(root[n - 1] >= root_target)) return kNaN;
  std::size_t k = n - 1;
  while (k > 0 && root[k - 1] >= root_target) --k;
  if (k == 0) {
    // Detected on the whole ladder. A fit that may not go below the first size names nothing
    // smaller; otherwise the change below it is taken to grow in proportion to the size.
    if (ladder.smallest > 0) return ladder.size[0];
    return ladder.size[0] * root_target / root[0];
  }
  // Between the last size missed and the first detected, in log size.
  const double t = (root_target - root[k - 1]) / (root[k] - root[k - 1]);
  return std::exp(std::log(ladder.size[k - 1]) +
                  t * (std::log(ladder.size[k]) - std::log(ladder.size[k - 1])));
}

double ExpectedDetectionLimit(const Workspace& ws, const Fit& current,
                              const std::vector<std::string>& free_current, const std::string& key,
                              const SizeLadder& ladder, double level) {
  const std::size_t n = ladder.size.size();
  if (n == 0) return kNaN;
  const double target = RootForEightyPercent(level);
  // The root of the noncentrality at a size, from the expected data; where the simulator fails
  // there, from the tangent plane.
  auto root_at = [&](double size, double fallback) {
    const double lambda = ExpectedNoncentrality(ws, current, free_current, key, size);
    return std::isfinite(lambda) ? std::sqrt(lambda) : fallback;
  };
  std::vector<double> root(n, kNaN);
  auto root_k = [&](std::size_t k) {
    if (!std::isfinite(root[k])) root[k] = root_at(ladder.size[k], ladder.projected[k].norm());
    return root[k];
  };
  if (!(root_k(n - 1) >= target)) return kNaN;
  // The first size detected, by bisection over the ladder (the noncentrality taken to grow with
  // the size), starting from the tangent plane's bracket: where the tangent plane is right, two
  // solves settle it.
  std::size_t hi = n - 1;  // detected
  std::ptrdiff_t lo = -1;  // the last index known missed (-1: none)
  std::size_t guess = n - 1;
  while (guess > 0 && ladder.projected[guess - 1].norm() >= target) --guess;
  if (guess < hi && root_k(guess) >= target)
    hi = guess;
  else if (guess < hi)
    lo = static_cast<std::ptrdiff_t>(guess);
  if (hi > 0 && static_cast<std::ptrdiff_t>(hi) - 1 > lo) {
    if (root_k(hi - 1) >= target)
      hi = hi - 1;
    else
      lo = static_cast<std::ptrdiff_t>(hi) - 1;
  }
  while (static_cast<std::ptrdiff_t>(hi) - lo > 1) {
    const auto mid = static_cast<std::size_t>((lo + static_cast<std::ptrdiff_t>(hi)) / 2);
    if (root_k(mid) >= target)
      hi = mid;
    else
      lo = static_cast<std::ptrdiff_t>(mid);
  }
  if (lo < 0) {
    // Detected at the smallest size: a fit that may not go below it names nothing smaller;
    // otherwise the change below it is taken to grow in proportion to the size.
    if (ladder.smallest > 0) return ladder.size[0];
    return ladder.size[0] * target / root_k(0);
  }
  // Between the last size missed and the first detected: regula falsi in log size on the root,
  // two steps (Illinois), so that the power at the limit is 80 % to a per cent or two.
  double a = std::log(ladder.size[static_cast<std::size_t>(lo)]), b = std::log(ladder.size[hi]);
  double fa = root_k(static_cast<std::size_t>(lo)) - target, fb = root_k(hi) - target;
  int side = 0;
  for (int step = 0; step < 2; ++step) {
    const double c = b - fb * (b - a) / (fb - fa);
    const double fc = root_at(std::exp(c), kNaN) - target;
    if (!std::isfinite(fc)) break;
    if (fc >= 0) {
      b = c, fb = fc;
      if (side == 1) fa /= 2;
      side = 1;
    } else {
      a = c, fa = fc;
      if (side == -1) fb /= 2;
      side = -1;
    }
  }
  return std::exp(b - fb * (b - a) / (fb - fa));
}

std::vector<LadderRay> LadderRays(const Workspace& ws, const SizeLadder& ladder,
                                  const std::vector<Eigen::Vector3d>& d_r,
                                  const std::vector<Sensitivity>& sens,
                                  const std::vector<TrialCovariance>& ref, double cos_max) {
  const WhitenedDesign w = Whiten(ws, sens, ref);
  const ProfileOut profile(w);
  const Eigen::VectorXd secant = profile(WhitenChange(ws, d_r, ref, w));
  const Eigen::VectorXd along = secant.norm() > 0 ? secant.normalized() : secant;
  // The sizes that the secant does not describe, and the directions taken among them.
  std::vector<std::size_t> off;
  std::vector<std::size_t> taken;  // ladder indices of the rays' representatives
  std::vector<Eigen::VectorXd> unit;
  for (std::size_t k = 0; k < ladder.size.size(); ++k) {
    const Eigen::VectorXd& b = ladder.projected[k];
    if (!(b.norm() > 0)) continue;
    const Eigen::VectorXd u = b.normalized();
    if (along.dot(u) >= cos_max) continue;
    off.push_back(k);
    bool described = false;
    for (const auto& t : unit) described |= t.dot(u) >= cos_max;
    if (described) continue;
    taken.push_back(k);
    unit.push_back(u);
  }
  std::vector<LadderRay> rays(taken.size());
  std::vector<bool> seen(taken.size(), false);
  for (std::size_t k : off) {
    const Eigen::VectorXd& b = ladder.projected[k];
    std::size_t nearest = 0;
    for (std::size_t r = 1; r < unit.size(); ++r)
      if (unit[r].dot(b) > unit[nearest].dot(b)) nearest = r;
    const double t = unit[nearest].dot(b) / ladder.projected[taken[nearest]].norm();
    LadderRay& ray = rays[nearest];
    ray.low = seen[nearest] ? std::min(ray.low, t) : t;
    ray.high = seen[nearest] ? std::max(ray.high, t) : t;
    seen[nearest] = true;
  }
  for (std::size_t r = 0; r < taken.size(); ++r) rays[r].change = ladder.change[taken[r]];
  return rays;
}

CandidateProbes ProbeCandidates(const Workspace& ws, const Model& current,
                                const std::vector<std::string>& keys,
                                const std::vector<Eigen::Vector3d>& residual_current,
                                const std::vector<Sensitivity>& sens,
                                const std::vector<TrialCovariance>& ref,
                                const DiscoveryOptions& options) {
  CandidateProbes out;
  const std::vector<int> all = ws.All();
  int n_ratio = 0;
  for (const Obs& o : ws.obs) n_ratio += std::isfinite(o.marker_ratio) ? 1 : 0;
  std::vector<std::vector<Eigen::Vector3d>> changes;
  std::vector<std::vector<LadderRay>> rays;
  int independent = 0;
  for (const auto& key : keys) {
    const LibraryEntry& e = Entry(key);
    if (e.measurement_effect) {
      independent += n_ratio >= 3 ? 1 : 0;
      continue;
    }
    Model probe = current;
    probe.effects[key] = {EffectForm::kShared, {e.probe}};
    const auto& r_probe = out.residual_probe[key] = ws.Residuals(probe, all);
    auto& d_r = out.change[key];
    d_r.resize(ws.obs.size());
    for (std::size_t i = 0; i < ws.obs.size(); ++i)
      d_r[i] = (residual_current[i] - r_probe[i]) / e.probe;
    changes.push_back(d_r);
    const SizeLadder& ladder = out.ladder[key] =
        Ladder(ws, current, key, residual_current, sens, ref);
    rays.push_back(LadderRays(ws, ladder, d_r, sens, ref));
  }
  // Min-P over the hypotheses tried, each candidate once per form (shared and, with two or more
  // surfaces, per surface: the form is chosen from the same data).
  out.naming = CalibrateNamingLevel(ws, changes, sens, ref, options.per_surface, independent,
                                    options.alpha, 20000, rays);
  return out;
}

}  // namespace internal

using namespace internal;

namespace {

/// The library entry of `key`, checked for a plan of `size` with `bootstrap_draws` draws; throws
/// std::invalid_argument naming what is wrong.
const LibraryEntry& PlanEntry(const std::string& key, double size, int bootstrap_draws) {
  if (bootstrap_draws < 0)
    throw std::invalid_argument("plan: the bootstrap's draws must be >= 0, got " +
                                std::to_string(bootstrap_draws));
  const LibraryEntry& e = Entry(key);
  if (e.measurement_effect)
    throw std::invalid_argument("plan: '" + key +
                                "' is a measurement effect; plans are for contact effects");
  if (!(size > 0 && size <= e.upper))
    throw std::invalid_argument("plan: the size of '" + key + "' must be in (0, " + Fmt(e.upper) +
                                "], got " + Fmt(size));
  return e;
}

/// Where the information comes from, per condition (surface and angle; speeds as a range), the
/// most informative per trial first. `info` is each trial's, `total` their sum.
std::vector<PlanCondition> PlanConditions(const Workspace& ws, const std::vector<double>& info,
                                          double total) {
  std::vector<PlanCondition> conditions;
  std::map<std::pair<int, double>, PlanCondition> by;
  for (std::size_t i = 0; i < ws.obs.size(); ++i) {
    const Obs& o = ws.obs[i];
    auto [it, added] = by.try_emplace({o.surface, o.angle_deg});
    PlanCondition& c = it->second;
    if (added) {
      c.surface = ws.surfaces[static_cast<std::size_t>(o.surface)];
      c.angle_deg = o.angle_deg;
      c.speed_low_m_s = c.speed_high_m_s = o.scale;
    }
    c.speed_low_m_s = std::min(c.speed_low_m_s, o.scale);
    c.speed_high_m_s = std::max(c.speed_high_m_s, o.scale);
    ++c.trials;
    c.information_per_trial += info[i];
    c.share += total > 0 ? info[i] / total : kNaN;
  }
  for (auto& [k, c] : by) {
    c.information_per_trial /= c.trials;
    conditions.push_back(c);
  }
  std::stable_sort(conditions.begin(), conditions.end(), [](const auto& a, const auto& b) {
    return a.information_per_trial > b.information_per_trial;
  });
  return conditions;
}

}  // namespace

Plan PlanDetection(const std::vector<pipeline::TrialAnalysis>& trials, const std::string& key,
                   double size, const DiscoveryOptions& options, int bootstrap_draws,
                   const std::function<void(const std::string&)>& progress) {
  options.Validate();
  const LibraryEntry& e = PlanEntry(key, size, bootstrap_draws);
  Plan plan;
  plan.key = key;
  plan.name = e.name;
  plan.parameter = e.parameter;
  plan.unit = e.unit;
  plan.size = size;
  Workspace ws;
  int skipped = 0;
  Build(trials, options, &skipped, ws);
  plan.trials = static_cast<int>(ws.obs.size());
  if (ws.obs.size() < 6) {
    plan.message = "too few measured trials with a fitted surface model (" +
                   std::to_string(ws.obs.size()) + "; at least 6 are needed)";
    return plan;
  }
  const std::vector<int> all = ws.All();
  const Fit base = FitBaseline(ws);
  const auto sens = ws.Sensitivities(base.model, all);
  const std::vector<TrialCovariance> ref = Covariances(ws, sens, base.noise);
  const auto r0 = ws.Residuals(base.model, all);
  // The naming level and the detection limit of the first round, as Discover sets them.
  std::vector<std::string> keys = options.candidates;
  if (keys.empty())
    for (const LibraryEntry& c : Library()) keys.push_back(c.key);
  const CandidateProbes probes = ProbeCandidates(ws, base.model, keys, r0, sens, ref, options);
  plan.level = probes.naming.level;
  const auto own = probes.ladder.find(key);
  plan.detection_limit = ExpectedDetectionLimit(
      ws, base, {}, key,
      own != probes.ladder.end() ? own->second : Ladder(ws, base.model, key, r0, sens, ref),
      plan.level);
  // The change at `size` itself (simulated, not scaled from another size), zeta and mu profiled
  // out: its noncentrality gives the power, and it grows in proportion to the trials.
  Model with = base.model;
  with.effects[key] = {EffectForm::kShared, {size}};
  const auto r1 = ws.Residuals(with, all);
  std::vector<Eigen::Vector3d> d_r(ws.obs.size());
  for (std::size_t i = 0; i < ws.obs.size(); ++i) d_r[i] = (r0[i] - r1[i]) / size;
  const auto info = ProfiledInformation(ws, d_r, sens, ref);
  const double total = std::accumulate(info.begin(), info.end(), 0.0);
  // The noncentrality itself from the study's expected data, as the detection limit takes it
  // (the tangent plane's where the simulator fails); the shares of the conditions are the
  // tangent plane's.
  const double expected = ExpectedNoncentrality(ws, base, {}, key, size);
  const double noncentrality = std::isfinite(expected) ? expected : size * size * total;
  const boost::math::normal z;
  const double z_level = boost::math::quantile(boost::math::complement(z, plan.level));
  const double z_target = RootForEightyPercent(plan.level);
  plan.power = noncentrality > 0 ? boost::math::cdf(z, std::sqrt(noncentrality) - z_level) : kNaN;
  plan.trials_needed =
      noncentrality > 0 ? std::ceil(plan.trials * z_target * z_target / noncentrality) : kNaN;
  plan.conditions = PlanConditions(ws, info, total);
  plan.bootstrap_power = plan.bootstrap_low = plan.bootstrap_high = kNaN;
  if (bootstrap_draws > 0) {
    const BootstrapResult b =
        BootstrapDetection(ws, base, key, size, plan.level, options, bootstrap_draws, progress);
    plan.bootstrap_draws = b.draws;
    plan.bootstrap_detected = b.detected;
    plan.bootstrap_lr_significant = b.lr_significant;
    plan.bootstrap_power = static_cast<double>(b.detected) / b.draws;
    std::tie(plan.bootstrap_low, plan.bootstrap_high) = stats::WilsonInterval(b.detected, b.draws);
  }
  plan.success = true;
  return plan;
}

}  // namespace hoof::discovery
