// run_evolution: the loop that ties the run's roles (evolve/run_roles.hpp: its
// problem, estimator and algorithm), an evaluator and the run store together,
// with budgets, checkpoints, resume and a polite stop.
#pragma once

#include <atomic>
#include <functional>
#include <string>

#include "evolve/evaluator.hpp"
#include "evolve/population.hpp"
#include "evolve/run_store.hpp"

namespace sodaevo {

struct Progress {
  int generation = 0;
  int generations = 0;             ///< planned
  GenerationStats stats;
  double wall_seconds = 0.0;       ///< since the run started (resumes included)
  double evaluations_per_second = 0.0;
};

struct EvolutionOptions {
  /// Called after each generation (for progress display).
  std::function<void(const Progress&)> on_generation;
  /// When it becomes true, the current generation is finished and saved, then
  /// the run stops (Ctrl-C).
  const std::atomic<bool>* stop_requested = nullptr;
  /// Resuming a checkpoint scored with another sine (evolve --resume-other-sine):
  /// its generation is scored again from scratch, as if newly born, and saved whole,
  /// so that no generation from there on holds fitnesses of two sines (elites
  /// carry theirs over, and the replicas they gathered were the old sine's).
  bool rescore_checkpoint = false;
};

struct EvolutionOutcome {
  int last_generation = -1;
  long long evaluations = 0;
  std::string stopped_because; ///< "completed", "evaluation budget", "wall-time budget", "interrupted"
  std::string best_id;
  double best_fitness = kWorstFitness;
};

/// Seed creatures from the config's seed models (read and made evolvable).
std::vector<soda::ModelDef> load_seed_creatures(const RunConfig& config);

/// Runs (or, if the store has a checkpoint, resumes) the evolution.
EvolutionOutcome run_evolution(RunStore& store, Evaluator& evaluator, const EvolutionOptions& options);

} // namespace sodaevo
