// Reading the /fitness/race object of a run config (configs/README.md, "Race
// fitness") into RaceFitnessConfig (problems/race_settings.hpp).
//
// A race run scores a creature by racing it, as the original Sodarace racer does
// (core/race_lane.hpp), on one or more terrains: race files named by path (relative
// to the config file) or bundled terrains named as in models/terrains/
// ("TerrainFlat"). The resolved config holds absolute paths. Parsing follows
// run_config.cpp's rules: strict, every problem collected, each naming the JSON
// pointer, what was expected and what was found.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "evolve/algorithms/map_elites_settings.hpp"
#include "evolve/config/strict_json.hpp"
#include "evolve/problems/fitness_kind.hpp"
#include "evolve/problems/race_settings.hpp"

namespace sodaevo {

/// Where a /fitness/race/terrains entry names a file: a path (relative to
/// `base_dir`) if one exists there, else a bundled terrain of that name (".xml"
/// optional) in models/terrains/ beside the config folder or the working directory.
/// Empty when neither exists.
std::filesystem::path find_race_terrain(const std::string& entry, const std::filesystem::path& base_dir);

/// Reads the /fitness/race object `value` over the defaults in `config`; appends
/// every problem (pointers absolute, "/fitness/race/..."). Each terrain is read as
/// a race file, so a bad one is reported with its pointer.
void read_race_fitness(const nlohmann::json& value, const std::filesystem::path& base_dir, RaceFitnessConfig& config,
                       std::vector<ConfigProblem>& problems);

/// What a race config contradicts: no terrains, /fitness/race with a walk, a race
/// with a step other than the original's (the racer runs its own: soda mode, no
/// energy or honesty check), or with MAP-Elites (`map_elites`, null for the GA)
/// placing creatures by a descriptor a race does not measure (race_describes).
std::vector<ConfigProblem> race_fitness_conflicts(FitnessKind kind, const RaceFitnessConfig& race, bool race_given,
                                                  const MapElitesConfig* map_elites, bool soda_mode);

/// The resolved /fitness/race object (every key).
nlohmann::json to_json(const RaceFitnessConfig& config);

} // namespace sodaevo
