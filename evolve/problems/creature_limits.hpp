// What a genome must be, whatever it is scored on: free masses and springs or
// muscles only, connected, and within the counts of /limits. The variation
// operators keep every creature they make within these limits; a Problem refuses
// a creature outside them.
#pragma once

#include <optional>
#include <string>

#include "core/model_def.hpp"

namespace sodaevo {

/// /limits: the counts a genome must keep to.
struct LimitsConfig {
  int min_masses = 3;   ///< /limits/min_masses [2, max_masses]
  int max_masses = 40;  ///< /limits/max_masses [min_masses, 10000]
  int max_links = 150;  ///< /limits/max_links [1, 100000]

  bool operator==(const LimitsConfig&) const = default;
};

/// Why `creature` is not a valid genome under `limits` (masses only, at least one
/// link, connected, within counts), or nullopt if it is.
std::optional<std::string> check_creature(const soda::ModelDef& creature, const LimitsConfig& limits);

} // namespace sodaevo
