#include "creature_graph.hpp"

#include <numeric>

namespace sodaevo {

namespace {

int find_root(std::vector<int>& parent, int i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

} // namespace

std::vector<int> connected_components(const soda::ModelDef& c, int* component_count) {
  const int n = static_cast<int>(c.nodes.size());
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  for (const soda::LinkDef& l : c.links) {
    if (l.a < 0 || l.b < 0 || l.a >= n || l.b >= n) continue;
    parent[find_root(parent, l.a)] = find_root(parent, l.b);
  }
  std::vector<int> label(n, -1), component(n);
  int count = 0;
  for (int i = 0; i < n; ++i) {
    const int r = find_root(parent, i);
    if (label[r] < 0) label[r] = count++;
    component[i] = label[r];
  }
  if (component_count) *component_count = count;
  return component;
}

bool is_connected(const soda::ModelDef& c) {
  int count = 0;
  connected_components(c, &count);
  return count <= 1;
}

bool are_linked(const soda::ModelDef& c, int a, int b) {
  for (const soda::LinkDef& l : c.links) {
    if ((l.a == a && l.b == b) || (l.a == b && l.b == a)) return true;
  }
  return false;
}

} // namespace sodaevo
