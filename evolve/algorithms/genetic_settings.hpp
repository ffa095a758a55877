// GeneticSettings: what the GA and its variation operators are constructed from
// (configs/README.md: /seed, /population, /selection, /mutation, /crossover, and the
// /limits and /world a child must respect). RunConfig (config/run_config.hpp)
// derives from it, so a run's config is handed to the GA as it is, and the GA sees
// none of the other roles' settings.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "evolve/problems/creature_limits.hpp"
#include "evolve/problems/world_settings.hpp"

namespace sodaevo {

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

struct GeneticSettings {
  std::uint64_t seed = 1;        ///< /seed: [0, 2^53]
  double crossover_rate = 0.0;   ///< /crossover/rate [0, 1]: one-point crossover on mass order (see configs/README.md)
  PopulationConfig population;
  SelectionConfig selection;
  MutationConfig mutation;
  LimitsConfig limits;
  WorldConfig world;

  bool operator==(const GeneticSettings&) const = default;
};

} // namespace sodaevo
