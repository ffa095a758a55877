// run_map_elites: the MAP-Elites loop (evolve/map_elites.hpp) with its run folder
// (evolve/archive_store.hpp), budgets, checkpoints, resume and a polite stop, as
// run_evolution is for the GA.
#pragma once

#include <atomic>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "evolve/archive_store.hpp"
#include "evolve/map_elites.hpp"

namespace sodaevo {

/// Evaluates creatures with their descriptors; result i belongs to creatures[i]
/// and does not depend on which others are in the call.
using DescribedEvaluator =
    std::function<std::vector<DescribedEvaluation>(const std::vector<const soda::ModelDef*>& creatures)>;

/// evaluate_described_creatures on `threads` threads (0 = all cores), in batches
/// stepped together as the GA's evaluations are.
DescribedEvaluator described_evaluator_on_threads(const RunConfig& config, const MapElitesConfig& me, int threads);

struct MapElitesProgress {
  int iteration = 0;
  int iterations = 0;        ///< planned
  long long evaluations = 0; ///< cumulative
  QdMetrics metrics;
  InsertionCounts counts;
  double wall_seconds = 0.0;
};

struct MapElitesOptions {
  std::function<void(const MapElitesProgress&)> on_iteration;
  /// When it becomes true, the current iteration is finished and saved, then the run stops.
  const std::atomic<bool>* stop_requested = nullptr;
};

struct MapElitesOutcome {
  int last_iteration = -1;
  long long evaluations = 0;
  std::string stopped_because; ///< "completed", "evaluation budget", "wall-time budget", "interrupted"
  QdMetrics metrics;
};

/// Runs MAP-Elites in the run folder `dir` (made by RunStore::create), or resumes
/// it from its archive checkpoint.
MapElitesOutcome run_map_elites(const std::filesystem::path& dir, const RunConfig& config, const MapElitesConfig& me,
                                const DescribedEvaluator& evaluate, const MapElitesOptions& options);

} // namespace sodaevo
