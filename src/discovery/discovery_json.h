#pragma once
/// @file
/// The discovery result as JSON (what `hoofimpact discover --json` prints, without the
/// command's own fields: the study file, the options and the figures written).

#include <nlohmann/json.hpp>

#include "discovery/discovery.h"

namespace hoof::discovery {

/// Every field of `result`: the fits, the rounds and their candidates and tests, the findings,
/// the residuals and the verdict. Numbers that are not finite are null.
nlohmann::json DiscoveryJson(const DiscoveryResult& result);

/// A plan (PlanDetection) as `hoofimpact discover --plan --json` prints it; numbers that are
/// not finite are null.
nlohmann::json PlanJson(const Plan& plan);

}  // namespace hoof::discovery
