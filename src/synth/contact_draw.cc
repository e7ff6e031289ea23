#include "synth/contact_draw.h"

namespace hoof::synth {
namespace {

/// A normal draw truncated to [lo, hi] by rejection (the bounds lie several s.d. out).
double TruncatedNormal(std::mt19937_64& rng, double mean, double sd, double lo, double hi) {
  std::normal_distribution<double> normal(mean, sd);
  for (int i = 0; i < 1000; ++i) {
    const double x = normal(rng);
    if (x >= lo && x <= hi) return x;
  }
  return std::clamp(mean, lo, hi);
}

}  // namespace

double MeanRestitution(dynamics::Surface surface, const dynamics::SpecimenParameters& specimen) {
  const dynamics::ContactParameters paper = dynamics::PaperContact(surface);
  return dynamics::RestitutionFromDampingRatio(
      dynamics::DampingRatio(paper.k_N_m, paper.b_N_s_m, specimen.mass_kg));
}

ContactDraw DrawContact(const TrialSpec& spec, const dynamics::SpecimenParameters& specimen,
                        std::mt19937_64& rng) {
  const dynamics::ContactParameters paper = dynamics::PaperContact(spec.surface);
  ContactDraw d;
  // A scale of 0 is no scatter: the draws are then taken at the paper's spread, exactly as
  // with scatter off, so that such a trial is the --no-scatter trial byte for byte.
  const bool scatter = spec.scatter_parameters && spec.scatter_scale > 0;
  const double scale = scatter ? spec.scatter_scale : 1.0;
  // Both draws are always taken so that a fixed e does not shift the mu draw and the rest.
  // (The bounds reject more draws at larger scales, and each rejection takes more numbers from
  // `rng`: two trials of one seed at different scales differ in their later draws too.)
  const double e_random = TruncatedNormal(rng, MeanRestitution(spec.surface, specimen),
                                          scale * RestitutionSpread(spec.surface),
                                          kMinDrawnRestitution, kMaxDrawnRestitution);
  const double mu_random = TruncatedNormal(rng, paper.mu, scale * kFrictionSpread, 0.0, 5.0);
  d.contact = paper;
  if (spec.e) {
    d.e_drawn = *spec.e;
  } else if (scatter) {
    d.e_drawn = e_random;
  } else {
    d.e_drawn = MeanRestitution(spec.surface, specimen);
  }
  d.contact.mu = spec.mu ? *spec.mu : (scatter ? mu_random : paper.mu);
  if (!spec.e && !scatter) {
    d.zeta = dynamics::DampingRatio(paper.k_N_m, paper.b_N_s_m, specimen.mass_kg);
  } else {
    d.zeta = dynamics::DampingRatioFromRestitution(d.e_drawn);
    d.contact.b_N_s_m = dynamics::DampingForRatio(d.zeta, paper.k_N_m, specimen.mass_kg);
  }
  d.contact.extensions = spec.hidden.contact;
  return d;
}

}  // namespace hoof::synth
