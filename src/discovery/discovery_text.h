#pragma once
/// @file
/// The discovery result and a detection plan as text: what `hoofimpact discover` prints to the
/// terminal (the verdict, a table of candidates per round, the findings), so that any program
/// or test gets the same text without running the command.

#include <ostream>
#include <string>

#include "discovery/discovery.h"

namespace hoof::discovery {

/// A number as the text prints it: `precision` significant digits, "-" where not finite.
std::string Num(double v, int precision = 4);

/// The whole result: a header naming `study` (the study file shown), the verdict, each round's
/// candidates and tests, the findings and what remains. A result that could not run gets one
/// line with its message.
void WriteDiscoveryText(std::ostream& os, const DiscoveryResult& result, const std::string& study);

/// A plan (PlanDetection): the detection limit, the power at its size, the trials needed and
/// the information per trial of each condition.
void WritePlanText(std::ostream& os, const Plan& plan, const std::string& study);

}  // namespace hoof::discovery
