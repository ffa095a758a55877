#include "evolve/problems/world_wire.hpp"

#include <algorithm>

namespace sodaevo {

void write_world_and_limits(WireWriter& out, const WorldConfig& world, const LimitsConfig& limits) {
  out.f64(world.gravity);
  out.f64(world.friction);
  out.f64(world.springyness);
  out.f64(world.surface_friction);
  out.f64(world.surface_reflection);
  out.i32(static_cast<int>(world.gravity_direction));
  out.u64(world.evolve.size());
  for (const std::string& name : world.evolve) out.text(name);
  out.i32(limits.min_masses);
  out.i32(limits.max_masses);
  out.i32(limits.max_links);
}

void read_world_and_limits(WireReader& in, const std::string& who, WorldConfig& w, LimitsConfig& l) {
  w.gravity = in.f64();
  w.friction = in.f64();
  w.springyness = in.f64();
  w.surface_friction = in.f64();
  w.surface_reflection = in.f64();
  const int direction = in.i32();
  if (direction < -1 || direction > 1) throw WireError(who + ": bad gravity direction value " + std::to_string(direction));
  w.gravity_direction = static_cast<soda::GravityDirection>(direction);
  const std::uint64_t evolving = in.u64();
  const std::vector<std::string>& names = world_parameter_names();
  if (evolving > names.size()) throw WireError(who + ": bad count of evolving world parameters");
  w.evolve.clear();
  for (std::uint64_t k = 0; k < evolving; ++k) {
    std::string name = in.text();
    if (std::find(names.begin(), names.end(), name) == names.end()) {
      throw WireError(who + ": unknown world parameter '" + name + "'");
    }
    w.evolve.push_back(std::move(name));
  }
  l.min_masses = in.i32();
  l.max_masses = in.i32();
  l.max_links = in.i32();
}

} // namespace sodaevo
