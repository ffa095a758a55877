// The world and the limits of a problem in the wire format (wire_format.hpp): the
// part every Problem kind shares (walk_problem.hpp, race_problem.hpp).
#pragma once

#include <string>

#include "evolve/problems/creature_limits.hpp"
#include "evolve/problems/wire_format.hpp"
#include "evolve/problems/world_settings.hpp"

namespace sodaevo {

void write_world_and_limits(WireWriter& out, const WorldConfig& world, const LimitsConfig& limits);
/// What write_world_and_limits wrote; `who` names the problem in WireError messages.
void read_world_and_limits(WireReader& in, const std::string& who, WorldConfig& world, LimitsConfig& limits);

} // namespace sodaevo
