// Individuals and generations: a creature with its identity, ancestry and score.
#pragma once

#include <string>
#include <vector>

#include "core/model_def.hpp"
#include "evolve/problems/evaluation.hpp"

namespace sodaevo {

struct Individual {
  std::string id;                   ///< "g<generation>-<index>", unique in a run
  std::vector<std::string> parents; ///< ids of the parents (empty for gen-0 creatures)
  soda::ModelDef creature;          ///< the genome, in canonical form
  Evaluation evaluation;
  bool evaluated = false;           ///< elites carry their evaluation over
};

struct Generation {
  int index = 0;
  std::vector<Individual> individuals;
  /// The race timeout this generation was scored with when
  /// /fitness/race/timeout_factor sets one (evolve/runs/race_schedule.hpp); 0: the run's.
  int race_timeout = 0;
  /// The /fitness/race/curriculum stage this generation raced (0: the first).
  int race_stage = 0;
};

/// Summary of an evaluated generation (over the creatures that are Ok).
struct GenerationStats {
  int generation = 0;
  long long evaluations = 0; ///< cumulative evaluations in the run so far
  double best = kWorstFitness, mean = kWorstFitness, median = kWorstFitness, worst = kWorstFitness;
  int invalid = 0;
  int diverged = 0;
  int best_index = -1;       ///< index of the best individual (ties: lowest index)
};

GenerationStats summarize(const Generation& generation, long long evaluations);

/// The GA's order of individuals: Ok before not Ok, then higher fitness, then
/// lower index. Whether individual a ranks before b.
bool ranks_before(const Generation& generation, std::size_t a, std::size_t b);
/// Indices of the individuals, best first (ranks_before).
std::vector<std::size_t> ranked_best_first(const Generation& generation);

} // namespace sodaevo
