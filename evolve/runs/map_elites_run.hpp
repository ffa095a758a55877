// run_map_elites: the MAP-Elites loop (evolve/algorithms/map_elites.hpp) with its run folder
// (evolve/store/archive_store.hpp), budgets, checkpoints, resume and a polite stop, as
// run_evolution is for the GA. It evaluates through the roles: the run's
// WalkProblem or RaceProblem measuring descriptors, its ReplicaEstimator (/fitness/replicas for a
// new creature, more as the insertion rule asks, up to /fitness/replicas_max), and
// the Evaluator it is given (threads, or MPI ranks).
#pragma once

#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "evolve/store/archive_store.hpp"
#include "evolve/evaluators/evaluator.hpp"
#include "evolve/algorithms/map_elites.hpp"
#include "evolve/estimators/replica_estimator.hpp"
#include "evolve/problems/walk_problem.hpp"
#include "evolve/runs/run_budget.hpp"

namespace sodaevo {

/// The problem MAP-Elites scores: the run's, measuring descriptors every
/// /map_elites/sample_every scored frames.
WalkProblem map_elites_problem(const RunConfig& config, const MapElitesConfig& me);

/// How insertion samples with the run's estimator: new creatures on its
/// replicas (/fitness/replicas), at most replicas_max a side, replicas more for a
/// confirmation.
ResamplePlan map_elites_resample_plan(const ReplicaPlan& plan);

/// The sampler insertion asks for further replicas: requests grouped by their
/// replica range, each group one call of `evaluator`.
ReplicaSampler replica_sampler(Evaluator& evaluator, const Problem& problem, const ReplicaEstimator& estimator);

struct MapElitesProgress {
  int iteration = 0;
  int iterations = 0;        ///< planned
  long long evaluations = 0; ///< cumulative
  long long rollouts = 0;    ///< cumulative
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
  long long rollouts = 0;
  StopReason stopped_because = StopReason::Completed;
  QdMetrics metrics;
};

/// Runs MAP-Elites in the run folder `dir` (made by RunStore::create), or resumes
/// it from its archive checkpoint.
MapElitesOutcome run_map_elites(const std::filesystem::path& dir, const RunConfig& config, const MapElitesConfig& me,
                                Evaluator& evaluator, const MapElitesOptions& options);

} // namespace sodaevo
