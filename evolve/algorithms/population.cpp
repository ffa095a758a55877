#include "population.hpp"

#include <algorithm>
#include <numeric>

namespace sodaevo {

GenerationStats summarize(const Generation& g, long long evaluations) {
  GenerationStats s;
  s.generation = g.index;
  s.evaluations = evaluations;
  std::vector<double> values;
  for (std::size_t i = 0; i < g.individuals.size(); ++i) {
    const Evaluation& e = g.individuals[i].evaluation;
    if (e.status == EvaluationStatus::Invalid) ++s.invalid;
    if (e.status == EvaluationStatus::Diverged) ++s.diverged;
    if (!e.ok()) continue;
    values.push_back(e.fitness);
    if (s.best_index < 0 || e.fitness > s.best) {
      s.best = e.fitness;
      s.best_index = static_cast<int>(i);
    }
  }
  if (values.empty()) return s;
  double sum = 0.0;
  for (double v : values) sum += v; // in index order: deterministic
  s.mean = sum / static_cast<double>(values.size());
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  s.median = n % 2 ? values[n / 2] : (values[n / 2 - 1] + values[n / 2]) / 2.0;
  s.worst = values.front();
  return s;
}

bool ranks_before(const Generation& g, std::size_t a, std::size_t b) {
  const Evaluation& ea = g.individuals[a].evaluation;
  const Evaluation& eb = g.individuals[b].evaluation;
  if (ea.ok() != eb.ok()) return ea.ok();
  if (ea.ok() && ea.fitness != eb.fitness) return ea.fitness > eb.fitness;
  return a < b;
}

std::vector<std::size_t> ranked_best_first(const Generation& g) {
  std::vector<std::size_t> ranked(g.individuals.size());
  std::iota(ranked.begin(), ranked.end(), 0);
  std::sort(ranked.begin(), ranked.end(), [&](std::size_t a, std::size_t b) { return ranks_before(g, a, b); });
  return ranked;
}

} // namespace sodaevo
