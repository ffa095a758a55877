// What a genome must be, whatever it is scored on: free masses and springs or
// muscles only, connected, and within the counts of /limits. The variation
// operators keep every creature they make within these limits; a Problem refuses
// a creature outside them.
#pragma once

#include <optional>
#include <string>

#include "core/model_def.hpp"
#include "evolve/config/run_config.hpp"

namespace sodaevo {

/// Why `creature` is not a valid genome under `limits` (masses only, at least one
/// link, connected, within counts), or nullopt if it is.
std::optional<std::string> check_creature(const soda::ModelDef& creature, const LimitsConfig& limits);

} // namespace sodaevo
