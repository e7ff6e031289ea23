// Out-of-plane rotation that grows in time (docs/discovery.md, "Out-of-plane rotation that grows"):
// a tilt or roll rate of the specimen, judged by two kinds of evidence at once.
//  - The marker distance per frame: a rotation at a steady rate makes it dip toward the impact
//    time and recover after it. Each trial's distance keeps its own scale (so a scale
//    calibration error cannot pass for a rotation); only the shape in time counts.
//  - The velocities: markers on the face toward the camera slide sideways as the body turns,
//    and the flight fits take the slide for a velocity. The trials are re-measured with the
//    motion (pipeline::RemeasureOutOfPlane) and the current contact model refitted to them.
// The two are independent data; their log-likelihoods add. The rate's sign is free (two-sided).
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include <boost/math/distributions/normal.hpp>
#include <boost/math/tools/minima.hpp>

#include "core/frames.h"
#include "discovery/internal.h"
#include "stats/distributions.h"

namespace hoof::discovery::internal {
namespace {

constexpr double kDeg = core::kRadPerDeg;

pipeline::OutOfPlaneMotion WithRate(pipeline::OutOfPlaneMotion m, const std::string& key,
                                    double rate_rad_s) {
  if (key == "out_of_plane_rate")
    m.tilt_rate_rad_s += rate_rad_s;
  else
    m.roll_rate_rad_s += rate_rad_s;
  return m;
}

/// One trial's marker distance ratio over its flight windows, with the times from its impact.
struct RatioSeries {
  std::vector<double> t_s, ratio;
};

std::vector<RatioSeries> Series(const Workspace& ws,
                                const std::vector<pipeline::TrialAnalysis>& measured) {
  std::vector<RatioSeries> out(ws.obs.size());
  for (std::size_t i = 0; i < ws.obs.size(); ++i) {
    const pipeline::TrialAnalysis& t = measured[ws.obs[i].trial_index];
    for (const auto* fit : {&t.impact.before, &t.impact.after})
      for (int f = fit->first_frame; f <= fit->last_frame; ++f) {
        if (f < 0 || static_cast<std::size_t>(f) >= t.marker_distance_ratio.size()) continue;
        const double r = t.marker_distance_ratio[static_cast<std::size_t>(f)];
        if (!std::isfinite(r)) continue;
        out[i].t_s.push_back(f / t.spec.fps - t.impact.impact_time_s);
        out[i].ratio.push_back(r);
      }
    if (out[i].t_s.size() < 3) out[i] = {};
  }
  return out;
}

/// Per obs, the residual sum of squares of the marker distance about its own scale times the
/// ratio `motion` predicts (NaN without a series), and the frames.
struct RatioTerms {
  std::vector<double> rss;
  std::vector<int> frames;
  double Loglik(const std::vector<int>& which) const {
    double ss = 0;
    int n = 0;
    for (int i : which)
      if (std::isfinite(rss[static_cast<std::size_t>(i)]))
        ss += rss[static_cast<std::size_t>(i)], n += frames[static_cast<std::size_t>(i)];
    return n > 0 ? -0.5 * n * std::log(std::max(ss / n, 1e-300)) : 0.0;
  }
  double Variance(const std::vector<int>& which) const {
    double ss = 0;
    int n = 0;
    for (int i : which)
      if (std::isfinite(rss[static_cast<std::size_t>(i)]))
        ss += rss[static_cast<std::size_t>(i)], n += frames[static_cast<std::size_t>(i)];
    return n > 0 ? ss / n : kNaN;
  }
};

RatioTerms Ratio(const Workspace& ws, const std::vector<pipeline::TrialAnalysis>& measured,
                 const std::vector<RatioSeries>& series, const pipeline::OutOfPlaneMotion& m) {
  RatioTerms out{std::vector<double>(ws.obs.size(), kNaN), std::vector<int>(ws.obs.size(), 0)};
  for (std::size_t i = 0; i < ws.obs.size(); ++i) {
    const RatioSeries& s = series[i];
    if (s.t_s.empty()) continue;
    const auto& specimen = measured[ws.obs[i].trial_index].spec.specimen;
    std::vector<double> model(s.t_s.size());
    double rm = 0, mm = 0;
    for (std::size_t f = 0; f < s.t_s.size(); ++f) {
      model[f] = pipeline::MarkerDistanceRatio(specimen, m.TiltAt(s.t_s[f]), m.RollAt(s.t_s[f]));
      rm += s.ratio[f] * model[f];
      mm += model[f] * model[f];
    }
    const double a = rm / mm;
    double rss = 0;
    for (std::size_t f = 0; f < s.t_s.size(); ++f)
      rss += (s.ratio[f] - a * model[f]) * (s.ratio[f] - a * model[f]);
    out.rss[i] = rss;
    out.frames[i] = static_cast<int>(s.t_s.size());
  }
  return out;
}

/// The rate of largest marker-distance likelihood over the obs `which` (a coarse grid on both
/// signs, then Brent between the best point's neighbours).
double RatioOnlyRate(const Workspace& ws, const std::vector<pipeline::TrialAnalysis>& measured,
                     const std::vector<RatioSeries>& series, const RoundState& st,
                     const std::string& key, const std::vector<int>& which, double upper) {
  auto minus = [&](double w) {
    return -Ratio(ws, measured, series, WithRate(st.motion, key, w)).Loglik(which);
  };
  std::vector<double> grid{0.0};
  for (int k = 0; k <= 12; ++k)
    grid.push_back(upper * std::pow(0.5, k)), grid.push_back(-upper * std::pow(0.5, k));
  std::sort(grid.begin(), grid.end());
  std::size_t best = 0;
  std::vector<double> value(grid.size());
  for (std::size_t j = 0; j < grid.size(); ++j) {
    value[j] = minus(grid[j]);
    if (value[j] < value[best]) best = j;
  }
  const double lo = grid[best > 0 ? best - 1 : 0], hi = grid[std::min(best + 1, grid.size() - 1)];
  if (!(hi > lo)) return grid[best];
  std::uintmax_t iterations = 40;
  const auto r = boost::math::tools::brent_find_minima(minus, lo, hi, 30, iterations);
  return r.second < value[best] ? r.first : grid[best];
}

/// The trials re-measured with a motion, and the workspace built from them (null when an obs
/// was lost: the likelihoods would not be of the same trials).
struct Remeasured {
  std::shared_ptr<std::vector<pipeline::TrialAnalysis>> trials;
  std::unique_ptr<Workspace> ws;
};

Remeasured Remeasure(const Workspace& ws, const std::vector<pipeline::TrialAnalysis>& measured,
                     const pipeline::OutOfPlaneMotion& m, const DiscoveryOptions& options) {
  Remeasured out;
  out.trials = std::make_shared<std::vector<pipeline::TrialAnalysis>>(measured.size());
  ws.ParallelFor(measured.size(), [&](std::size_t i) {
    (*out.trials)[i] = pipeline::RemeasureOutOfPlane(measured[i], m, options.kinematics);
  });
  auto w = std::make_unique<Workspace>();
  int skipped = 0;
  try {
    Build(*out.trials, options, &skipped, *w);
  } catch (const std::exception&) {
    // A rate far from the truth can bias a trial past e = 1, where the surface's starting
    // model cannot be made: the rate is not a feasible point.
    return out;
  }
  bool same = w->obs.size() == ws.obs.size();
  for (std::size_t i = 0; same && i < ws.obs.size(); ++i)
    same = w->obs[i].trial_index == ws.obs[i].trial_index;
  if (same) out.ws = std::move(w);
  return out;
}

/// The joint log-likelihood at one rate, with what it was computed from.
struct Point {
  double rate = 0.0;
  double loglik = -HUGE_VAL, ratio_loglik = 0.0, velocity_loglik = -HUGE_VAL;
  Fit fit;
  Remeasured remeasured;
};

/// Detection limit of a rotation rate (degrees per second, NaN beyond `upper`): the smallest
/// rate whose noncentrality, from the velocities (their information `info_velocity` about the
/// rate, quadratic in it) and the marker distance (its dip, each trial's mean removed, over the
/// no-rate variance), gives a two-sided test with critical value `z_level` 80 % power.
double DetectionLimit(const Workspace& ws, const std::vector<pipeline::TrialAnalysis>& measured,
                      const std::vector<RatioSeries>& series, const RoundState& st,
                      const std::string& key, const RatioTerms& none, double z_level, double upper,
                      double info_velocity) {
  const double var = none.Variance(ws.All());
  auto noncentrality = [&](double rate) {
    double lambda = info_velocity * rate * rate;
    if (var > 0) {
      const pipeline::OutOfPlaneMotion m = WithRate(st.motion, key, rate);
      for (std::size_t i = 0; i < ws.obs.size(); ++i) {
        const RatioSeries& s = series[i];
        if (s.t_s.empty()) continue;
        const auto& specimen = measured[ws.obs[i].trial_index].spec.specimen;
        std::vector<double> d(s.t_s.size());
        for (std::size_t j = 0; j < d.size(); ++j)
          d[j] = pipeline::MarkerDistanceRatio(specimen, m.TiltAt(s.t_s[j]), m.RollAt(s.t_s[j])) -
                 pipeline::MarkerDistanceRatio(specimen, st.motion.TiltAt(s.t_s[j]),
                                               st.motion.RollAt(s.t_s[j]));
        const double md = std::accumulate(d.begin(), d.end(), 0.0) / static_cast<double>(d.size());
        for (double x : d) lambda += (x - md) * (x - md) / var;
      }
    }
    return lambda;
  };
  const double target = std::pow(z_level + boost::math::quantile(boost::math::normal(), 0.8), 2);
  if (!(noncentrality(upper) >= target)) return kNaN;
  double lo = 0, hi = upper;
  for (int it = 0; it < 60; ++it) {
    const double m = 0.5 * (lo + hi);
    (noncentrality(m) >= target ? hi : lo) = m;
  }
  return hi / kDeg;
}

/// One rotation rate's search (EvaluateRotationRate), with what each of its steps needs.
struct RateSearch {
  const Workspace& ws;
  const RoundState& st;
  const std::string& key;
  const std::vector<std::string>& free_current;
  const DiscoveryOptions& options;
  const std::vector<pipeline::TrialAnalysis>& measured = *st.measured;
  const std::vector<int> all = ws.All();
  const std::vector<RatioSeries> series = Series(ws, measured);
  const double upper = Entry(key).upper * kDeg, probe = Entry(key).probe * kDeg;

