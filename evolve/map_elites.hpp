// MAP-Elites (Mouret and Clune 2015): instead of one population converging on one
// body plan, an archive (evolve/grid_archive.hpp) keeps the best creature of each
// kind of body and gait, and new creatures are made from random elites.
//
// One iteration: batch_size children, each a random elite (uniform over the filled
// cells) changed by the GA's mutation operators (evolve/variation.hpp), or, with
// probability crossover_rate, the crossover of two random elites, mutated; the
// children are evaluated (fitness and descriptors of the same rollouts), then
// inserted in child order by the archive's noise-aware rule. Iteration 0 is the
// GA's first generation (seeds and random creatures, /population).
//
// Determinism: child k of iteration t draws from its own stream
// Rng::stream(seed, t, k, kMapElitesPurpose), and insertion runs in child order on
// one thread, so results depend on neither the thread nor the rank count; a
// checkpoint needs only the archive and t (the random state is a function of them).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "evolve/described_evaluation.hpp"
#include "evolve/grid_archive.hpp"
#include "evolve/map_elites_config.hpp"
#include "evolve/population.hpp"
#include "evolve/run_config.hpp"

namespace sodaevo {

/// The fourth coordinate of MAP-Elites' random streams (the GA's RngPurpose uses 1 and 2).
inline constexpr std::uint64_t kMapElitesPurpose = 3;

/// A child and its first estimate.
struct Challenger {
  Individual individual;
  DescribedEvaluation first; ///< replica 0
};

/// The children of iteration `iteration` >= 1 from a non-empty archive (not evaluated).
/// `config` gives the seed, the mutation operators and the limits.
std::vector<Individual> map_elites_children(const RunConfig& config, const MapElitesConfig& me,
                                            const GridArchive& archive, int iteration);

/// Evaluations of replicas [first, first + count) of a creature (replica 0 is the
/// exact run). The archive asks for more only while cap > 1.
using ReplicaSampler =
    std::function<std::vector<DescribedEvaluation>(const soda::ModelDef& creature, long long first, long long count)>;

/// What insertion did with a batch.
struct InsertionCounts {
  int entered = 0;       ///< into an empty cell
  int replaced = 0;      ///< an elite
  int rejected = 0;      ///< not better, or invalid / diverged
  long long resampled = 0; ///< replicas evaluated to make counts comparable
};

/// Inserts challengers in order by judge() (grid_archive.hpp), sampling either side
/// with `sample` as it asks, up to `cap` replicas. Invalid and diverged challengers
/// are rejected.
InsertionCounts insert_challengers(GridArchive& archive, std::vector<Challenger> challengers, int iteration,
                                   long long cap, const ReplicaSampler& sample);

} // namespace sodaevo
