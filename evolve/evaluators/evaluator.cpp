#include "evaluator.hpp"

#include <algorithm>
#include <map>
#include <memory>

#include "core/batch_step.hpp"
#include "evolve/evaluators/parallel_for.hpp"

namespace sodaevo {

long long evaluate_generation(Evaluator& evaluator, Generation& g, const Problem& problem,
                              const Estimator& estimator) {
  std::vector<std::size_t> todo;
  std::vector<const soda::ModelDef*> creatures;
  // Survivors the estimator wants to see again, by the rollout count it wants
  // (adaptive resampling; an estimator without it never asks).
  std::map<int, std::vector<std::size_t>> resample;
  for (std::size_t i = 0; i < g.individuals.size(); ++i) {
    if (g.individuals[i].evaluated) {
      if (const int n = estimator.resample_to(g.individuals[i].evaluation); n > 0) resample[n].push_back(i);
      continue;
    }
    todo.push_back(i);
    creatures.push_back(&g.individuals[i].creature);
  }
  std::vector<Evaluation> results = evaluator.evaluate(creatures, problem, estimator);
  std::vector<std::pair<std::size_t, Evaluation>> resampled;
  for (const auto& [rollouts, who] : resample) {
    std::vector<const soda::ModelDef*> again;
    for (std::size_t i : who) again.push_back(&g.individuals[i].creature);
    const std::unique_ptr<Estimator> more = estimator.with_rollouts(rollouts);
    std::vector<Evaluation> r = evaluator.evaluate(again, problem, *more);
    for (std::size_t k = 0; k < who.size(); ++k) resampled.emplace_back(who[k], std::move(r[k]));
  }
  // Stored only once every evaluation succeeded: all or nothing.
  for (std::size_t k = 0; k < todo.size(); ++k) {
    g.individuals[todo[k]].evaluation = std::move(results[k]);
    g.individuals[todo[k]].evaluated = true;
  }
  for (auto& [i, e] : resampled) g.individuals[i].evaluation = std::move(e);
  return static_cast<long long>(todo.size() + resampled.size());
}

long long confirm_best(Evaluator& evaluator, Generation& g, const Problem& problem, const Estimator& estimator,
                       int count, long long max_evaluations) {
  long long done = 0;
  for (;;) {
    std::map<int, std::vector<std::size_t>> todo; // by the rollout count wanted
    int seen = 0;
    long long wanted = 0;
    for (std::size_t i : ranked_best_first(g)) {
      const Individual& ind = g.individuals[i];
      if (seen >= count || !ind.evaluated || !ind.evaluation.ok()) break;
      if (max_evaluations >= 0 && done + wanted >= max_evaluations) break;
      ++seen;
      if (const int n = estimator.confirm_to(ind.evaluation); n > 0) {
        todo[n].push_back(i);
        ++wanted;
      }
    }
    if (todo.empty()) return done;
    for (const auto& [rollouts, who] : todo) {
      std::vector<const soda::ModelDef*> creatures;
      for (std::size_t i : who) creatures.push_back(&g.individuals[i].creature);
      const std::unique_ptr<Estimator> more = estimator.with_rollouts(rollouts);
      std::vector<Evaluation> results = evaluator.evaluate(creatures, problem, *more);
      for (std::size_t k = 0; k < who.size(); ++k) g.individuals[who[k]].evaluation = std::move(results[k]);
      done += static_cast<long long>(who.size());
    }
  }
}

std::size_t evaluation_batch_size(std::size_t count, int threads) {
  const std::size_t per_thread = 2 * static_cast<std::size_t>(std::max(1, threads));
  return std::clamp<std::size_t>((count + per_thread - 1) / per_thread, 1, kMaxEvaluationBatch);
}

ThreadEvaluator::ThreadEvaluator(int threads, std::size_t batch)
    : threads_(resolve_thread_count(threads)), batch_(batch) {}

std::vector<Evaluation> ThreadEvaluator::evaluate(const std::vector<const soda::ModelDef*>& creatures,
                                                  const Problem& problem, const Estimator& estimator) {
  const std::size_t batch = batch_ > 0 ? batch_ : evaluation_batch_size(creatures.size(), threads_);
  std::vector<Evaluation> results(creatures.size());
  // Batches end where the batch stepper would start a new fused scene anyway:
  // smaller work items balance the threads better and lose none of the fusing.
  // (The link count of the genome is that of the prepared model.)
  std::vector<int> links;
  for (const soda::ModelDef* c : creatures) links.push_back(static_cast<int>(c->links.size()));
  const std::vector<std::size_t> ends = soda::fused_batch_ends(links, batch);
  parallel_for_index(ends.size(), threads_, [&](std::size_t b) {
    const std::size_t first = b == 0 ? 0 : ends[b - 1], last = ends[b];
    const std::vector<const soda::ModelDef*> mine(creatures.begin() + static_cast<std::ptrdiff_t>(first),
                                                  creatures.begin() + static_cast<std::ptrdiff_t>(last));
    std::vector<Evaluation> scored = estimator.estimate(problem, mine);
    for (std::size_t k = 0; k < scored.size(); ++k) results[first + k] = std::move(scored[k]);
  });
  return results;
}

} // namespace sodaevo
