// MAP-Elites (Mouret and Clune 2015): instead of one population converging on one
// body plan, an archive (evolve/algorithms/grid_archive.hpp) keeps the best creature of each
// kind of body and gait, and new creatures are made from random elites.
//
// One iteration: batch_size children, each a random elite (uniform over the filled
// cells, or with /map_elites/parent_tournament k > 1 the fittest of k uniform
// draws, which spends more children on good cells) changed by the GA's mutation operators (evolve/algorithms/variation.hpp), or, with
// probability crossover_rate, the crossover of two random elites, mutated; the
// children are estimated through the roles (the Evaluator runs the Estimator's
// replicas of the Problem's rollouts, on threads or MPI ranks: fitness and
// descriptors are means over the same replicas), then inserted in child order by
// the archive's noise-aware rule, which asks for more replicas of a challenger or
// an elite as it needs them. Iteration 0 is the GA's first generation (seeds and
// random creatures, /population).
//
// Determinism: child k of iteration t draws from its own stream
// Rng::stream(seed, t, k, kMapElitesPurpose); replica r of a creature has a seed
// of (run seed, genome, r) (evolve/estimators/replica_estimator.hpp); insertion decides in
// child order within each cell, and cells do not interact, so the extra replicas
// that all cells ask for at once are evaluated together in rounds without
// changing any decision. Results depend on neither the thread nor the rank
// count; a checkpoint needs only the archive and t.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "evolve/problems/evaluation.hpp"
#include "evolve/algorithms/grid_archive.hpp"
#include "evolve/algorithms/map_elites_settings.hpp"
#include "evolve/algorithms/population.hpp"
#include "evolve/algorithms/genetic_settings.hpp"

namespace sodaevo {

/// The fourth coordinate of MAP-Elites' random streams (the GA's RngPurpose uses 1 and 2).
inline constexpr std::uint64_t kMapElitesPurpose = 3;

/// A child and its first estimate (replicas 0 .. /fitness/replicas - 1, with descriptors).
struct Challenger {
  Individual individual;
  Evaluation first;
};

/// The children of iteration `iteration` >= 1 from a non-empty archive (not evaluated).
/// `config` gives the seed, the mutation operators and the limits.
std::vector<Individual> map_elites_children(const GeneticSettings& config, const MapElitesConfig& me,
                                            const GridArchive& archive, int iteration);

/// More replicas of one creature: [first, first + count).
struct SampleRequest {
  const soda::ModelDef* creature = nullptr;
  long long first = 0;
  long long count = 0;
};

/// Estimates of each request's replicas (result i for requests[i]: estimate over
/// those replicas, descriptors their means). Asked only while the cap is above 1.
using ReplicaSampler = std::function<std::vector<Evaluation>(const std::vector<SampleRequest>& requests)>;

/// What insertion did with a batch.
struct InsertionCounts {
  int entered = 0;       ///< into an empty cell
  int replaced = 0;      ///< an elite
  int rejected = 0;      ///< not better, or invalid / diverged
  int evicted = 0;       ///< elites that failed on a further replica
  long long resampled = 0;         ///< estimates of further replicas (one per request)
  long long resampled_rollouts = 0; ///< the replicas in them
};

/// Inserts challengers by judge() (grid_archive.hpp), in child order within each
/// cell, sampling either side with `sample` as it asks, within `plan`. Invalid and
/// diverged challengers are rejected; an elite that fails on a further replica
/// leaves its cell (a creature that diverges on another machine's sine is no elite).
InsertionCounts insert_challengers(GridArchive& archive, std::vector<Challenger> challengers, int iteration,
                                   const ResamplePlan& plan, const ReplicaSampler& sample);

} // namespace sodaevo
