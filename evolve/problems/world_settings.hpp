// WorldConfig: the /world object of a run config (configs/README.md), the world
// every creature of a run is put in; the Problem applies it, the variation
// operators evolve the parameters /world/evolve names.
#pragma once

#include <string>
#include <vector>

#include "core/enum_names.hpp"
#include "core/model_def.hpp"

namespace sodaevo {

/// The world every creature lives in. Values within the original's ranges.
struct WorldConfig {
  double gravity = 0.38046992;          ///< /world/gravity [0, 4] (Dainty Walker's world)
  double friction = 0.028299415;        ///< /world/friction [0, 1]
  double springyness = 0.5;             ///< /world/springyness [0, 0.5]
  double surface_friction = 0.1;        ///< /world/surface_friction [0, 1]
  double surface_reflection = -0.75;    ///< /world/surface_reflection [-1, 0]
  soda::GravityDirection gravity_direction = soda::GravityDirection::Down; ///< "down"|"up"|"off"
  /// /world/evolve: world parameters each creature may choose for itself (as
  /// Sodarace contenders did), names from {"gravity","friction","springyness",
  /// "surface_friction","surface_reflection"}; empty = the world is fixed.
  std::vector<std::string> evolve;

  bool operator==(const WorldConfig&) const = default;
};

/// The world parameters /world/evolve may name, in canonical order (parsing
/// stores /world/evolve in this order): gravity, friction, springyness,
/// surface_friction, surface_reflection.
inline const std::vector<std::string>& world_parameter_names() {
  static const std::vector<std::string> names = {"gravity", "friction", "springyness", "surface_friction",
                                                 "surface_reflection"};
  return names;
}

/// /world/gravity_direction's spellings.
inline constexpr soda::EnumName<soda::GravityDirection> kGravityDirectionNames[] = {
    {soda::GravityDirection::Down, "down"}, {soda::GravityDirection::Up, "up"}, {soda::GravityDirection::Off, "off"}};
inline std::string gravity_direction_name(soda::GravityDirection d) { return soda::name_of(kGravityDirectionNames, d); }

} // namespace sodaevo
