#include "evaluator.hpp"

#include <vector>

#include "evolve/parallel_for.hpp"

namespace sodaevo {

ThreadEvaluator::ThreadEvaluator(int threads) : threads_(resolve_thread_count(threads)) {}

long long ThreadEvaluator::evaluate(Generation& g, const RunConfig& config) {
  std::vector<std::size_t> todo;
  for (std::size_t i = 0; i < g.individuals.size(); ++i) {
    if (!g.individuals[i].evaluated) todo.push_back(i);
  }
  parallel_for_index(todo.size(), threads_, [&](std::size_t k) {
    Individual& ind = g.individuals[todo[k]];
    ind.evaluation = evaluate_creature(ind.creature, config);
    ind.evaluated = true;
  });
  return static_cast<long long>(todo.size());
}

} // namespace sodaevo