  /// Whether the rate leaves the distance of the layout's first two markers as it is (a roll
  /// when they lie along x_B): then nothing is held out, and the velocities alone decide.
  bool RatioBlind() const {
    bool blind = true;
    const pipeline::OutOfPlaneMotion with = WithRate(st.motion, key, probe);
    for (const Obs& o : ws.obs) {
      const auto& specimen = measured[o.trial_index].spec.specimen;
      blind &=
          std::abs(pipeline::MarkerDistanceRatio(specimen, with.TiltAt(2e-3), with.RollAt(2e-3)) -
                   pipeline::MarkerDistanceRatio(specimen, st.motion.TiltAt(2e-3),
                                                 st.motion.RollAt(2e-3))) < 1e-9;
    }
    return blind;
  }

  /// The marker distance's log-likelihood at `rate`.
  double RatioLoglik(double rate) const {
    return Ratio(ws, measured, series, WithRate(st.motion, key, rate)).Loglik(all);
  }

  /// The trials re-measured with `rate` and the current model refitted to them (`passes` of
  /// fit and noise model): the joint log-likelihood, -inf where the point is not feasible.
  Point Evaluate(double rate, int passes) const {
    Point p;
    p.rate = rate;
    const pipeline::OutOfPlaneMotion m = WithRate(st.motion, key, rate);
    p.ratio_loglik = Ratio(ws, measured, series, m).Loglik(all);
    p.remeasured = Remeasure(ws, measured, m, options);
    if (!p.remeasured.ws) return p;
    try {
      p.fit = FitModel(*p.remeasured.ws, all, st.current.model, free_current, st.current.noise,
                       true, passes);
    } catch (const std::exception&) {
      return p;  // not a feasible point (see Remeasure)
    }
    if (!p.fit.ok) return p;
    p.velocity_loglik = p.fit.loglik;
    p.loglik = p.ratio_loglik + p.velocity_loglik;
    return p;
  }

