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

#include "core/model_def.hpp"
#include "core/stepping.hpp"
#include "evolve/config/map_elites_config.hpp"
#include "evolve/config/race_fitness_config.hpp"

namespace sodaevo {

enum class WalkDirection { Right, Left, Either };
enum class FitnessScaling { None, Sodarace };
/// What counts as diverged (core/divergence.hpp): only non-finite numbers, or also
/// runaway energy beyond what the muscles can supply.
enum class DivergenceCheck { Finite, Energy };
/// The statistic of a creature's replicas that is its fitness
/// (evolve/estimators/replica_estimator.hpp): their mean, their median, or the lower end of
/// the 95 % confidence interval of their mean.
enum class EstimateStatistic { Mean, Median, LowerBound };

/// How a creature is scored: the distance walked by the centroid, or a race
/// (configs/README.md, /fitness).
struct FitnessConfig {
  FitnessKind kind = FitnessKind::Walk; ///< /fitness/kind: "walk" | "race"
  RaceFitnessConfig race;               ///< /fitness/race: only with kind "race"
  long long frames = 2000;        ///< /fitness/frames: scored frames, [1, 1e7]
  long long settle_frames = 200;  ///< /fitness/settle_frames: unscored frames first, [0, 1e7]
  WalkDirection direction = WalkDirection::Right; ///< /fitness/direction: "right" | "left" | "either"
  /// /fitness/scaling: "sodarace" scales the creature as the Sodarace racer did
  /// (configs/README.md, /fitness/scaling: s = 211/sqrt(sum Lmax^2), positions, rest lengths,
  /// velocities and gravity times s) so that growing is no way to win; "none" leaves it.
  FitnessScaling scaling = FitnessScaling::Sodarace;
  double drop_height = 5.0;       ///< /fitness/drop_height: lowest mass placed this high, px, [0, 1000]
  /// /fitness/mode, /fitness/integrator, /fitness/substeps: how the physics is
  /// stepped (core/stepping.hpp); default the original's one update per frame.
  soda::PhysicsMode mode = soda::PhysicsMode::Soda;
  soda::Integrator integrator = soda::Integrator::Euler;
  int substeps = 1;               ///< [1, 4096], continuous mode only
  DivergenceCheck divergence = DivergenceCheck::Finite; ///< /fitness/divergence: "finite" | "energy"
  /// /fitness/honesty/max_change: flag (as diverged) a creature whose distance
  /// changes by more than this share when re-evaluated with
  /// /fitness/honesty/substeps_factor times the sub-steps (evolve/problems/honesty.hpp);
  /// 0 = no check. [0, 1e6]
  double honesty_max_change = 0.0;
  int honesty_substeps_factor = 4; ///< /fitness/honesty/substeps_factor [2, 64]
  /// /fitness/replicas: rollouts per new creature, replica 0 exact and the others
  /// with their own sine jitter (core/sine_jitter.hpp), [1, 256].
  int replicas = 8;
  /// /fitness/replicas_max: the creatures that survive a generation (the elites)
  /// gather /fitness/replicas more each generation up to this many,
  /// [replicas, 1024].
  int replicas_max = 32;
  /// /fitness/confirm: when the run ends, its best this many creatures are
  /// estimated again on replicas_max replicas each (ranked again until the best
  /// this many all are), so that what the run hands over is not its luckiest
  /// draws (evolve/evaluators/evaluator.hpp, confirm_best). 0 = off. [0, 100000]
  int confirm = 10;
  EstimateStatistic statistic = EstimateStatistic::Mean; ///< /fitness/statistic: "mean" | "median" | "lcb"
  double jitter = 0.002; ///< /fitness/jitter: share of sines a jittered replica moves by 1 ulp, [0, 1]
  /// /fitness/stability_margin_min: refuse (as invalid, with the reason) a creature
  /// whose predicted stability margin of the step (core/stability.hpp, at its
  /// prepared start, in this stepping) is below this: a guard against walks that
  /// are an integration instability. 0 = no check. [0, 1e6]
  double stability_margin_min = 0.0;

  [[nodiscard]] soda::Stepping stepping() const { return {mode, integrator, substeps}; }

  bool operator==(const FitnessConfig&) const = default;
};

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

/// Random creatures for the initial population.
struct RandomCreatureConfig {
  int masses_min = 4;          ///< /population/random/masses_min [2, limits.max_masses]
  int masses_max = 10;         ///< /population/random/masses_max [masses_min, limits.max_masses]
  double extra_links_per_mass = 1.5; ///< /population/random/extra_links_per_mass [0, 20]: beyond a spanning tree
  double muscle_fraction = 0.5;      ///< /population/random/muscle_fraction [0, 1]
  double size = 120.0;               ///< /population/random/size: bounding box side, px, (0, 10000]

