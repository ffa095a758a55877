// MapElitesConfig: the /map_elites object of a run config (configs/README.md,
// "MAP-Elites"), read and checked here and embedded in RunConfig.
//
// Parsing follows run_config.cpp's rules: strict, every problem collected, each
// naming the JSON pointer, what was expected and what was found.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "evolve/problems/descriptors.hpp"
#include "evolve/algorithms/grid_archive.hpp"

namespace sodaevo {

/// /algorithm: what searches (the GA by default).
enum class AlgorithmKind { Genetic, MapElites };
std::string algorithm_name(AlgorithmKind a);           ///< "ga", "map-elites"
const std::vector<std::string>& algorithm_names();

/// Most cells a grid may have (bins multiplied over the axes).
inline constexpr double kMaxArchiveCells = 100000;

struct MapElitesConfig {
  /// /map_elites/descriptors, /bins, /ranges: the grid's axes, 2 or 3. Default:
  /// width, height and mass count (OpenELM's Sodarace axes), 12 x 12 x 12 = 1,728 cells.
  std::vector<GridAxis> axes = {
      {Descriptor::Width, 12, 40.0, 300.0},
      {Descriptor::Height, 12, 0.0, 100.0},
      {Descriptor::MassCount, 12, 2.5, 14.5},
  };
  int iterations = 100;        ///< /map_elites/iterations [1, 1e6]: batches after the initial population
  int batch_size = 64;         ///< /map_elites/batch_size [1, 100000]: children per iteration
  double crossover_rate = 0.0; ///< /map_elites/crossover_rate [0, 1]: a child of two random elites
  /// /map_elites/parent_tournament [1, 64]: a parent is the fittest of this many
  /// elites drawn uniformly (1: uniform over the filled cells, plain MAP-Elites).
  int parent_tournament = 1;
  /// /map_elites/elite_share [0, 1]: the share of each batch's children (the first
  /// ones) whose parents are drawn from the elite pool instead of every filled cell:
  /// an optimising emitter, so that the archive's best climbs as a GA's does while
  /// the rest of the batch keeps exploring (0: plain MAP-Elites).
  double elite_share = 0.0;
  /// /map_elites/elite_pool [1, 100000]: how many of the fittest elites (highest
  /// mean) the elite share draws its parents from.
  int elite_pool = 16;
  int snapshot_every = 10;     ///< /map_elites/snapshot_every [0, 1e6]: archive snapshots (0 = the last only)
  int sample_every = 8;        ///< /map_elites/sample_every [1, 1e6]: scored frames between descriptor samples
  double qd_offset = 0.0;      ///< /map_elites/qd_offset: subtracted from each elite's fitness in the QD-score
  /// /map_elites/check_replicas [0, 4096]: fresh replicas each elite is checked on
  /// at the end of a run (RUN/archive_checked.json, evolve/runs/archive_check.hpp); 0 = no check.
  int check_replicas = 8;

  bool operator==(const MapElitesConfig&) const = default;
};

/// One problem found while reading: where, and "expected ..., got ..." or similar.
struct ConfigProblem {
  std::string pointer;
  std::string message;
};

/// Reads the /map_elites object `value` over the defaults in `config`; appends
/// every problem (pointers absolute, "/map_elites/...").
void read_map_elites(const nlohmann::json& value, MapElitesConfig& config, std::vector<ConfigProblem>& problems);

/// The resolved /map_elites object (every key); read_map_elites reads it back to
/// the same config.
nlohmann::json to_json(const MapElitesConfig& config);

} // namespace sodaevo