  /// The best point of the joint likelihood from `zero` and the starts (the ratio's own rate,
  /// either sign, and the probe's), refined by Brent on its side; `velocity` gets the
  /// velocities' log-likelihood at each start.
  Point Search(const Point& zero, double from_ratio, std::map<double, double>& velocity) const {
    std::vector<double> starts;
    if (from_ratio > 1e-3 * probe) starts = {from_ratio, -from_ratio};
    starts.push_back(probe);
    starts.push_back(-probe);
    Point best;
    best.rate = 0.0;
    best.loglik = zero.loglik;
    velocity = {{0.0, zero.velocity_loglik}};
    for (double s : starts) {
      Point p = Evaluate(s, kSearchPasses);
      velocity[s] = p.velocity_loglik;
      if (p.loglik > best.loglik) best = std::move(p);
    }
    if (best.rate != 0.0) {
      // Refine on the best point's side, between a quarter and four times it.
      const double sign = best.rate > 0 ? 1.0 : -1.0;
      const double a = std::abs(best.rate) / 4, b = std::min(upper, 4 * std::abs(best.rate));
      std::uintmax_t iterations = 12;
      auto minus = [&](double r) {
        Point p = Evaluate(sign * r, kSearchPasses);
        const double value = std::isfinite(p.loglik) ? -p.loglik : HUGE_VAL;
        if (p.loglik > best.loglik) best = std::move(p);  // kept: not evaluated again
        return value;
      };
      boost::math::tools::brent_find_minima(minus, a, b, 10, iterations);
    }
    return best;
  }

