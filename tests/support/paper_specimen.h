#pragma once
/// @file
/// The paper's specimen as a study's specimen record (docs/science.md, "Specimen defaults"), for
/// tests that build trials by hand.

#include "pipeline/study_format.h"

namespace hoof::testing {

inline pipeline::SpecimenSpec PaperSpecimenSpec() {
  pipeline::SpecimenSpec s;
  s.mass_kg = 0.008;
  s.inertia_kg_m2 = 1.5207e-6;
  s.end_radius_m = 0.009;
  s.d_EC_m = 0.0135;
  s.markers_B_m = {{"M1", {0.006, 0.0}}, {"M2", {0.024, 0.0}}};
  return s;
}

}  // namespace hoof::testing
