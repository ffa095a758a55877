// GeneticAlgorithm: makes generations (pagmo's "algorithm" role). It neither
// simulates nor writes files: an Evaluator scores creatures, the run store keeps
// them.
//
// Generational GA with elitism and tournament selection. All randomness of a
// child comes from the stream (seed, generation, index), so a generation depends
// only on the config and the previous generation: runs are reproducible and
// resumable from any checkpoint, whatever the number of threads.
#pragma once

#include <vector>

#include "core/model_def.hpp"
#include "evolve/population.hpp"
#include "evolve/run_config.hpp"

namespace sodaevo {

/// Purposes of RNG streams (the fourth stream coordinate).
enum class RngPurpose : std::uint64_t { Initial = 1, Breed = 2 };

/// Generation 0: seeds (index 0..: first each seed as is, then mutated copies)
/// and random creatures, in the proportions of the config. Not evaluated.
Generation initial_generation(const RunConfig& config, const std::vector<soda::ModelDef>& seeds);

/// The next generation from an evaluated one: the elites (copied with their
/// evaluation) then children by tournament selection, optional crossover and
/// mutation. Not evaluated (except the elites).
Generation next_generation(const RunConfig& config, const Generation& evaluated);

} // namespace sodaevo