  /// Held out: the marker distance of each fold's trials under the rate fitted without them,
  /// against no rate, both in units of the no-rate variance of the other folds.
  void HeldOut(const RatioTerms& none, bool ratio_blind, CandidateResult& c) const {
    CrossValidation cv, cv_none;
    cv.error.assign(ws.obs.size(), kNaN);
    cv_none.error.assign(ws.obs.size(), kNaN);
    for (int f = 0; f < options.folds && !ratio_blind; ++f) {
      std::vector<int> train, test;
      for (int i : all) (ws.obs[static_cast<std::size_t>(i)].fold == f ? test : train).push_back(i);
      const double rate = RatioOnlyRate(ws, measured, series, st, key, train, upper);
      const RatioTerms with = Ratio(ws, measured, series, WithRate(st.motion, key, rate));
      const double var = none.Variance(train);
      if (!(var > 0)) continue;
      for (int i : test) {
        const auto k = static_cast<std::size_t>(i);
        if (!std::isfinite(none.rss[k])) continue;
        cv_none.error[k] = none.rss[k] / none.frames[k] / var;
        cv.error[k] = with.rss[k] / with.frames[k] / var;
      }
    }
    auto mean = [](const std::vector<double>& v) {
      double s = 0;
      int n = 0;
      for (double x : v)
        if (std::isfinite(x)) s += x, ++n;
      return n ? s / n : kNaN;
    };
    c.cv_error = mean(cv.error);
    c.cv_error_current = mean(cv_none.error);
    c.cv_p = PairedImprovementP(cv_none.error, cv.error);
    if (ratio_blind || !std::isfinite(c.cv_error)) c.cv_error = c.cv_error_current = c.cv_p = kNaN;
  }

