#pragma once
/// @file
/// Discovery (docs/discovery.md): find where the baseline model and the measurements disagree,
/// name the missing physical effect with evidence, add it to the model and show the gap shrink
/// on trials the fit never saw.
///
/// The workflow (its parts are listed in discovery/internal.h):
///  1. Fit the current model (per surface zeta and mu, plus the effects added so far) to every
///     measured trial under a noise model: each trial's zeta and mu scatter about their
///     surface's, and each measured velocity has its own error. The residuals after the impact
///     are v_SC.x, v_SC.y (which carries e) and w d_EC, as fractions of the impact speed, and
///     per frame the marker distance ratio (image-level evidence of out-of-plane rotation).
///  2. Describe the residuals against the noise model: levels and trends with speed and angle,
///     the marker distance ratio, and a lack-of-fit test where conditions were repeated (Holm).
///     These describe; they do not decide what is named.
///  3. Fit every candidate of the library (Library()) jointly with the per-surface parameters and
///     the noise model, shared by all surfaces and per surface; test it by its likelihood ratio
///     against the current model, cross-validate it on held-out trials, probe what it is
///     confounded with, and give its detection limit.
///  4. Add the strongest significant candidate (p below the naming level, Round::naming_level; its
///     estimate clear of 0 by its s.e., a lower held-out score: HeldOutFell; after an added
///     effect, significantly lower), with its outcome and reason for every other one; repeat
///     until nothing is significant.
///  5. The verdict: an effect is *named* when, with it in the model, no significant structure
///     remains; otherwise it is *tentative* and the disagreement *unexplained*. Candidates that
///     fit as well as the added one are reported as indistinguishable, with the measurement that
///     would separate them.

#include <array>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/frames.h"
#include "dynamics/impact_simulator.h"
#include "pipeline/trial_analysis.h"

