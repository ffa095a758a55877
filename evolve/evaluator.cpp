#include "evaluator.hpp"

#include <vector>

#include "evolve/batch_evaluation.hpp"
#include "evolve/parallel_for.hpp"

namespace sodaevo {

ThreadEvaluator::ThreadEvaluator(int threads) : threads_(resolve_thread_count(threads)) {}

long long ThreadEvaluator::evaluate(Generation& g, const RunConfig& config) {
  std::vector<std::size_t> todo;
  for (std::size_t i = 0; i < g.individuals.size(); ++i) {
    if (!g.individuals[i].evaluated) todo.push_back(i);
  }
  std::vector<const soda::ModelDef*> creatures;
  for (std::size_t i : todo) creatures.push_back(&g.individuals[i].creature);
  std::vector<Evaluation> results = evaluate_creatures(creatures, config, threads_); // batches, by index
  for (std::size_t k = 0; k < todo.size(); ++k) {
    g.individuals[todo[k]].evaluation = std::move(results[k]);
    g.individuals[todo[k]].evaluated = true;
  }
  return static_cast<long long>(todo.size());
}

} // namespace sodaevo
