#pragma once
/// @file
/// Per-trial contact coefficients: e and mu drawn around the surface's mean with the paper's
/// spread (docs/synthetic-trials.md, "What is drawn"), turned into the two-phase law's
/// (k, b, mu).

#include <algorithm>
#include <random>

#include "dynamics/parameters.h"
#include "synth/options.h"

namespace hoof::synth {

/// The coefficients a trial is simulated with, and where they came from.
struct ContactDraw {
  double e_drawn = 0.0;  ///< Normal restitution without gravity that sets zeta; in (0, 1).
  double zeta = 0.0;     ///< Damping ratio b / (2 sqrt(k m)).
  dynamics::ContactParameters contact;  ///< k from the paper, b from zeta, mu, extensions.
};

/// Mean of the e draw for a surface: the closed-form e of the paper's (k, b)
/// (0.8502, 0.7089, 0.4984 for steel, concrete, asphalt).
double MeanRestitution(dynamics::Surface surface, const dynamics::SpecimenParameters& specimen);

/// Range of the e draw. Every e in (0, 1] has a damping ratio (zeta > 1 below exp(-1), see
/// dynamics::RestitutionOfTwoPhaseLaw); the bounds only keep draws physical. The upper one is
/// 3.4 s.d. above steel's mean and moves its drawn mean and s.d. by about 1e-4; the lower one
/// is more than 6 s.d. below every mean.
inline constexpr double kMinDrawnRestitution = 0.05;
inline constexpr double kMaxDrawnRestitution = 0.99;

/// Draws e ~ N(MeanRestitution, s RestitutionSpread) truncated to [kMinDrawnRestitution,
/// kMaxDrawnRestitution] by rejection and
/// mu ~ N(PaperContact(surface).mu, s kFrictionSpread) truncated to >= 0, in that order from
/// `rng`, with s = spec.scatter_scale, unless `spec` fixes them or turns scatter off (s = 0
/// turns it off too). The bounds are the same at every scale, so above 1 they cut the draws
/// more: steel's e (mean 0.85, at most 0.99) keeps 96 % of the scaled s.d. at s = 1.5, 91 % at
/// 2 and 77 % at 4, and its mean falls (0.842 at 2). k is the paper's, b = 2 zeta sqrt(k m) with
/// zeta = DampingRatioFromRestitution(e). The hidden contact extensions are copied in.
ContactDraw DrawContact(const TrialSpec& spec, const dynamics::SpecimenParameters& specimen,
                        std::mt19937_64& rng);

}  // namespace hoof::synth
