#include "model_def.hpp"

#include <cmath>

namespace soda {

ModelDef canonical_form(const ModelDef& def) {
  ModelDef out = def;
  out.nodes.clear();
  out.links.clear();
  std::vector<int> new_index(def.nodes.size(), -1);
  for (bool fixed_pass : {true, false}) {
    for (std::size_t i = 0; i < def.nodes.size(); ++i) {
      if (def.nodes[i].fixed != fixed_pass) continue;
      NodeDef node = def.nodes[i];
      int index = static_cast<int>(out.nodes.size());
      node.id = node.fixed ? "n" : "m";
      node.id += std::to_string(index);
      new_index[i] = index;
      out.nodes.push_back(std::move(node));
    }
  }
  for (LinkKind kind : {LinkKind::Spring, LinkKind::Muscle, LinkKind::FixedBar}) {
    for (const LinkDef& link : def.links) {
      if (link.kind != kind) continue;
      LinkDef copy = link;
      copy.a = new_index.at(static_cast<std::size_t>(link.a));
      copy.b = new_index.at(static_cast<std::size_t>(link.b));
      out.links.push_back(copy);
    }
  }
  return out;
}

} // namespace soda
