#pragma once
/// @file
/// The parts of the discovery workflow (docs/discovery.md), shared by its translation units and
/// not part of the public API:
///  - library.cc: the candidate library, enum names, option checks;
///  - workspace.cc: the measured trials as the workflow uses them, and the simulator calls;
///  - noise.cc: the noise model (per-trial coefficient scatter plus measurement error) and its
///    maximum-likelihood estimate;
///  - fit.cc: a model fitted with Ceres under the noise model;
///  - structure.cc: the residuals' trends against the noise model (descriptive tests);
///  - cross_validation.cc: held-out errors;
///  - out_of_plane.cc: a rotation out of the plane that grows in time, with re-measured trials;
///  - candidates.cc: one candidate of a round fitted, tested and judged (evaluation.h);
///  - round.cc: one round: every candidate evaluated, the strongest significant one added;
///  - multiplicity.cc: the naming level, calibrated for how the candidates' tests overlap;
///  - plan.cc: detection limits and how many trials would detect an effect;
///  - verdict.cc: findings and the verdict in words;
///  - discovery.cc: the rounds.

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <boost/container/static_vector.hpp>

#include "core/frames.h"
#include "discovery/discovery.h"
#include "dynamics/impact_simulator.h"
#include "pipeline/out_of_plane.h"
#include "pipeline/trial_analysis.h"

namespace hoof::discovery::internal {

using core::kNaN;
inline constexpr int kComponents = 3;  // v_x, v_y, w d
inline constexpr const char* kComponentName[kComponents] = {"v_x", "v_y", "w"};

const LibraryEntry& Entry(const std::string& key);
/// A candidate's result row with its library entry's names filled in (detection limit NaN).
CandidateResult CandidateOf(const std::string& key);
/// Sets the extension of `key` to `value` (its own units).
void Apply(const std::string& key, double value, dynamics::ContactExtensions& x);

std::string Fmt(double v, int precision = 3);
std::string FmtP(double p);
/// "a", "a and b", "a, b and c".
std::string JoinedWords(const std::vector<std::string>& words);
/// " unit", or nothing for a dimensionless "1".
std::string UnitSuffix(const std::string& unit);

/// A measured trial as the workflow uses it.
struct Obs {
  const pipeline::TrialAnalysis* trial = nullptr;
  std::size_t trial_index = 0;  // in the trials the workspace was built from
  int surface = 0;
  double angle_deg = 0.0, speed_m_s = 0.0;
  bool normal = false;
  int cell = 0, fold = 0;
  dynamics::SpecimenParameters specimen;
  dynamics::ImpactConditions conditions;
  double t_touch_s = 0.0, impact_time_s = 0.0, phi = 0.0;
  Eigen::Vector3d measured{0, 0, 0};  // v_x, v_y, w d after impact, in S
  /// Variance of the random measurement error of each component (the per-trial fits' s.e.,
  /// after and before the impact), as fractions of the impact speed squared.
  Eigen::Vector3d measurement_var{0, 0, 0};
  double scale = 1.0;  // impact speed |v_SC before|
  std::array<bool, kComponents> used{false, false, false};
  double marker_ratio = kNaN;        // mean over the flight windows
  double marker_ratio_slope = kNaN;  // per second, over the flight windows
  int Dim() const { return used[0] + used[1] + used[2]; }
};

/// A contact effect in a model: one value for all surfaces, or one per surface.
struct EffectParam {
  EffectForm form = EffectForm::kShared;
  std::vector<double> value;  // size 1 (shared) or one per surface; own units
  double At(int surface) const {
    return form == EffectForm::kShared ? value.at(0) : value.at(static_cast<std::size_t>(surface));
  }
};

/// Parameter values of a model.
struct Model {
  std::vector<double> zeta, mu;                // per surface
  std::map<std::string, EffectParam> effects;  // contact effects
};

/// The noise model: per surface the trial-to-trial s.d. of zeta and mu, and the systematic
/// measurement s.d. (fraction of the impact speed) beyond each trial's own s.e., per surface for
/// v_x and w d_EC and shared by the surfaces for v_y.
struct Noise {
  std::vector<double> zeta_sd, mu_sd;
  /// Per surface: a model misfit that one surface's trials share (a stick/slip kink the
  /// linearisation cannot follow) stays with that surface instead of blinding the others. The
  /// v_y component is one for all surfaces (EstimateNoise keeps it so).
  std::vector<Eigen::Vector3d> systematic_sd;
};

/// Per trial: the derivatives of the prediction (fractions of the impact speed) by zeta and mu.
using Sensitivity = Eigen::Matrix<double, kComponents, 2>;

class Workspace {
 public:
  std::vector<Obs> obs;
  std::vector<std::string> surfaces;
  std::vector<double> k;                     // per surface (the paper's; not identified)
  std::vector<bool> has_oblique;             // per surface
  std::vector<double> zeta_start, mu_start;  // the comparison's per-surface fit
  /// Per surface: the largest |mu_eff| measured on its oblique trials (0 without): a contact
  /// that sticks in all of them holds for any mu above it.
  std::vector<double> mu_eff_max;
  double rtol = 1e-8;
  double measurement_floor = 1e-4;
  int threads = 2;
  mutable std::atomic<long long> simulations{0};
  /// The workspace whose `simulations` counts this one's, where it is a copy made for a
  /// simulated study (WithMeasured); null for a workspace of measured trials.
  const Workspace* counted_in = nullptr;

