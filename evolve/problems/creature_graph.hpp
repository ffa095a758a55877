// Graph questions about a creature: which masses are linked, is it in one piece.
#pragma once

#include <vector>

#include "core/model_def.hpp"

namespace sodaevo {

/// Component index of every node (links of any kind join nodes).
std::vector<int> connected_components(const soda::ModelDef& creature, int* component_count = nullptr);

/// True if every node is reachable from every other through links.
bool is_connected(const soda::ModelDef& creature);

/// True if some link joins a and b (either way round).
bool are_linked(const soda::ModelDef& creature, int a, int b);

} // namespace sodaevo
