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

}  // namespace hoof::discovery
