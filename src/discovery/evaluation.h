#pragma once
/// @file
/// A candidate's evaluation in one round of the discovery workflow (internal to
/// hoof::discovery): candidates.cc evaluates each candidate, round.cc chooses among them and
/// writes the round's decision.
#include <memory>
#include <string>
#include <vector>

#include "discovery/internal.h"

namespace hoof::discovery::internal {

/// One candidate's evaluation: its result row and what adding it would take.
struct Evaluation {
  CandidateResult c;
  Fit fit;
  TiltFit tilt;
  CrossValidation cv;
  std::vector<std::string> free;
  // A rotation rate: the motion with it, the trials re-measured with it, and the contact
  // model's held-out velocities on them.
  pipeline::OutOfPlaneMotion motion;
  std::shared_ptr<const std::vector<pipeline::TrialAnalysis>> remeasured;
  std::shared_ptr<Workspace> remeasured_ws;
  CrossValidation velocity_cv;
  // Another optimum of the candidate's fit that fits nearly as well, in words (empty if none).
  std::string other_optimum;
  // The starts of its profile of sizes, where this round profiled it.
  std::vector<double> profile_starts;
};

/// What every candidate of a round is judged against.
struct RoundContext {
  const Workspace& ws;
  const RoundState& state;
  const std::vector<Eigen::Vector3d>& residual_current;
  const std::vector<Sensitivity>& sens;
  const std::vector<TrialCovariance>& ref;
  const DiscoveryOptions& options;
  std::vector<int> all;
  std::vector<std::string> free_current;  // the contact effects in the current model
  CandidateProbes probes;
  double level = 0.0;  // the naming level
  CrossValidation cv_current, cv_tilt_current;
  int n_ratio = 0;     // trials with a marker distance
  double n_res = 0.0;  // residual components used
  double chi95 = 0.0;  // 95 % point of chi-square with 1 dof
};

/// AIC of a candidate against the current model (< 0 is better).
inline double Aic(const CandidateResult& c) { return -c.lr_statistic + 2 * c.df; }

/// Residual components the workspace's trials use.
int UsedResiduals(const Workspace& ws);

/// A rotation rate (out_of_plane.cc), with the held-out gap of the velocities it would bring.
Evaluation EvaluateRate(const RoundContext& x, const std::string& key);
/// The constant out-of-plane tilt, judged on the marker distance alone.
Evaluation EvaluateTilt(const RoundContext& x, const std::string& key);

/// The candidate `key`, not tested for the reason `why` (OutOfPlaneGap's).
Evaluation NotApplicable(const std::string& key, const std::string& why);
/// A contact effect: probed for identifiability, fitted (shared, then per surface), tested by
/// its likelihood ratio, cross-validated, and checked to stand clear of 0.
Evaluation EvaluateContact(const RoundContext& x, const std::string& key);
/// The outcome and reason of a candidate that is not significant.
void ExplainNotSignificant(const RoundContext& x, CandidateResult& c);

}  // namespace hoof::discovery::internal
