#include "evolve/race_schedule.hpp"

#include <algorithm>
#include <cmath>

#include "core/race_def.hpp"
#include "evolve/race_problem.hpp"

namespace sodaevo {

int next_race_timeout(const RunConfig& config, const Generation& evaluated) {
  const double factor = config.fitness.race.timeout_factor;
  if (config.fitness.kind != FitnessKind::Race || !(factor > 0.0)) return 0;
  const GenerationStats stats = summarize(evaluated, 0);
  if (stats.best_index < 0) return evaluated.race_timeout;
  const double frames = evaluated.individuals[static_cast<std::size_t>(stats.best_index)].evaluation.distance;
  const double timeout = std::ceil(factor * frames);
  return static_cast<int>(std::clamp(timeout, 1.0, static_cast<double>(soda::kMaxRaceTimeout)));
}

void schedule_race(const RunConfig& config, const Generation& evaluated, Generation& next) {
  next.race_timeout = next_race_timeout(config, evaluated);
  if (next.race_timeout == evaluated.race_timeout) return;
  for (Individual& ind : next.individuals) ind.evaluated = false;
}

std::unique_ptr<Problem> scheduled_problem(const Problem& run_problem, const Generation& g) {
  const auto* race = dynamic_cast<const RaceProblem*>(&run_problem);
  if (race == nullptr || g.race_timeout == 0) return nullptr;
  return std::make_unique<RaceProblem>(race->with_adaptive_timeout(g.race_timeout));
}

} // namespace sodaevo
