// Algorithm: what makes the next creatures to evaluate from the evaluated ones
// (pagmo's "algorithm" role). It neither simulates nor writes files: the run loop
// (evolve/runs/evolution_run.hpp) has an Evaluator score the individuals it returns
// unevaluated and the RunStore keep them.
//
// Today's algorithm is the generational GA (evolve/algorithms/genetic_algorithm.hpp). Every
// call is a pure function of the algorithm's settings and its argument, so a run
// resumes from any checkpoint; an algorithm with more state than a generation
// (an archive) has to keep it in what it returns.
#pragma once

#include <vector>

#include "core/model_def.hpp"
#include "evolve/algorithms/population.hpp"

namespace sodaevo {

class Algorithm {
 public:
  virtual ~Algorithm() = default;
  /// Generation 0 from the seed creatures; not evaluated.
  [[nodiscard]] virtual Generation first(const std::vector<soda::ModelDef>& seeds) const = 0;
  /// The next generation from an evaluated one; the individuals with
  /// evaluated == false are to be evaluated.
  [[nodiscard]] virtual Generation next(const Generation& evaluated) const = 0;
  /// The most evaluations next() asks for (the run loop stops before a generation
  /// that would exceed the evaluation budget).
  [[nodiscard]] virtual long long evaluations_per_generation() const = 0;
};

} // namespace sodaevo
