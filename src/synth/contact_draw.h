#pragma once
/// @file
/// Per-trial contact coefficients: e and mu drawn around the surface's mean with the paper's
/// spread (SCIENCE.md section 4), turned into the two-phase law's (k, b, mu).

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

/// Range of the e draw. The two-phase law with damping in compression only and zeta < 1 cannot
/// give e below exp(-1) = 0.368 (the closed form's limit as zeta -> 1), and
/// DampingRatioFromRestitution has no root there, so draws are truncated at 0.38. This cuts
/// asphalt's N(0.498, 0.071) 1.67 s.d. below its mean: its drawn mean is 0.506 and its s.d.
/// 0.064 (truncated-normal moments); steel and concrete are unaffected.
inline constexpr double kMinDrawnRestitution = 0.38;
inline constexpr double kMaxDrawnRestitution = 0.99;

/// Draws e ~ N(MeanRestitution, RestitutionSpread) truncated to [kMinDrawnRestitution,
/// kMaxDrawnRestitution] by rejection and
/// mu ~ N(PaperContact(surface).mu, kFrictionSpread) truncated to >= 0, in that order from
/// `rng`, unless `spec` fixes them or turns scatter off. k is the paper's, b = 2 zeta sqrt(k m)
/// with zeta = DampingRatioFromRestitution(e). The hidden contact extensions are copied in.
ContactDraw DrawContact(const TrialSpec& spec, const dynamics::SpecimenParameters& specimen,
                        std::mt19937_64& rng);

}  // namespace hoof::synth