  bool operator==(const RandomCreatureConfig&) const = default;
};

struct PopulationConfig {
  int size = 60;                         ///< /population/size [2, 100000]
  std::vector<std::string> seed_models;  ///< /population/seed_models: XML paths, relative to the config file
  double random_fraction = 0.5;          ///< /population/random_fraction [0, 1]: share of random creatures (the rest: mutated seeds)
  RandomCreatureConfig random;

  bool operator==(const PopulationConfig&) const = default;
};

struct SelectionConfig {
  int tournament_size = 3; ///< /selection/tournament_size [1, population.size]
  int elites = 2;          ///< /selection/elites [0, population.size - 1]

  bool operator==(const SelectionConfig&) const = default;
};

/// A rate is the probability that the operator is applied to a child.
struct MutationConfig {
  double muscle_phase_rate = 0.4;       ///< /mutation/muscle_phase/rate [0, 1]
  double muscle_phase_sigma = 0.08;     ///< /mutation/muscle_phase/sigma: cycles (wraps), (0, 1]
  double muscle_amplitude_rate = 0.3;   ///< /mutation/muscle_amplitude/rate
  double muscle_amplitude_sigma = 0.1;  ///< /mutation/muscle_amplitude/sigma (clamped to [0,1])
  double rest_length_rate = 0.3;        ///< /mutation/rest_length/rate
  double rest_length_sigma = 0.08;      ///< /mutation/rest_length/sigma: relative, (0, 1]
  double wave_rate = 0.2;               ///< /mutation/wave/rate
  double wave_speed_sigma = 0.003;      ///< /mutation/wave/speed_sigma: cycles/frame, (0, 0.1]
  double wave_amplitude_sigma = 0.1;    ///< /mutation/wave/amplitude_sigma (clamped to [0,1])
  double move_mass_rate = 0.2;          ///< /mutation/move_mass/rate
  double move_mass_sigma = 5.0;         ///< /mutation/move_mass/sigma: px, (0, 1000]
  double add_link_rate = 0.1;           ///< /mutation/add_link/rate
  double remove_link_rate = 0.1;        ///< /mutation/remove_link/rate
  double toggle_muscle_rate = 0.1;      ///< /mutation/toggle_muscle/rate
  double add_mass_rate = 0.05;          ///< /mutation/add_mass/rate
  double remove_mass_rate = 0.05;       ///< /mutation/remove_mass/rate
  double world_rate = 0.1;              ///< /mutation/world/rate (only with /world/evolve)
  double world_sigma = 0.05;            ///< /mutation/world/sigma: relative to each range, (0, 1]

  bool operator==(const MutationConfig&) const = default;
};

struct LimitsConfig {
  int min_masses = 3;   ///< /limits/min_masses [2, max_masses]
  int max_masses = 40;  ///< /limits/max_masses [min_masses, 10000]
  int max_links = 150;  ///< /limits/max_links [1, 100000]

  bool operator==(const LimitsConfig&) const = default;
};

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

struct RunConfig {
  std::string name = "run";      ///< /name: [A-Za-z0-9_.-]{1,64}; names the run folder
  std::uint64_t seed = 1;        ///< /seed: [0, 2^53]
  double crossover_rate = 0.0;   ///< /crossover/rate [0, 1]: one-point crossover on mass order (see configs/README.md)
  PopulationConfig population;
  SelectionConfig selection;
  MutationConfig mutation;
  LimitsConfig limits;
  BudgetConfig budget;
  FitnessConfig fitness;
  WorldConfig world;
  SaveConfig save;
  AlgorithmKind algorithm = AlgorithmKind::Genetic; ///< /algorithm: "ga" | "map-elites"
  MapElitesConfig map_elites;    ///< /map_elites: only with /algorithm "map-elites" (map_elites_config.hpp)

  bool operator==(const RunConfig&) const = default;
};

/// The world parameters /world/evolve may name, in canonical order (parsing
/// stores /world/evolve in this order): gravity, friction, springyness,
/// surface_friction, surface_reflection.
const std::vector<std::string>& world_parameter_names();

/// The JSON spellings of the enums ("right", "sodarace", "down", ...).
std::string direction_name(WalkDirection d);
std::string scaling_name(FitnessScaling s);
std::string divergence_check_name(DivergenceCheck d);
std::string statistic_name(EstimateStatistic s);
std::string gravity_direction_name(soda::GravityDirection d);

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