  static constexpr int kSearchPasses = 2;
};

/// A rate the image cannot see, in a round after the first: not measured again.
void NotMeasuredAgain(CandidateResult& c) {
  c.fitted = false;
  c.message = "not measured again after round 1 (the image cannot see it)";
  c.estimate = c.se = c.p_value = c.lr_statistic = c.delta_aic = c.delta_bic = kNaN;
  c.detection_limit = kNaN;
  c.identifiability = Identifiability::kNotTested;
  c.outcome = CandidateOutcome::kNotTested;
  c.reason =
      "the distance of the layout's first two markers does not change with this rotation, and "
      "its bias of the velocities alone cannot be told from a contact effect on v_x and spin; "
      "measured in round 1 only, since it cannot be named in any round";
}

/// Why a rate that the image cannot see, or that only the velocities show, is not named.
void ExplainRate(bool ratio_blind, double ratio_p, double level, CandidateResult& c) {
  if (ratio_blind) {
    c.identifiability = Identifiability::kNotTested;
    c.outcome = CandidateOutcome::kNotTested;
    c.reason =
        "the distance of the layout's first two markers does not change with this rotation, and "
        "its bias "
        "of the velocities alone cannot be told from a contact effect on v_x and spin (LR p = " +
        FmtP(c.p_value) + "); markers apart across the axis, or a second camera, would test it";
  } else if (c.p_value < level && c.wald_clear && !(ratio_p < level)) {
    c.outcome = CandidateOutcome::kNotSignificant;
    c.reason =
        "likelihood-ratio p = " + FmtP(c.p_value) +
        ", but the marker distance alone does not show it (p = " + FmtP(ratio_p) +
        "): a bias of the velocities alone is also what a contact effect on v_x and spin does";
  }
}

/// The information about a parameter from the curvature of a log-likelihood (0 where it is not
/// finite or not negative).
double Information(double curvature) {
  return std::isfinite(curvature) ? std::max(0.0, -curvature) : 0.0;
}

/// Ends an evaluation at the point `p` of the search: its fit, the motion with its rate, and the
/// trials re-measured with it.
void Finish(const RateSearch& x, Point& p, RateEvaluation& out) {
  out.fit = p.fit;
  out.motion = WithRate(x.st.motion, x.key, p.rate);
  out.remeasured = p.remeasured.trials;
  out.ws = std::move(p.remeasured.ws);
}

/// A later round where the marker distance alone does not show the rate (ratio p `ratio_p`):
/// named only with the image's evidence, so the velocities are not searched again; the probes
/// on either side of 0 still give their information for the detection limit.
void NotSearchedAgain(const RateSearch& x, Point& zero, double ratio_p, double z_level,
                      const RatioTerms& none, RateEvaluation& out) {
  constexpr int kSearchPasses = RateSearch::kSearchPasses;
  CandidateResult& c = out.c;
  const double curvature_at_0 =
      (x.Evaluate(x.probe, kSearchPasses).velocity_loglik - 2 * zero.velocity_loglik +
       x.Evaluate(-x.probe, kSearchPasses).velocity_loglik) /
      (x.probe * x.probe);
  c.fitted = false;
  c.message = "not searched again after round 1: the marker distance alone does not show it";
  c.estimate = c.se = c.p_value = c.lr_statistic = c.delta_aic = c.delta_bic = kNaN;
  c.cv_error = c.cv_error_current = c.cv_p = kNaN;
  c.identifiability = Identifiability::kIdentified;
  c.outcome = CandidateOutcome::kNotSignificant;
  c.reason = "the marker distance alone does not show it (p = " + FmtP(ratio_p) +
             "), and it is named only with the image's evidence; the velocities were searched "
             "for it in round 1 and are not searched again";
  c.detection_limit = DetectionLimit(x.ws, x.measured, x.series, x.st, x.key, none, z_level,
                                     x.upper, Information(curvature_at_0));
  out.fit = zero.fit;
  out.motion = x.st.motion;
  out.remeasured = zero.remeasured.trials;
  out.ws = std::move(zero.remeasured.ws);
}

/// The statistics of the rate's final fit `fin` against `zero_final` (the current model refitted
/// to the trials as measured): the estimate, its s.e. from the curvature of the joint
/// log-likelihood about the search's best point `best`, the likelihood ratio, AIC and BIC, the
/// identifiability (from the marker series and the velocities' information `info_velocity`) and
/// the Wald check at `z_level`.
void RateStatistics(const RateSearch& x, const Point& fin, const Point& zero_final,
                    const Point& best, double info_velocity, double z_level, CandidateResult& c) {
  constexpr int kSearchPasses = RateSearch::kSearchPasses;
  c.fitted = true;
  c.estimate = fin.rate / kDeg;
  // The s.e. from the curvature of the joint log-likelihood.
  c.se = kNaN;
  if (fin.rate != 0.0) {
    const double h = 0.1 * std::abs(fin.rate);
    // At the same passes as the search, whose best point is the middle one.
    const Point lo = x.Evaluate(fin.rate - h, kSearchPasses),
                hi = x.Evaluate(fin.rate + h, kSearchPasses);
    const double curvature = (hi.loglik - 2 * best.loglik + lo.loglik) / (h * h);
    if (curvature < 0) c.se = 1 / std::sqrt(-curvature) / kDeg;
  }
  c.values = {EffectValue{x.key, "", c.estimate, c.se}};
  c.lr_statistic = std::max(0.0, 2 * (fin.loglik - zero_final.loglik));
  c.p_value = stats::ChiSquaredUpperTail(c.lr_statistic, 1);
  c.delta_aic = -c.lr_statistic + 2;
  int frames = 0, residuals = 0;
  for (const auto& s : x.series) frames += static_cast<int>(s.t_s.size());
  for (const Obs& o : x.ws.obs) residuals += o.Dim();
  c.delta_bic = -c.lr_statistic + std::log(static_cast<double>(frames + residuals));
  c.identifiability = frames == 0 && !(info_velocity > 0) ? Identifiability::kNotTested
                                                          : Identifiability::kIdentified;
  c.wald_clear = c.se > 0 && std::abs(c.estimate) / c.se > z_level;
}

}  // namespace

bool IsRotationRate(const std::string& key) { return Entry(key).rotation_rate; }

RateEvaluation EvaluateRotationRate(const Workspace& ws, const RoundState& st,
                                    const std::string& key,
                                    const std::vector<std::string>& free_current, double level,
                                    const DiscoveryOptions& options) {
  const RateSearch x{ws, st, key, free_current, options};
  constexpr int kSearchPasses = RateSearch::kSearchPasses;
  RateEvaluation out;
  out.c = CandidateOf(key);
  CandidateResult& c = out.c;
  c.form = EffectForm::kShared;
  c.df = 1;
  const bool ratio_blind = x.RatioBlind();
  // Such a rotation is never named (below), so it is measured in the first round only: in a
  // later round every refit carries the added effects, and its search was a third of the time of
  // a study that named the tangential spring (docs/performance.md).
  if (ratio_blind && !st.accepted.empty()) {
    NotMeasuredAgain(c);
    return out;
  }
  // The image's own evidence first: the marker distance alone, at its best rate (its sign is
  // not seen), against none. It needs no fit of the velocities.
  const double from_ratio =
      std::abs(RatioOnlyRate(ws, x.measured, x.series, st, key, x.all, x.upper));
  const double ratio_lr = std::max(0.0, 2 * (x.RatioLoglik(from_ratio) - x.RatioLoglik(0.0)));
  const double ratio_p = stats::ChiSquaredUpperTail(ratio_lr, 1);
  Point zero = x.Evaluate(0.0, kSearchPasses);
  if (!std::isfinite(zero.loglik)) {
    c.fitted = false;
    c.message = "the current model could not be refitted to the trials as measured";
    c.identifiability = Identifiability::kNotTested;
    return out;
  }
  // Named only with the image's own evidence (below), so where the marker distance does not show
  // the rate, a later round does not search the velocities for it again: there every refit
  // carries the added effects, and the search took a fifth of the time of a study that named the
  // tangential spring (docs/performance.md). The probes on either side of 0 still give the
  // velocities' information for the detection limit.
  const double z_level =
      boost::math::quantile(boost::math::complement(boost::math::normal(), level / 2));
  const RatioTerms none = Ratio(ws, x.measured, x.series, st.motion);
  if (!st.accepted.empty() && !(ratio_p < level)) {
    NotSearchedAgain(x, zero, ratio_p, z_level, none, out);
    return out;
  }
  std::map<double, double> velocity;
  const Point best = x.Search(zero, from_ratio, velocity);
  // The velocities' information about the rate at 0 (for the detection limit), from the probes.
  const double info_velocity = Information(
      (velocity[x.probe] - 2 * velocity[0.0] + velocity[-x.probe]) / (x.probe * x.probe));
  // The final fit at the best rate (the noise model to convergence), and at 0 the same way.
  Point zero_final = x.Evaluate(0.0, 8);
  Point with_rate;
  if (best.rate != 0.0) with_rate = x.Evaluate(best.rate, 8);
  Point& fin = std::isfinite(with_rate.loglik) && with_rate.loglik > zero_final.loglik ? with_rate
                                                                                       : zero_final;
  RateStatistics(x, fin, zero_final, best, info_velocity, z_level, c);
  x.HeldOut(none, ratio_blind, c);
  // Named only with the image's own evidence: a bias of the velocities alone is also what a
  // contact effect on v_x and spin does (the scorecard named a roll rate in studies with rolling
  // resistance or tangential compliance hidden before this rule).
  c.significant = c.p_value < level && c.wald_clear && ratio_p < level && HeldOutFell(c);
  ExplainRate(ratio_blind, ratio_p, level, c);
  // The velocities' information from the probes; where the noise model's refits bend the
  // log-likelihood there (it takes up a bias at 0), the observed information at the estimate.
  c.detection_limit = DetectionLimit(ws, x.measured, x.series, st, key, none, z_level, x.upper,
                                     info_velocity > 0 ? info_velocity
                                     : c.se > 0        ? 1 / std::pow(c.se * kDeg, 2)
                                                       : 0.0);
  Finish(x, fin, out);
  return out;
}

}  // namespace hoof::discovery::internal
