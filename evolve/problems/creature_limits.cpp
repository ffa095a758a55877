#include "creature_limits.hpp"

#include "evolve/problems/creature_graph.hpp"

namespace sodaevo {

std::optional<std::string> check_creature(const soda::ModelDef& c, const LimitsConfig& limits) {
  const int masses = static_cast<int>(c.nodes.size());
  if (masses < limits.min_masses) {
    return "has " + std::to_string(masses) + " masses, fewer than limits.min_masses " + std::to_string(limits.min_masses);
  }
  if (masses > limits.max_masses) {
    return "has " + std::to_string(masses) + " masses, more than limits.max_masses " + std::to_string(limits.max_masses);
  }
  if (static_cast<int>(c.links.size()) > limits.max_links) {
    return "has " + std::to_string(c.links.size()) + " links, more than limits.max_links " + std::to_string(limits.max_links);
  }
  if (c.links.empty()) return "has no links";
  for (const soda::NodeDef& n : c.nodes) {
    if (n.fixed) return "has a fixed node ('" + n.id + "'); creatures are free masses only";
  }
  for (const soda::LinkDef& l : c.links) {
    if (l.kind == soda::LinkKind::FixedBar) return "has a fixed bar; creatures have springs and muscles only";
    if (l.a < 0 || l.b < 0 || l.a >= masses || l.b >= masses || l.a == l.b) return "has a link with bad ends";
  }
  if (!is_connected(c)) return "is not connected (some masses are not linked to the rest)";
  return std::nullopt;
}

} // namespace sodaevo
