#pragma once
/// @file
/// The one specimen type: the rigid body's mass, inertia and contact geometry, shared by the
/// simulator (dynamics), the impact measurement (kinematics), the trial files (pipeline) and the
/// renderer (synth).

namespace hoof::core {

/// Rigid hoof-wall specimen (paper section 2.1). The paper gives m and R; d and I_C are
/// derived (docs/science.md, "Specimen defaults"): d is the centre of the 45 mm bar minus R, and
/// I_C = m (L^2 + W^2) / 12 for the 45 x 16 mm bar.
struct SpecimenParameters {
  double mass_kg = 0.008;            ///< m, in kg; > 0.
  double inertia_kg_m2 = 1.5207e-6;  ///< I_C about the centre of mass C, out of plane; > 0.
  double end_radius_m = 0.009;       ///< R, radius of the round end centred at E; > 0.
  double d_EC_m = 0.0135;            ///< d = |EC|, from the end centre E to C; >= 0.

  /// Throws std::invalid_argument naming the first invalid field and its value
  /// ("specimen.mass_kg = 0 is invalid: must be > 0").
  void Validate() const;
};

}  // namespace hoof::core