  dynamics::ContactExtensions Extensions(const Model& m, int surface) const;
  /// v_x, v_y and w d after the impact at the measured impact time, in S.
  Eigen::Vector3d Predict(const Obs& o, double zeta, double mu,
                          const dynamics::ContactExtensions& x, bool* ok) const;
  /// Residuals (measured - model) / impact speed of the obs `which`; unused components are NaN,
  /// a failed simulation gives 1 (a large misfit rather than a gap).
  std::vector<Eigen::Vector3d> Residuals(const Model& m, const std::vector<int>& which) const;
  /// d prediction / d (zeta, mu) of the obs `which` at `m` (central differences).
  std::vector<Sensitivity> Sensitivities(const Model& m, const std::vector<int>& which) const;
  void ParallelFor(std::size_t n, const std::function<void(std::size_t)>& f) const;
  std::vector<int> All() const;
};

/// Builds the workspace from the measured trials.
void Build(const std::vector<pipeline::TrialAnalysis>& trials, const DiscoveryOptions& options,
           int* skipped, Workspace& ws);

// ---- noise (noise.cc) ---------------------------------------------------------------------

/// The covariance of one trial's used residual components under `noise`, and the matrix W with
/// W^T W = covariance^-1 (whitening), both of the trial's dimension.
/// Matrices and vectors of at most one row per residual component, held inline: a trial's
/// covariance is formed in every evaluation of a likelihood, and these never allocate.
using SmallMatrix =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kComponents, kComponents>;
using SmallVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kComponents, 1>;
/// The indices of a trial's used residual components (0 v_x, 1 v_y, 2 w d), in order.
using ComponentList = boost::container::static_vector<int, kComponents>;
struct TrialCovariance {
  SmallMatrix cov, whiten;
  ComponentList components;
  double log_det = 0.0;
};
TrialCovariance Covariance(const Workspace& ws, const Obs& o, const Sensitivity& s,
                           const Noise& noise);
/// Covariance() of every obs of `ws`, with `sens` its sensitivities (one per obs).
std::vector<TrialCovariance> Covariances(const Workspace& ws, const std::vector<Sensitivity>& sens,
                                         const Noise& noise);
/// -1/2 sum over trials of (log det V + r^T V^-1 r), constants dropped.
double LogLikelihood(const Workspace& ws, const std::vector<int>& which,
                     const std::vector<Eigen::Vector3d>& r, const std::vector<Sensitivity>& s,
                     const Noise& noise);
/// The noise model of largest likelihood for these residuals (coordinate-wise Brent searches
/// on the log s.d.s), starting from `start`.
Noise EstimateNoise(const Workspace& ws, const std::vector<int>& which,
                    const std::vector<Eigen::Vector3d>& r, const std::vector<Sensitivity>& s,
                    const Noise& start);
Noise InitialNoise(const Workspace& ws);

// ---- fits (fit.cc) ------------------------------------------------------------------------

struct Fit {
  Model model;
  Noise noise;
  double loglik = 0.0;
  std::map<std::string, std::vector<double>> effect_se;  // like EffectParam::value
  std::vector<double> zeta_se, mu_se;
  int parameters = 0;  // fitted mean parameters (zeta, mu, effects)
  bool ok = true;
  std::string message;
};

/// Fits the per-surface zeta and mu and the `free_effects` (others fixed at their values in
/// `start`; each free effect in the form `start` gives it) to the obs `which`. With
/// `estimate_noise`, the noise model is re-estimated before and after each Ceres solve, for up
/// to `passes` solves until the likelihood stops rising (it is then the profile likelihood);
/// otherwise it stays `noise` and one solve is made. A pass that lowers the likelihood is
/// halved toward its start (up to four times), and kept back at its start where no part of it
/// gains: with `estimate_noise` a fit never ends below its start.
Fit FitModel(const Workspace& ws, const std::vector<int>& which, const Model& start,
             const std::vector<std::string>& free_effects, const Noise& noise, bool estimate_noise,
             int passes = 8);
/// The baseline as every workflow fits it: zeta and mu per surface from the comparison's
/// per-surface fit (Workspace::zeta_start, mu_start), the noise model from InitialNoise, to
/// convergence (12 passes), on every obs.
Fit FitBaseline(const Workspace& ws);

/// The out-of-plane (measurement) model: the marker distance ratio is cos(tilt) in every trial.
struct TiltFit {
  double tilt_rad = 0.0, tilt_se_rad = kNaN;
  double sigma = 1.0, loglik = 0.0;
};
TiltFit FitTilt(const Workspace& ws, const std::vector<int>& which, bool free);

/// Upper tail of the chi-bar-square of `df` independent parameters at their lower bound:
/// sum over k of C(df, k) 2^-df P(chi2_k > x).
double ChiBarSquareUpperTail(double x, int df);

// ---- structure (structure.cc) -------------------------------------------------------------

std::vector<StructureTest> StructureTests(const Workspace& ws,
                                          const std::vector<Eigen::Vector3d>& r,
                                          const std::vector<Sensitivity>& s, const Noise& noise,
                                          double tilt_rad, const DiscoveryOptions& options);

// ---- cross-validation (cross_validation.cc) ------------------------------------------------

struct CrossValidation {
  std::vector<double> error;              // per obs (held out), kHeldOutErrorUnit
  std::vector<Eigen::Vector3d> residual;  // per obs (held out)
  double mean_error = 0.0;
  // Per obs (held out), kHeldOutDensityUnit, under the model's own noise model (AddDensity);
  // empty until then.
  std::vector<double> density;
  double mean_density = kNaN;
};
/// Each fold's trials predicted by `start` refitted (noise held at the full-data fit's) without
/// them; errors in units of the variance `reference` predicts for each trial.
CrossValidation CrossValidate(const Workspace& ws, const Fit& start,
                              const std::vector<std::string>& free_effects,
                              const std::vector<TrialCovariance>& reference, int folds);
/// Sets `cv.density`: each held-out residual's negative log density under `own`, the
/// covariances the model's own noise model predicts (1/2 (log det V + r^T V^-1 r), constants
/// dropped), and its mean.
void AddDensity(CrossValidation& cv, const std::vector<TrialCovariance>& own);
CrossValidation CrossValidateTilt(const Workspace& ws, bool free, int folds);
/// One-sided paired t test that `b` has lower errors than `a`.
double PairedImprovementP(const std::vector<double>& a, const std::vector<double>& b);
double Rms(const Eigen::Vector3d& r);

// ---- a round (candidates.cc, round.cc) ---------------------------------------------------

/// What one round works from: the current model and what was added.
struct RoundState {
  Fit current;
  std::vector<std::string> accepted;  // contact effects and measurement effects
  bool tilt_on = false;
  TiltFit tilt;
  /// The trials as measured, and the out-of-plane motion added so far: the workspace's trials
  /// are these re-measured with it.
  const std::vector<pipeline::TrialAnalysis>* measured = nullptr;
  pipeline::OutOfPlaneMotion motion;
  /// Per effect with a profile of sizes (LibraryEntry::profile_sizes): the sizes its fit starts
  /// from, found by the first round that profiled it. The optima lie where the effect's own
  /// phase puts them; later rounds start from them without profiling again.
  std::map<std::string, std::vector<double>> profile_starts;
};

/// Evaluates every candidate against `state`, ranks them and decides; fills `round` (tests
/// excepted) and, when one was added, returns what the next state needs.
struct RoundOutcome {
  bool added = false;
  std::string key;
  std::vector<std::string> alike;  // look-alikes of the added effect
  Fit fit;                         // the model with it (contact effect)
  TiltFit tilt;                    // the tilt (measurement effect)
  /// A rotation rate: the motion with it, and the trials re-measured with that motion.
  pipeline::OutOfPlaneMotion motion;
  std::shared_ptr<const std::vector<pipeline::TrialAnalysis>> remeasured;
  std::shared_ptr<Workspace> ws;  // built from `remeasured`, for the rounds after
  std::map<std::string, std::vector<double>> profile_starts;  // profiled in this round
};
/// `residual_current` and `sens` are the current model's residuals and sensitivities of all obs.
RoundOutcome RunCandidates(const Workspace& ws, const RoundState& state,
                           const std::vector<Eigen::Vector3d>& residual_current,
                           const std::vector<Sensitivity>& sens,
                           const std::vector<std::string>& keys, const DiscoveryOptions& options,
                           const std::function<void(const std::string&)>& say, Round& round);

/// A contact candidate of `rd` that an earlier round found significant by its likelihood ratio
/// (p below that round's naming level) is not "not tested by these data" or "confounded" in a
/// later round: the data did test it. Its fit gaining nothing there says that an effect added
/// since (`added`, library keys) takes up what it explained: its outcome becomes "not
/// significant", its identifiability "identified", and its reason says so with the earlier p.
void KeepEarlierEvidence(const std::vector<Round>& earlier, const std::vector<std::string>& added,
                         Round& rd);
/// The first candidate `key` of the rounds before round `before` (Round::index) that was fitted
/// and whose likelihood-ratio p was below its round's naming level, with that round's index in
/// `round`; nullptr when there is none.
const CandidateResult* EarlierSignificance(const std::vector<Round>& rounds, int before,
                                           const std::string& key, int* round = nullptr);

/// One contact candidate judged against `current` as a round judges it (its fits, likelihood
/// ratio, held-out error and the estimate's distance from 0), at the naming level `level`, alone:
/// no other candidate competes. `significant` says whether the round would call it so.
CandidateResult JudgeCandidate(const Workspace& ws, const Fit& current, const std::string& key,
                               const DiscoveryOptions& options, double level);

// ---- out-of-plane rotation growing in time (out_of_plane.cc) ---------------------------------

/// True for a library key whose entry is a rotation rate (LibraryEntry::rotation_rate).
bool IsRotationRate(const std::string& key);

/// A rotation rate's evaluation against the current model: the rate (rad/s) of largest joint
/// likelihood of the marker distance (per frame, each trial's own scale free) and of the
/// velocities re-measured with it (the current contact model and noise refitted), its s.e., the
/// likelihood ratio against no rate, held-out errors of the marker distance, and what adding it
/// would take.
struct RateEvaluation {
  CandidateResult c;
  Fit fit;
  pipeline::OutOfPlaneMotion motion;
  std::shared_ptr<const std::vector<pipeline::TrialAnalysis>> remeasured;
  std::shared_ptr<Workspace> ws;  // built from `remeasured`
};
RateEvaluation EvaluateRotationRate(const Workspace& ws, const RoundState& state,
                                    const std::string& key,
                                    const std::vector<std::string>& free_current, double level,
                                    const DiscoveryOptions& options);

// ---- detection limits and plans (plan.cc) ---------------------------------------------------

/// The noise model's whitened design: every obs's used components as rows (whitened by `ref`),
/// d prediction / d (zeta, mu) of each surface as columns, and where each obs's rows start (one
/// entry more than obs).
struct WhitenedDesign {
  Eigen::MatrixXd X;
  std::vector<Eigen::Index> first;
};
WhitenedDesign Whiten(const Workspace& ws, const std::vector<Sensitivity>& sens,
                      const std::vector<TrialCovariance>& ref);
/// Projects zeta and mu per surface out of whitened vectors (or of each column of a matrix):
/// d - Q Q^T d, Q an orthonormal basis of the design's columns.
class ProfileOut {
 public:
  explicit ProfileOut(const WhitenedDesign& w);
  template <typename Derived>
  Eigen::MatrixXd operator()(const Eigen::MatrixBase<Derived>& d) const {
    return d - q_ * (q_.transpose() * d);
  }