namespace hoof::discovery {

/// One effect of the candidate library (docs/science.md, "Effects the model lacks"): a nested
/// extension whose parameter gives back the baseline at 0.
struct LibraryEntry {
  std::string key;        ///< "hunt_crossley", "hertz_stiffness", "plastic_unloading",
                          ///< "static_friction", "tangential_compliance", "rolling_resistance",
                          ///< "out_of_plane", "out_of_plane_rate", "out_of_plane_roll_rate"
  std::string name;       ///< in words
  std::string parameter;  ///< symbol
  std::string unit;       ///< of the parameter
  double probe = 0.0;     ///< a realistic size, used to probe identifiability and to scale the fit
  double upper = 0.0;     ///< largest value the fit may take
  bool measurement_effect = false;     ///< changes what the camera sees, not the impact
  std::string signature;               ///< what it changes, in words
  std::string separating_measurement;  ///< what would tell it from its look-alikes
  /// Smallest value the fit may take other than 0 (the baseline, which the current model is).
  /// A tangential spring far stiffer than the normal one makes the contact's equations stiff
  /// and the explicit integrator slow.
  double smallest = 0.0;
  /// Sizes per decade of the ladder on which a contact effect's fit starts and its detection
  /// limit is found (docs/discovery.md, "A ladder of sizes"). An effect whose change swings in
  /// sign from one size to the next needs a fine ladder for the fit to start near its optimum.
  double ladder_per_decade = 8.0;
  /// Its change depends on mu even where every trial sticks at the baseline's mu (a tangential
  /// spring slips where the rigid contact sticks). Where all of a surface's trials stick, the
  /// baseline's mu is not identified and may sit at any value above the stick limit (often the
  /// fit's bound, 2), from which no fit moves it (the gradient by mu is 0): such an effect's fit
  /// also starts with mu lowered to 1.5 x the largest mu_eff measured on the surface
  /// (docs/discovery.md, "Fits").
  bool friction_limited = false;
  /// Starts of its fit where no size of the ladder gains: log-spaced from the ladder's lowest
  /// size to a tenth of the probe (one start, a tenth of the probe, when 1). The ladder is linear
  /// in zeta and mu; a tangential spring gains only once a surface's mu moves far (from the
  /// bound where its trials all stick, say), and its optima lie one per swing of its change, so
  /// its ladder can show no gain where a fit from the right size finds one (docs/discovery.md,
  /// "Fits").
  int starts_without_gain = 1;
  /// Sizes of a profile from whose best two local maxima its fit also starts (0: none): the
  /// effect held at each size while zeta, mu and the noise model are refitted (one solve), the
  /// sizes spaced evenly in size^-1/2 from `smallest` to a tenth of the probe. The spring's
  /// change swings in sign at a phase that turns with sqrt(k_t / k), and once zeta and mu move its
  /// likelihood has optima a few per cent of the size wide that the ladder, linear in zeta and
  /// mu, misses (docs/discovery.md, "A profile of sizes").
  int profile_sizes = 0;
  /// A measurement effect that grows through the clip: the trials are re-measured with it
  /// (a tilt or roll rate, docs/discovery.md "Out-of-plane rotation that grows").
  bool rotation_rate = false;
  /// The contact extension it sets (a key of dynamics::ContactExtensionFields()); empty for a
  /// measurement effect.
  std::string extension;
};

/// The library, in a fixed order.
const std::vector<LibraryEntry>& Library();

/// True when `value` of the library effect `key` lies on the largest value the fit may take
/// (LibraryEntry::upper): the data may call for more than the library allows, and the estimate's
/// s.e. describes the curvature there, not an interval around an optimum.
bool AtUpperBound(const std::string& key, double value);
/// " (the library's upper bound)" when AtUpperBound, else nothing.
std::string UpperBoundNote(const std::string& key, double value);

/// Settings of the workflow.
struct DiscoveryOptions {
  /// Family-wise significance level: of the structure tests (Holm) and of naming a candidate
  /// (min-P over the candidates and their forms, Round::naming_level); in (0, 0.5).
  double alpha = 0.01;
  int folds = 3;       ///< Leave-trials-out folds (trials dealt round-robin in design order); >= 2.
  int max_rounds = 3;  ///< Effects added at most; >= 1.
  int jobs = 0;        ///< Threads (0 = all cores).
  /// Library keys to try (Library()); empty = all.
  std::vector<std::string> candidates;
  /// Let a contact effect take its own value on each surface, besides one value shared by all
  /// surfaces; which of the two the data support is decided by a likelihood-ratio test.
  bool per_surface = true;
  double relative_tolerance = 1e-8;  ///< Of the simulator during fits; in (0, 1e-4].
  /// Smallest departure of the projected / layout marker distance from the model's that
  /// counts as a disagreement: the scale calibration and the centre finding hold the ratio to
  /// about 1e-4 (docs/tracking.md), so 1e-3 (a tilt of 2.6 deg) is well clear of them. The
  /// marker tests are tests of a departure larger than this; in [0, 0.1).
  double marker_ratio_tolerance = 1e-3;
  /// Lower bound of the error per velocity component that the noise model adds to each trial's
  /// own s.e., as a fraction of the impact speed (it is estimated, and kept from falling below
  /// this). The tracker's systematic errors on rendered frames are about 1e-4 of the impact
  /// speed (docs/tracking.md), but the noise model is linear in the scatter of zeta and mu: a
  /// scatter of e of 0.04-0.07 bends the predictions off its tangent plane by about 1e-3, and
  /// with a smaller floor that curvature is taken for physics (docs/discovery.md); in [0, 0.1).
  double measurement_floor = 1e-3;
  /// Where conditions were repeated (replicate cells), the lack-of-fit test compares the cell
  /// means of the residuals with the scatter within cells, free of the noise model. It counts
  /// only the part of a cell mean beyond this (a fraction of the impact speed): the tracker's
  /// systematic errors, of order 1e-4 and different from cell to cell (docs/tracking.md), are
  /// not physics; in [0, 0.1).
  double replicate_tolerance = 5e-4;
  /// The options the trials were measured with: a trial re-measured with a fitted out-of-plane
  /// motion is measured with them again (studyfile::ReadKinematicsOptions).
  kinematics::KinematicsOptions kinematics;

