// Evaluators decide where creatures are evaluated: on the threads of this process
// (ThreadEvaluator) or over the ranks of an MPI job (mpi/mpi_evaluator.hpp),
// pagmo's "evaluator" role. They are given a Problem and an Estimator, never the
// run's config, and store results by index, so which thread or process evaluated
// a creature never changes the result.
#pragma once

#include <cstddef>
#include <vector>

#include "core/model_def.hpp"
#include "evolve/estimators/estimator.hpp"
#include "evolve/algorithms/population.hpp"
#include "evolve/problems/problem.hpp"

namespace sodaevo {

class Evaluator {
 public:
  virtual ~Evaluator() = default;
  /// Result i is exactly estimator.estimate(problem, {creatures[i]}).front(),
  /// whichever thread or process ran it and whichever creatures shared its batch.
  /// Throws (and returns nothing) if part of the work failed.
  virtual std::vector<Evaluation> evaluate(const std::vector<const soda::ModelDef*>& creatures,
                                           const Problem& problem, const Estimator& estimator) = 0;
};

/// Evaluates the individuals of `generation` with evaluated == false and stores
/// their evaluations (all or, if the evaluator throws, none); returns how many.
long long evaluate_generation(Evaluator& evaluator, Generation& generation, const Problem& problem,
                              const Estimator& estimator);

/// Confirmation at the end of a run (/fitness/confirm): the best `count` valid
/// individuals of an evaluated generation whose estimate the estimator would
/// sharpen (Estimator::confirm_to) are estimated again, the generation is ranked
/// again, and so on until its best `count` are all confirmed (or none is left to
/// confirm). Why: the best of a generation are its luckiest draws too; estimated
/// again on more replicas, a lucky one falls back and the next is confirmed, so
/// what the run hands over claims what it walks. Returns the evaluations made.
/// At most `max_evaluations` evaluations (< 0: no limit), the best first.
/// Deterministic: the order is ranked_best_first's, the rollouts are seeded.
long long confirm_best(Evaluator& evaluator, Generation& generation, const Problem& problem,
                       const Estimator& estimator, int count, long long max_evaluations = -1);

/// Largest number of creatures a thread estimates in one batch (stepped together
/// on one core: small creatures alone leave most of the core idle, fused they
/// share its SIMD batches; core/batch_step.hpp).
inline constexpr std::size_t kMaxEvaluationBatch = 16;

/// Creatures per batch for `count` creatures on `threads` threads: at most
/// kMaxEvaluationBatch, and small enough that every thread gets about two batches.
std::size_t evaluation_batch_size(std::size_t count, int threads);

/// Evaluates on the threads of this process, a batch of creatures at a time.
class ThreadEvaluator final : public Evaluator {
 public:
  /// `threads` 0 = all cores; `batch` 0 = evaluation_batch_size. Neither changes a
  /// result (tests/test_evolve.cpp).
  explicit ThreadEvaluator(int threads, std::size_t batch = 0);
  std::vector<Evaluation> evaluate(const std::vector<const soda::ModelDef*>& creatures, const Problem& problem,
                                   const Estimator& estimator) override;
  [[nodiscard]] int threads() const { return threads_; }

 private:
  int threads_;
  std::size_t batch_;
};

} // namespace sodaevo
