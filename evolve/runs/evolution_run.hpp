// run_evolution: the loop that ties the run's roles (evolve/runs/run_roles.hpp: its
// problem, estimator and algorithm), an evaluator and the run store together,
// with budgets, checkpoints, resume and a polite stop.
#pragma once

#include <atomic>
#include <functional>
#include <string>

#include "evolve/evaluators/evaluator.hpp"
#include "evolve/runs/run_budget.hpp"
#include "evolve/algorithms/population.hpp"
#include "evolve/store/run_store.hpp"

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
  StopReason stopped_because = StopReason::Completed;
  std::string best_id;
  double best_fitness = kWorstFitness;
};

/// Seed creatures from the config's seed models (read and made evolvable).
std::vector<soda::ModelDef> load_seed_creatures(const RunConfig& config);

/// A new run folder for `config` (RunStore::create), its seed models checked
/// first, so that a seed that cannot be evolved is an error of the config
/// (prefixed with `source`, the config's name) before a folder exists (a folder
/// without a checkpoint could not be resumed). `evolve` and the Python module's
/// evolve() start runs this way.
RunStore start_run(const RunConfig& config, const std::string& source, const std::filesystem::path& dir, bool force,
                   const std::string& command_line);

/// How many of a finished run's best creatures are checked on fresh replicas for
/// RUN/champions.json (write_run_champions), and on how many replicas each.
inline constexpr int kRunChampionsChecked = 10;
inline constexpr int kRunChampionReplicas = 16;

/// Runs (or, if the store has a checkpoint, resumes) the evolution.
EvolutionOutcome run_evolution(RunStore& store, Evaluator& evaluator, const EvolutionOptions& options);

} // namespace sodaevo
