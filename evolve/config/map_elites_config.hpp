// Reading the /map_elites object of a run config (configs/README.md,
// "MAP-Elites") into MapElitesConfig (algorithms/map_elites_settings.hpp).
//
// Parsing follows run_config.cpp's rules: strict, every problem collected, each
// naming the JSON pointer, what was expected and what was found.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "evolve/algorithms/map_elites_settings.hpp"
#include "evolve/config/strict_json.hpp"

namespace sodaevo {

/// Reads the /map_elites object `value` over the defaults in `config`; appends
/// every problem (pointers absolute, "/map_elites/...").
void read_map_elites(const nlohmann::json& value, MapElitesConfig& config, std::vector<ConfigProblem>& problems);

/// The resolved /map_elites object (every key); read_map_elites reads it back to
/// the same config.
nlohmann::json to_json(const MapElitesConfig& config);

} // namespace sodaevo
