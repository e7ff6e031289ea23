#include "core/specimen.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string_view>

namespace hoof::core {
namespace {

[[noreturn]] void ThrowField(std::string_view field, double value, std::string_view requirement) {
  std::ostringstream os;
  os << "specimen." << field << " = " << value << " is invalid: " << requirement;
  throw std::invalid_argument(os.str());
}

}  // namespace

void SpecimenParameters::Validate() const {
  const std::pair<std::string_view, double> fields[] = {{"mass_kg", mass_kg},
                                                        {"inertia_kg_m2", inertia_kg_m2},
                                                        {"end_radius_m", end_radius_m},
                                                        {"d_EC_m", d_EC_m}};
  for (const auto& [field, value] : fields)
    if (!std::isfinite(value)) ThrowField(field, value, "must be a finite number");
  if (mass_kg <= 0) ThrowField("mass_kg", mass_kg, "must be > 0");
  if (inertia_kg_m2 <= 0) ThrowField("inertia_kg_m2", inertia_kg_m2, "must be > 0");
  if (end_radius_m <= 0) ThrowField("end_radius_m", end_radius_m, "must be > 0");
  if (d_EC_m < 0) ThrowField("d_EC_m", d_EC_m, "must be >= 0");
}

}  // namespace hoof::core