 private:
  Eigen::MatrixXd q_;
};
/// A residual change per obs (NaN counts as 0), whitened into the design's rows.
Eigen::VectorXd WhitenChange(const Workspace& ws, const std::vector<Eigen::Vector3d>& d_r,
                             const std::vector<TrialCovariance>& ref, const WhitenedDesign& w);
/// Per trial: the Fisher information about an effect (1 / unit^2) left after zeta and mu per
/// surface are profiled out, from `d_r`, the residual changes of one unit of the effect, `sens`,
/// the derivatives by zeta and mu, and `ref`, the noise model's whitening. Their sum is the
/// study's.
std::vector<double> ProfiledInformation(const Workspace& ws,
                                        const std::vector<Eigen::Vector3d>& d_r,
                                        const std::vector<Sensitivity>& sens,
                                        const std::vector<TrialCovariance>& ref);
/// The smallest size that a one-sided test at `level` detects with 80 % power (Wald).
double DetectionLimit(const std::vector<double>& information, double level);

/// A contact effect at a ladder of sizes, log-spaced from LibraryEntry::smallest (or 1e-3 of
/// the probe when that is 0) to LibraryEntry::upper at LibraryEntry::ladder_per_decade, with the
/// other parameters at the current model's values: what the effect changes at each size, in the
/// whitened residuals with zeta and mu per surface projected out (the Wald approximation in
/// zeta and mu only; the effect itself is simulated at each size, not linearised).
struct SizeLadder {
  std::vector<double> size;                          ///< ascending
  std::vector<std::vector<Eigen::Vector3d>> change;  ///< r_current - r(size), per obs
  std::vector<Eigen::VectorXd> projected;            ///< `change` whitened, zeta and mu out
  Eigen::VectorXd current;                           ///< r_current whitened, zeta and mu out
  double smallest = 0.0;                             ///< LibraryEntry::smallest
};
SizeLadder Ladder(const Workspace& ws, const Model& current, const std::string& key,
                  const std::vector<Eigen::Vector3d>& r_current,
                  const std::vector<Sensitivity>& sens, const std::vector<TrialCovariance>& ref);
/// The ladder's local maxima of the profiled gain in log-likelihood over the current model, the
/// `most` largest first; only sizes that gain. Where the candidate's fit starts: an effect whose
/// change swings in sign has several optima, as far apart as one swing.
std::vector<double> LadderStarts(const SizeLadder& ladder, std::size_t most);
/// The smallest size from which on every size of the ladder is detected with 80 % power by a
/// one-sided test at `level` (noncentrality of the simulated change, zeta and mu profiled out);
/// NaN when the largest size is not. An effect whose change grows with its size gives the Wald
/// limit of DetectionLimit; one whose change swings in sign gives the size above which it never
/// falls below detection.
double LadderDetectionLimit(const SizeLadder& ladder, double level);
/// The detection limit as LadderDetectionLimit gives it, with the noncentrality of each size
/// from the study's expected data (ExpectedNoncentrality: zeta, mu and the current model's
/// effects `free_current` refitted nonlinearly) instead of the tangent plane: the first size of
/// the ladder detected with 80 % power, found by bisection from the tangent plane's bracket, and
/// refined between it and the size below by two steps of regula falsi in log size. NaN when the
/// largest size is not detected.
double ExpectedDetectionLimit(const Workspace& ws, const Fit& current,
                              const std::vector<std::string>& free_current, const std::string& key,
                              const SizeLadder& ladder, double level);
/// A direction of a candidate's change that its secant (the change per unit at the probe size)
/// does not describe, and the stretch of it that the ladder's sizes reach: the change at the
/// sizes nearest to it, as multiples `low` to `high` of `change`'s own length along it (zeta and
/// mu projected out). A fit that searches the sizes tries every point of that stretch.
struct LadderRay {
  std::vector<Eigen::Vector3d> change;  ///< the representative size's change, per obs
  double low = 0.0, high = 0.0;
};
/// The ladder's rays: directions taken greedily, each whose cosine with the secant `d_r` and with
/// every direction taken before is below `cos_max`; every size not described by the secant
/// belongs to the ray it is closest to. Empty for an effect whose change only grows.
std::vector<LadderRay> LadderRays(const Workspace& ws, const SizeLadder& ladder,
                                  const std::vector<Eigen::Vector3d>& d_r,
                                  const std::vector<Sensitivity>& sens,
                                  const std::vector<TrialCovariance>& ref, double cos_max = 0.99);

// ---- the naming level (multiplicity.cc) -----------------------------------------------------

struct NamingLevel {
  double level = 0.0;       // per hypothesis: min-P, never below Bonferroni
  double bonferroni = 0.0;  // alpha / tests (the hypotheses and their rays)
  int hypotheses = 0;       // forms of the candidates with information, plus the independent ones
  int draws = 0;            // Monte Carlo draws (0: Bonferroni was used)
};
/// The level at which the smallest p of a round's hypotheses falls below it with probability
/// `alpha` under the current model: each candidate of `changes` (its residual change per unit,
/// per obs) tried shared and, with `per_surface` and two or more surfaces, per surface, plus
/// `independent` hypotheses tested on other data (the marker distance). By `draws` seeded Monte
/// Carlo draws of the scores' joint normal distribution under the linearised noise model.
/// `rays`, empty or one list per candidate of `changes`: further directions of its change at
/// other sizes (LadderRays); its shared form's likelihood ratio is then the largest over the
/// secant (any multiple) and the stretches of these rays, as a fit that searches the sizes can
/// find any of them.
NamingLevel CalibrateNamingLevel(const Workspace& ws,
                                 const std::vector<std::vector<Eigen::Vector3d>>& changes,
                                 const std::vector<Sensitivity>& sens,
                                 const std::vector<TrialCovariance>& ref, bool per_surface,
                                 int independent, double alpha, int draws = 20000,
                                 const std::vector<std::vector<LadderRay>>& rays = {});

// ---- the candidates probed against the current model (plan.cc) -----------------------------

/// Every contact candidate of `keys` against the current model, without refitting: its
/// residuals at the probe size, the change per unit of the effect from there (a secant), and its
/// ladder of sizes; and the naming level they set together (CalibrateNamingLevel, with the
/// ladders' rays, and the measurement effects as independent tests when at least 3 trials have
/// a marker distance). What a round of Discover and PlanDetection both start from.
struct CandidateProbes {
  std::map<std::string, std::vector<Eigen::Vector3d>> residual_probe, change;
  std::map<std::string, SizeLadder> ladder;
  NamingLevel naming;
};
CandidateProbes ProbeCandidates(const Workspace& ws, const Model& current,
                                const std::vector<std::string>& keys,
                                const std::vector<Eigen::Vector3d>& residual_current,
                                const std::vector<Sensitivity>& sens,
                                const std::vector<TrialCovariance>& ref,
                                const DiscoveryOptions& options);

// ---- the parametric bootstrap of a plan (bootstrap.cc) ----------------------------------------

/// Per surface, the largest |mu_eff| of the oblique obs of `ws` from their velocities in S (the
/// change of the centre's velocity from first touch to `measured`, tangential over normal): the
/// Workspace::mu_eff_max of a workspace whose velocities were simulated rather than measured.
std::vector<double> MuEffMax(const Workspace& ws);

/// Velocities of every obs simulated from `truth` (its model with its effects, and its noise
/// model): each trial's e (then its zeta, through the two-phase law) and mu drawn about its
/// surface's with the noise model's scatter (the s.d. of zeta turned into one of e by the law's
/// slope: in e the velocities are linear, so the noise model is exact there to first order), its
/// velocities with the measurement's random and systematic error. Seeded: the same seed gives
/// the same values, whatever the threads.
std::vector<Eigen::Vector3d> SimulateStudy(const Workspace& ws, const Fit& truth,
                                           std::uint64_t seed);
/// The noncentrality of the likelihood ratio for `key` at `size` against `current` (its model,
/// with the contact effects `free_current`, and its noise model held), from the study's expected
/// data: every obs's velocities simulated with the effect at `size` and no scatter or error, the
/// current model refitted to them (zeta, mu and `free_current`, nonlinearly), and twice the
/// log-likelihood it falls short of the truth's. Where zeta and mu take up an effect only as
/// they change by a finite amount, this is what the tangent-plane noncentrality of
/// LadderDetectionLimit misses. NaN where the simulator fails on a trial under both models.
double ExpectedNoncentrality(const Workspace& ws, const Fit& current,
                             const std::vector<std::string>& free_current, const std::string& key,
                             double size, int passes = 8);
struct BootstrapResult {
  int draws = 0, detected = 0;
  int lr_significant = 0;         // draws whose likelihood ratio alone is below the level
  std::vector<double> estimates;  // per draw, the candidate's estimate
};
/// `draws` studies simulated from `baseline` with `key` at `size`; on each, the baseline is
/// refitted and the candidate judged alone (JudgeCandidate) at `level`.
BootstrapResult BootstrapDetection(const Workspace& ws, const Fit& baseline, const std::string& key,
                                   double size, double level, const DiscoveryOptions& options,
                                   int draws, const std::function<void(const std::string&)>& say);

// ---- verdict (verdict.cc) -----------------------------------------------------------------

std::vector<SurfaceFit> SurfaceFits(const Workspace& ws, const Fit& f);
std::vector<EffectValue> EffectValues(const Workspace& ws, const Fit& f, const std::string& key);
/// The verdict in words, from the filled result.
std::string VerdictText(const DiscoveryResult& out, const DiscoveryOptions& options, int skipped);

/// A paragraph for the verdict on the trials of unknown mass (a ball without a specimen,
/// simulated at compare::kReferenceMass_kg), or "" when every mass is known.
std::string MassNote(const Workspace& ws);

/// Why the out-of-plane candidates cannot be judged on the workspace's trials, or "" when they
/// can: they read the projected distance of a body's markers, which a ball (whose rotation is
/// not seen) and an unmarked outline do not have.
std::string OutOfPlaneGap(const Workspace& ws);

/// Whether a candidate's message is one of OutOfPlaneGap's.
bool IsOutOfPlaneGap(const std::string& message);

}  // namespace hoof::discovery::internal
