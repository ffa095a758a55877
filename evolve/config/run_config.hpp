// RunConfig: everything that defines an evolution run, read from JSON.
//
// A config file names only what differs from the defaults below; the run folder
// gets the resolved config (every key filled in), which is what `--resume` and
// `replay` read back. Parsing is strict: unknown keys, wrong types and values out
// of range are errors, all collected, each naming the JSON pointer, what was
// expected and what was found. configs/README.md documents every key.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "evolve/algorithms/genetic_settings.hpp"
#include "evolve/algorithms/map_elites_settings.hpp"
#include "evolve/problems/fitness_settings.hpp"

namespace sodaevo {


struct BudgetConfig {
  int generations = 40;              ///< /generations [1, 1e6]
  long long max_evaluations = 0;     ///< /budget/evaluations: stop after this many (0 = no limit)
  double max_wall_seconds = 0.0;     ///< /budget/wall_seconds: stop after this long (0 = no limit)

  bool operator==(const BudgetConfig&) const = default;
};

struct SaveConfig {
  int generation_every = 10;  ///< /save/generation_every: save whole generations every N (0 = only the last), [0, 1e6]
  int checkpoint_every = 1;   ///< /save/checkpoint_every: checkpoint every N generations, [1, 1e6]

  bool operator==(const SaveConfig&) const = default;
};

/// The run's config: the settings of each role (the GA's as its base:
/// algorithms/genetic_settings.hpp; the Problem's and Estimator's /fitness:
/// problems/fitness_settings.hpp; MAP-Elites': algorithms/map_elites_settings.hpp)
/// and the run's own (its name, budget and saving).
struct RunConfig : GeneticSettings {
  std::string name = "run";      ///< /name: [A-Za-z0-9_.-]{1,64}; names the run folder
  BudgetConfig budget;
  FitnessConfig fitness;
  SaveConfig save;
  AlgorithmKind algorithm = AlgorithmKind::Genetic; ///< /algorithm: "ga" | "map-elites"
  MapElitesConfig map_elites;    ///< /map_elites: only with /algorithm "map-elites" (algorithms/map_elites_settings.hpp)

  bool operator==(const RunConfig&) const = default;
};

/// Parses and validates a config. `source` names the file in messages; relative
/// seed-model paths are resolved against `base_dir` (the config's folder).
/// Throws soda::InputError listing every problem, one per line, each as
/// "<source>: <json pointer>: expected <what>, got <value>".
RunConfig parse_run_config(const std::string& json_text, const std::string& source,
                           const std::filesystem::path& base_dir);

/// Reads a config file (errors name the path; JSON syntax errors name line and column).
RunConfig read_run_config(const std::filesystem::path& path);

/// The resolved config: every key with its value (seed-model paths absolute).
/// parse_run_config(to_json(c).dump(), ...) == c.
nlohmann::json to_json(const RunConfig& config);

} // namespace sodaevo
