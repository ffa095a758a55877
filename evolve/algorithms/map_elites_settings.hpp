// MapElitesConfig: the /map_elites object of a run config (configs/README.md,
// "MAP-Elites"), the settings MAP-Elites is constructed from: its grid, batches,
// parents, snapshots and check. config/map_elites_config.hpp reads it.
#pragma once

#include <string>
#include <vector>

#include "core/enum_names.hpp"
#include "evolve/algorithms/grid_archive.hpp"
#include "evolve/problems/descriptors.hpp"

namespace sodaevo {

/// /algorithm: what searches (the GA by default).
enum class AlgorithmKind { Genetic, MapElites };
inline constexpr soda::EnumName<AlgorithmKind> kAlgorithmNames[] = {{AlgorithmKind::Genetic, "ga"},
                                                                   {AlgorithmKind::MapElites, "map-elites"}};
inline std::string algorithm_name(AlgorithmKind a) { return soda::name_of(kAlgorithmNames, a); }

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
  /// /map_elites/elite_recent [0, 1e6]: when > 0, the elite pool is the fittest of
  /// the elites that entered their cell in the last this many iterations (topped
  /// up with the fittest of all). Why: a pool of the fittest of all stalls once no
  /// child beats them (the archive keeps one per cell and never lets an equal child
  /// in), while a GA's population keeps moving; drawing on the recent entrants
  /// lets the pool drift as a population does. 0: the fittest of all.
  int elite_recent = 0;
  int snapshot_every = 10;     ///< /map_elites/snapshot_every [0, 1e6]: archive snapshots (0 = the last only)
  int sample_every = 8;        ///< /map_elites/sample_every [1, 1e6]: scored frames between descriptor samples
  double qd_offset = 0.0;      ///< /map_elites/qd_offset: subtracted from each elite's fitness in the QD-score
  /// /map_elites/check_replicas [0, 4096]: fresh replicas each elite is checked on
  /// at the end of a run (RUN/archive_checked.json, evolve/runs/archive_check.hpp); 0 = no check.
  int check_replicas = 8;

  bool operator==(const MapElitesConfig&) const = default;
};

} // namespace sodaevo