  /// Throws std::invalid_argument naming the field.
  void Validate() const;
};

/// One test of the residuals for structure, against the noise model.
struct StructureTest {
  std::string quantity;   ///< "v_x", "v_y", "w" (residuals after impact) or "marker_ratio"
  std::string scope;      ///< surface name, or "all"
  std::string covariate;  ///< "speed", "angle", "level", "time in the trial", "cells (speed)"
  std::string test;       ///< "slope z", "mean z", "mean t", "lack-of-fit F"
  double statistic = 0.0;
  double df1 = 0.0, df2 = 0.0;  ///< degrees of freedom (df1 only for t; none for z)
  double p = 1.0;               ///< unadjusted
  double p_holm = 1.0;          ///< Holm-adjusted over every test of the round
  bool significant = false;     ///< p_holm < alpha
  std::string description;      ///< in words, e.g. "v_y residual falls 0.4 % per m/s"
};

/// Whether the data can tell a candidate from the baseline's own parameters.
enum class Identifiability {
  kIdentified,  ///< the data tell it apart: its size is estimated
  kNotTested,   ///< no trial is sensitive to it at a realistic size
  kConfounded,  ///< at a realistic size, refitting zeta or mu takes its change back
};

/// Why a candidate was or was not added in a round.
enum class CandidateOutcome {
  kAdded,              ///< the strongest significant candidate: added to the model
  kIndistinguishable,  ///< significant, but fits as well as the one added
  kWeakerThanAdded,    ///< significant, but the one added explains clearly more
  kNotSignificant,     ///< its likelihood ratio is not significant at the naming level
                       ///< (Round::naming_level)
  kWorseHeldOut,       ///< significant in the fit, but it does not predict held-out trials better
  kBelowResolution,    ///< significant, but smaller than the measurement resolves (out-of-plane
                       ///< tilt within DiscoveryOptions::marker_ratio_tolerance)
  kAtSmallestValue,    ///< its likelihood ratio is significant, but its estimate does not stand
                       ///< clear of LibraryEntry::smallest (where that is above 0)
  kRestsOnOneTrial,    ///< significant, but not without the trial that gains most from it
                       ///< (CandidateResult::influential_trial)
  kNotTested,   ///< see Identifiability::kNotTested; also a rotation rate the marker layout cannot
                ///< see
  kConfounded,  ///< see Identifiability::kConfounded
  kNotFitted,   ///< the fit failed (message)
};

/// A contact effect's value: shared by all surfaces, or one per surface.
enum class EffectForm { kShared, kPerSurface };

/// Status of a finding in the verdict.
enum class FindingStatus {
  kNamed,              ///< added, its evidence holds, and no significant structure remains
  kTentative,          ///< added, but a significant structure remains that no effect explains
  kIndistinguishable,  ///< fits as well as an added effect, or cannot be told from zeta or mu
};

const char* ToString(Identifiability v);
const char* ToString(CandidateOutcome v);
const char* ToString(EffectForm v);
const char* ToString(FindingStatus v);

/// How the held-out gap changed, from the fraction by which it shrank (RoundResult::gap_shrink):
/// "12.5 % smaller", "2.35 % larger" (an effect can lower the held-out error, which weighs each
/// residual by its predicted variance, and still widen the unweighted gap, which the per-trial
/// scatter dominates), "unchanged" below 0.05 %, "n/a" when not finite.
std::string GapChangeText(double gap_shrink);
/// Every candidate outcome, in the enum's order (for the tables' choices and the text's widths).
const std::array<CandidateOutcome, 11>& AllCandidateOutcomes();
/// The inverses (for the study file); throw std::invalid_argument naming the text.
Identifiability IdentifiabilityFromString(const std::string& s);
CandidateOutcome CandidateOutcomeFromString(const std::string& s);
EffectForm EffectFormFromString(const std::string& s);
FindingStatus FindingStatusFromString(const std::string& s);

/// The unit of the held-out error: the mean over held-out trials of the squared residuals,
/// each divided by the variance the current model's noise model predicts for it (per-trial
/// coefficient scatter plus measurement error), averaged over the trial's components. A model
/// that predicts as well as its noise model says gives about 1.
inline constexpr const char* kHeldOutErrorUnit = "mean squared residual / predicted variance";

/// The unit of the held-out density: the mean over held-out trials of the negative log density
/// of each trial's residuals under the model's *own* noise model, 1/2 (log det V + r^T V^-1 r)
/// with V that model's predicted covariance (velocities in m/s) and the constant dropped.
/// Lower is better; only differences between models mean anything. A contact effect is judged
/// by it: an effect that explains part of the trial-to-trial scatter shrinks its own noise
/// model, which the error in the current model's units cannot credit.
inline constexpr const char* kHeldOutDensityUnit =
    "nats per held-out trial (-log predictive density, constant dropped)";

/// One value of an effect: for all surfaces (surface empty) or for one.
struct EffectValue {
  std::string key;
  std::string surface;           ///< empty: shared by all surfaces
  double value = 0.0, se = 0.0;  ///< in the library entry's unit
};

/// How a candidate did in one round.
struct CandidateResult {
  std::string key;                  ///< library key, e.g. "hunt_crossley"
  std::string name;                 ///< e.g. "velocity-dependent (Hunt-Crossley) damping"
  std::string parameter;            ///< e.g. "c"
  std::string unit;                 ///< e.g. "N s/m^2"
  bool measurement_effect = false;  ///< out-of-plane rotation: changes the image, not the physics
  bool fitted = false;              ///< the fit ran
  std::string message;              ///< why not, or empty
  EffectForm form = EffectForm::kShared;  ///< the form the data chose
  /// The shared value, or for a per-surface effect the largest of the surface values (its
  /// values are in `values`); NaN when undefined.
  double estimate = 0.0, se = 0.0;
  std::vector<EffectValue> values;  ///< every value of the chosen form
  /// Likelihood-ratio test against the current model under the noise model (boundary-corrected
  /// chi-bar-square with df parameters at their lower bound 0).
  double lr_statistic = 0.0;
  int df = 1;
  double p_value = 1.0;
  /// Per-surface against shared: the larger of the likelihood-ratio p and the p of a Wald test
  /// that the per-surface values are equal (each chi-square with surfaces - 1 dof).
  double p_per_surface = 1.0;
  double delta_aic = 0.0, delta_bic = 0.0;  ///< this model minus the current (< 0 is better)
  /// Held-out error (kHeldOutErrorUnit) for this model and for the current model, each fitted
  /// without the trial's fold.
  double cv_error = 0.0, cv_error_current = 0.0;
  /// Held-out density (kHeldOutDensityUnit) for this model and for the current model, each
  /// under its own noise model: what a contact effect is judged by. NaN for an out-of-plane
  /// candidate, which is judged by its held-out error on the image.
  double cv_density = core::kNaN, cv_density_current = core::kNaN;
  /// Paired one-sided t test that the held-out score the candidate is judged by fell (the
  /// density for a contact effect, the error otherwise).
  double cv_p = 1.0;
  Identifiability identifiability = Identifiability::kIdentified;
  /// Baseline parameters that absorbed it in the identifiability probe, e.g. "a changed zeta".
  std::string confounded_with;
  /// The estimate stands clear of 0 (of LibraryEntry::smallest, where that is above 0) by its
  /// standard error (one-sided Wald at the naming level; any surface's value for a per-surface
  /// effect).
  bool wald_clear = false;
  /// The trial whose likelihood gains most from the effect (a contact effect whose evidence
  /// holds otherwise; empty when not checked), and the likelihood-ratio p of the effect with both
  /// models refitted without that trial (NaN when not checked).
  std::string influential_trial;
  double p_without_influential = core::kNaN;
  /// p_value < the naming level (Round::naming_level), wald_clear, and the held-out score fell
  /// (HeldOutFell); for a contact effect in a round after an effect was added, also cv_p < 0.05;
  /// for a contact effect, also p_without_influential below kWithoutInfluentialLevel where
  /// checked.
  bool significant = false;
  CandidateOutcome outcome = CandidateOutcome::kNotSignificant;
  std::string reason;  ///< why it was or was not added, in words
  /// Smallest size (the library entry's unit) that these trials, with this noise, detect at
  /// the naming level with 80 % power, from the study's expected data with the effect at the
  /// ladder's sizes (shared form; docs/discovery.md "Candidates and the decision", item 6; NaN
  /// when the ladder's largest size is not detected or the limit was not computed).
  double detection_limit = 0.0;
  int rank = 0;  ///< 1 = added or strongest evidence
};

/// Whether the candidate is judged by its held-out density (a contact effect: cv_density is
/// finite) rather than its held-out error.
bool JudgedOnDensity(const CandidateResult& c);
/// The held-out score the candidate is judged by fell below the current model's.
bool HeldOutFell(const CandidateResult& c);

/// In a round after an effect was added, a contact candidate must also predict the held-out
/// trials significantly better: cv_p (paired one-sided t of the held-out densities) below this
/// level. Its likelihood ratio is then taken against a model whose added effect was fitted
/// through the trials' scatter, and there it was seen to be far from its nominal level: on the
/// unreplicated scorecard, 5 of the 8 wrong names that the density alone let through were a
/// second effect named beside the hidden one (docs/discovery.md, "The held-out rule").
inline constexpr double kLaterRoundHeldOutLevel = 0.05;
/// A contact candidate's evidence must also hold without the trial that gains most from it:
/// its likelihood-ratio p with both models refitted without that trial
/// (CandidateResult::p_without_influential) below this level. It confirms one candidate already
/// chosen at the naming level rather than searching among them, so it is not divided among the
/// hypotheses: the default family-wise alpha. At the naming level instead it refused 4 of 20 true
/// springs on the unreplicated scorecard design, two of them with p 6.4e-4 and 0.0033 without
/// the trial; every wrong or false name it refused had p = 1 (docs/discovery.md, "One trial is
/// no effect").
inline constexpr double kWithoutInfluentialLevel = 0.01;
/// Whether a contact candidate's evidence names it: fitted, its likelihood-ratio p below the
/// round's naming level, its estimate clear of 0 (wald_clear), its held-out score lower
/// (HeldOutFell), and in a round after an effect was added (`later_round`), significantly lower
/// (cv_p < kLaterRoundHeldOutLevel), and where it was checked, its p without its most
/// influential trial below kWithoutInfluentialLevel (CandidateResult::p_without_influential).
bool ContactEvidenceHolds(const CandidateResult& c, double naming_level, bool later_round);
/// That score for this model and for the current model, as text: the density to 3 decimals (its
/// values sit far from 0 and only their difference matters), the error to 3 significant digits;
/// "n/a" where not finite.
std::array<std::string, 2> HeldOutScores(const CandidateResult& c);
/// That score before and after, with its unit: "held-out -log density -12.301 -> -12.725 (nats
/// per held-out trial ...)" or "held-out error 1.21 -> 0.95 (mean squared residual / ...)".
std::string HeldOutText(const CandidateResult& c);

/// One held-out trial's disagreement before and after an effect is added.
struct GapTrial {
  std::string id, surface;
  double angle_deg = 0.0, speed_m_s = 0.0;
  int fold = 0;
  /// Residuals after impact (fractions of the impact speed): before (current model) and after
  /// (with the effect), each fitted without this trial's fold.
  Eigen::Vector3d residual_before{0, 0, 0}, residual_after{0, 0, 0};  ///< v_x, v_y, w d
  double gap_before = 0.0, gap_after = 0.0;  ///< root mean square of the used components
};

/// One round of the workflow.
struct Round {
  int index = 1;
  std::vector<StructureTest> tests;         ///< on the current model's residuals
  std::vector<CandidateResult> candidates;  ///< in rank order
  /// The naming level of this round's candidates: the per-hypothesis level at which the
  /// smallest p of all `hypotheses` (candidates x forms) falls below it with probability alpha
  /// under the current model (min-P, by Monte Carlo under the linearised noise model), and
  /// Bonferroni's alpha / tests, which it never falls below (the tests are the hypotheses and
  /// the further directions of the changes that a search over the sizes tries, LadderRays).
  double naming_level = 0.0, bonferroni_level = 0.0;
  int hypotheses = 0;
  std::string accepted;       ///< key of the effect added in this round, empty when none
  std::string decision;       ///< in words
  std::vector<GapTrial> gap;  ///< held-out trials, when an effect was added
  /// Aggregate held-out gap (root mean square over trials and components, fractions of the
  /// impact speed) and its shrink.
  double gap_before = 0.0, gap_after = 0.0, gap_shrink = 0.0;
};

/// The model per surface (the fitted parameters; k is not identified and stays the paper's),
/// and its noise: the trial-to-trial scatter of the contact coefficients.
struct SurfaceFit {
  std::string surface;
  double zeta = 0.0, zeta_se = 0.0;
  double mu = 0.0, mu_se = 0.0;
  double k_N_m = 0.0;
  int trials = 0;
  double zeta_sd = 0.0;  ///< s.d. of zeta from trial to trial
  double mu_sd = 0.0;    ///< s.d. of mu from trial to trial (NaN without oblique trials)
  /// The noise model's systematic measurement s.d. of v_x, v_y and w d_EC on this surface beyond
  /// each trial's own s.e. (fraction of the impact speed; NaN for a component its trials do not
  /// use, and in study files written before it was per surface).
  Eigen::Vector3d measurement_sd = Eigen::Vector3d::Constant(core::kNaN);
};

/// What the verdict says about one effect.
struct Finding {
  std::string key, name, parameter, unit;
  FindingStatus status = FindingStatus::kNamed;
  EffectForm form = EffectForm::kShared;
  /// Surfaces it was found on: empty for a shared effect.
  std::vector<std::string> surfaces;
  double estimate = 0.0, se = 0.0;  ///< shared value, or the largest surface value
  std::vector<EffectValue> values;
  std::string partner;                 ///< what it cannot be told apart from
  std::string separating_measurement;  ///< what would separate them
  double gap_shrink = 0.0;             ///< held-out, when it was added
};

/// One trial's residuals under the baseline and the final model (full-data fits).
struct TrialResiduals {
  std::string id, surface;
  double angle_deg = 0.0, speed_m_s = 0.0;
  Eigen::Vector3d baseline{0, 0, 0}, final_model{0, 0, 0};  ///< v_x, v_y, w d (fractions)
  double marker_ratio = 0.0;  ///< mean projected / layout marker distance after impact
};

/// One trial against the baseline model on the scale of its prediction interval
/// (docs/discovery.md, "Prediction intervals"). Components v_x, v_y, w d_EC after the impact,
/// in S, as fractions of the impact speed; NaN for a component the trial does not use.
struct TrialPrediction {
  std::string id, surface;
  double angle_deg = 0.0, speed_m_s = 0.0;
  Eigen::Vector3d residual = Eigen::Vector3d::Constant(core::kNaN);  ///< measured - predicted
  /// The s.d. of a new trial's residual: under the noise model refitted without the trial, its
  /// own measurement error, the trial-to-trial scatter of its surface's zeta and mu carried
  /// through the model and the systematic measurement error (the diagonal of the covariance
  /// discovery uses); and the error of the fitted zeta and mu.
  Eigen::Vector3d prediction_sd = Eigen::Vector3d::Constant(core::kNaN);
  Eigen::Vector3d t = Eigen::Vector3d::Constant(core::kNaN);  ///< residual / prediction_sd
  /// Degrees of freedom of t: the surface's other trials less its mean parameters (zeta, and mu
  /// where the surface has oblique trials).
  int dof = 0;
  /// The standard normal z with the two-sided tail probability of t on `dof` (NormalEquivalent):
  /// |z| > 3 has probability 0.27 % under the model, as for a known variance.
  Eigen::Vector3d z = Eigen::Vector3d::Constant(core::kNaN);
};

/// The standard normal z whose two-sided tail probability equals that of `t` under Student's t
/// on `dof` degrees of freedom, with t's sign; NaN when t is not finite or dof < 1.
double NormalEquivalent(double t, int dof);

/// Every measured trial's prediction z under the baseline model and its noise model, fitted to
/// all the trials as discovery fits its baseline (the same fit: the Discovery section's tests
/// and these z use one noise model).
struct BaselinePredictions {
  bool success = false;
  std::string message;     ///< why there are none
  int trials_skipped = 0;  ///< not measured, or on a surface without normal trials
  std::vector<SurfaceFit> surfaces;
  std::vector<TrialPrediction> trials;
};

/// Fits the baseline model and its noise model to `trials` (FitBaseline of the discovery
/// workflow, with `options`' simulator tolerance, measurement floor and jobs) and returns each
/// trial's prediction z. Needs at least 6 trials with a fitted surface model (else success =
/// false with the reason). Throws std::invalid_argument for options out of range.
BaselinePredictions PredictBaseline(const std::vector<pipeline::TrialAnalysis>& trials,
                                    const DiscoveryOptions& options = {});

/// Everything the workflow found.
struct DiscoveryResult {
  bool success = false;
  std::string message;  ///< why it could not run
  int trials_used = 0;
  int trials_skipped = 0;  ///< not measured, or on a surface without normal trials (no zeta)
  std::vector<SurfaceFit> baseline, final_model;
  /// Systematic measurement error per component (v_x, v_y, w d; fractions of the impact speed)
  /// of the final noise model: the largest over the surfaces (each surface's is its
  /// SurfaceFit::measurement_sd).
  Eigen::Vector3d measurement_sd{0, 0, 0};
  std::vector<EffectValue> effects;  ///< the final model's effects
  std::vector<Round> rounds;
  std::vector<Finding> findings;
  /// A significant disagreement that the final model leaves.
  bool unexplained = false;
  std::vector<StructureTest> remaining;  ///< the significant tests the final model leaves
  std::vector<TrialResiduals> residuals;
  std::string verdict;  ///< plain language, several paragraphs
  double seconds = 0.0;
  long long simulations = 0;
};

/// Runs the workflow on the measured trials of a study (failed trials are skipped).
/// `progress`, when set, gets lines of progress in words. Throws std::invalid_argument for bad
/// options; a study that cannot be analysed (too few trials) comes back with success false.
DiscoveryResult Discover(const std::vector<pipeline::TrialAnalysis>& trials,
                         const DiscoveryOptions& options = {},
                         const std::function<void(const std::string&)>& progress = {});

/// How many trials, and where, a study would need to detect an effect of a given size: the
/// answer to "what could these trials have found, and what would find it".
struct PlanCondition {
  std::string surface;
  double angle_deg = 0.0;
  double speed_low_m_s = 0.0, speed_high_m_s = 0.0;  ///< range of the impact speeds measured
  int trials = 0;
  /// Fisher information about the effect per trial of this condition (zeta and mu per surface
  /// profiled out, 1 / unit^2), and this condition's share of the study's.
  double information_per_trial = 0.0, share = 0.0;
};

struct Plan {
  bool success = false;
  std::string message;  ///< why it could not run
  std::string key, name, parameter, unit;
  double size = 0.0;   ///< the size asked about
  int trials = 0;      ///< trials of the study
  double level = 0.0;  ///< the naming level of the first round (Round::naming_level)
  /// The smallest size this study detects with 80 % power, and its power at `size`, both from
  /// the noncentrality of the study's expected data (the effect simulated without scatter or
  /// error, zeta and mu refitted to it).
  double detection_limit = 0.0, power = 0.0;
  /// Trials of this study's design (its conditions in the same proportions) for 80 % power at
  /// `size`.
  double trials_needed = 0.0;
  std::vector<PlanCondition> conditions;  ///< most informative first
  /// The parametric bootstrap (when asked for): studies of these trials simulated from the
  /// fitted baseline with the effect at `size`, each trial's e and mu drawn from the noise
  /// model's scatter, and in how many the candidate, judged alone at `level` as a round judges
  /// it, was significant; that rate with its Wilson 95 % interval (NaN without draws); and in
  /// how many its likelihood ratio alone was below `level` (the test whose power `power` is).
  int bootstrap_draws = 0, bootstrap_detected = 0, bootstrap_lr_significant = 0;
  double bootstrap_power = 0.0, bootstrap_low = 0.0, bootstrap_high = 0.0;
};

/// The plan for `key` at `size` (its library unit) under the baseline fitted to `trials` with its
/// noise model: the naming level and the detection limit as the first round of Discover sets
/// them (the ladder of sizes, CandidateResult::detection_limit), and the power at `size` from the
/// study's expected data with the effect at that size (zeta and mu refitted). Throws
/// std::invalid_argument for a
/// bad key, size or options.
/// With `bootstrap_draws` > 0, also the parametric bootstrap (Plan::bootstrap_power), each draw
/// reported through `progress`.
Plan PlanDetection(const std::vector<pipeline::TrialAnalysis>& trials, const std::string& key,
                   double size, const DiscoveryOptions& options = {}, int bootstrap_draws = 0,
                   const std::function<void(const std::string&)>& progress = {});

}  // namespace hoof::discovery
