#include "evolve/runs/race_schedule.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/race_def.hpp"
#include "evolve/problems/race_problem.hpp"
#include "evolve/store/run_reader.hpp"
#include "evolve/runs/run_roles.hpp"

namespace sodaevo {

namespace {
/// The race result (frames) of the best creature of `evaluated`, or nothing when none was scored.
std::optional<double> best_frames(const Generation& evaluated) {
  const GenerationStats stats = summarize(evaluated, 0);
  if (stats.best_index < 0) return std::nullopt;
  return evaluated.individuals[static_cast<std::size_t>(stats.best_index)].evaluation.distance;
}
} // namespace

int next_race_timeout(const RunConfig& config, const Generation& evaluated) {
  const double factor = config.fitness.race.timeout_factor;
  if (!(factor > 0.0)) return 0; // off, or not a race (a walk has no /fitness/race)
  const std::optional<double> frames = best_frames(evaluated);
  if (!frames) return evaluated.race_timeout;
  const double timeout = std::ceil(factor * *frames);
  return static_cast<int>(std::clamp(timeout, 1.0, static_cast<double>(soda::kMaxRaceTimeout)));
}

int next_race_stage(const RunConfig& config, const Generation& evaluated) {
  const std::vector<CurriculumStage>& stages = config.fitness.race.curriculum;
  const std::size_t stage = static_cast<std::size_t>(evaluated.race_stage);
  if (stage + 1 >= stages.size()) return evaluated.race_stage; // the last stage, or no curriculum
  const std::optional<double> frames = best_frames(evaluated);
  if (!frames) return evaluated.race_stage;
  return *frames < stages[stage].threshold ? evaluated.race_stage + 1 : evaluated.race_stage;
}

void schedule_race(const RunConfig& config, const Generation& evaluated, Generation& next) {
  next.race_stage = next_race_stage(config, evaluated);
  next.race_timeout = next.race_stage == evaluated.race_stage ? next_race_timeout(config, evaluated) : 0;
  if (next.race_stage == evaluated.race_stage && next.race_timeout == evaluated.race_timeout) return;
  for (Individual& ind : next.individuals) ind.evaluated = false;
}

std::unique_ptr<Problem> scheduled_problem(const Problem& run_problem, const Generation& g) {
  const auto* race = dynamic_cast<const RaceProblem*>(&run_problem);
  if (race == nullptr || (g.race_timeout == 0 && g.race_stage == 0)) return nullptr;
  return std::make_unique<RaceProblem>(race->at_stage(g.race_stage).with_adaptive_timeout(g.race_timeout));
}

std::unique_ptr<Problem> final_problem(const std::filesystem::path& run_dir, const RunConfig& config) {
  std::unique_ptr<Problem> problem = problem_of(config);
  const auto* race = dynamic_cast<const RaceProblem*>(problem.get());
  if (race == nullptr || config.fitness.race.curriculum.empty()) return problem;
  const std::vector<int> saved = saved_generations(run_dir);
  if (saved.empty()) return problem;
  return std::make_unique<RaceProblem>(race->at_stage(read_saved_generation(run_dir, saved.back()).race_stage));
}

} // namespace sodaevo
