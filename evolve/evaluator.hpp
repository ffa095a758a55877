// Evaluators score the individuals of a generation that are not yet evaluated
// (pagmo's "evaluator" role). Results are stored by index, so which thread or
// process evaluated a creature never changes the result.
#pragma once

#include "evolve/population.hpp"
#include "evolve/run_config.hpp"

namespace sodaevo {

class Evaluator {
 public:
  virtual ~Evaluator() = default;
  /// Evaluates every individual with evaluated == false; returns how many.
  virtual long long evaluate(Generation& generation, const RunConfig& config) = 0;
};

/// Evaluates on `threads` threads of this process (0 = all cores).
class ThreadEvaluator final : public Evaluator {
 public:
  explicit ThreadEvaluator(int threads);
  long long evaluate(Generation& generation, const RunConfig& config) override;
  [[nodiscard]] int threads() const { return threads_; }

 private:
  int threads_;
};

} // namespace sodaevo
