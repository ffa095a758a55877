#include "evolution_run.hpp"

#include <algorithm>
#include <chrono>

#include "core/input_error.hpp"
#include "evolve/runs/race_schedule.hpp"
#include "evolve/runs/run_budget.hpp"
#include "evolve/runs/run_roles.hpp"
#include "evolve/algorithms/variation.hpp"
#include "formats/model_file.hpp"

namespace sodaevo {

std::vector<soda::ModelDef> load_seed_creatures(const RunConfig& config) {
  std::vector<soda::ModelDef> seeds;
  for (std::size_t i = 0; i < config.population.seed_models.size(); ++i) {
    const std::string& path = config.population.seed_models[i];
    try {
      seeds.push_back(creature_from_seed(soda::read_model_file(path).def, config));
    } catch (const soda::InputError& e) {
      throw soda::InputError(std::string(e.what()) + " (seed model " + path + ", /population/seed_models/" +
                             std::to_string(i) + ")");
    }
  }
  return seeds;
}

RunStore start_run(const RunConfig& config, const std::string& source, const std::filesystem::path& dir, bool force,
                   const std::string& command_line) {
  try {
    load_seed_creatures(config);
  } catch (const soda::InputError& e) {
    throw soda::InputError(source + ": " + e.what());
  }
  return RunStore::create(dir, config, force, command_line);
}

EvolutionOutcome run_evolution(RunStore& store, Evaluator& evaluator, const EvolutionOptions& options) {
  const RunConfig& config = store.config();
  const RunRoles roles = roles_of(config);
  using Clock = std::chrono::steady_clock;
  RunClock clock;
  EvolutionOutcome outcome;

  Generation current;
  long long evaluations = 0;
  bool need_evaluation = true;
  bool rescoring = false; // the checkpoint's generation, scored again (options.rescore_checkpoint)
  if (std::optional<Checkpoint> checkpoint = store.read_checkpoint()) {
    store.truncate_logs_after(checkpoint->generation.index);
    current = std::move(checkpoint->generation);
    evaluations = checkpoint->evaluations;
    clock.carry_over(checkpoint->wall_seconds);
    need_evaluation = false; // the checkpoint holds an evaluated generation
    outcome.last_generation = current.index;
    if (options.rescore_checkpoint) {
      for (Individual& ind : current.individuals) ind.evaluation = {}, ind.evaluated = false;
      need_evaluation = rescoring = true;
    }
  } else {
    current = roles.algorithm->first(load_seed_creatures(config));
  }
  auto wall = [&] { return clock.seconds(); };

  // The evaluation budget stops the run before a generation it has no room for
  // (its children, then the final confirmation, /fitness/confirm).
  const long long limit = config.budget.max_evaluations;
  const auto no_room_after = [&](long long spent) {
    return limit > 0 && spent + roles.algorithm->evaluations_per_generation() + config.fitness.confirm > limit;
  };
  for (;;) {
    if (need_evaluation) {
      const auto t0 = Clock::now();
      // The generation's race timeout (/fitness/race/timeout_factor; evolve/runs/race_schedule.hpp).
      const std::unique_ptr<Problem> scheduled = scheduled_problem(*roles.problem, current);
      const Problem& problem = scheduled ? *scheduled : *roles.problem;
      long long done = evaluate_generation(evaluator, current, problem, *roles.estimator);
      // The generation the run ends with (by its budget of generations or of
      // evaluations: known now, so that a resumed run does the same) hands over its
      // best: they are confirmed on more replicas first, within the budget (the
      // last generation leaves room for the confirmation's first round).
      const bool last = current.index + 1 >= config.budget.generations || no_room_after(evaluations + done);
      if (last) {
        done += confirm_best(evaluator, current, problem, *roles.estimator, config.fitness.confirm,
                             limit > 0 ? std::max(0LL, limit - evaluations - done) : -1);
      }
      const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
      evaluations += done;
      const GenerationStats stats = summarize(current, evaluations);
      // A generation scored again (rescore_checkpoint) replaces its saved file of the old sine.
      const bool save_whole = last || rescoring ||
                              (config.save.generation_every > 0 && current.index % config.save.generation_every == 0);
      std::optional<soda::ModelDef> best_file;
      if (stats.best_index >= 0) {
        const Individual& best = current.individuals[static_cast<std::size_t>(stats.best_index)];
        best_file = problem.export_form(best.creature, best.id, best.evaluation);
      }
      store.record_generation(current, stats, wall(), seconds, done, save_whole, best_file);
      // Scored again: checkpointed at once, the checkpoint naming the sine that scored it.
      if (last || rescoring || current.index % config.save.checkpoint_every == 0) {
        store.write_checkpoint({current, evaluations, wall(), {}});
      }
      outcome.last_generation = current.index;
      rescoring = false;
      if (options.on_generation) {
        options.on_generation({current.index, config.budget.generations, stats, wall(),
                               seconds > 0 ? static_cast<double>(done) / seconds : 0.0});
      }
    }
    need_evaluation = true;

    // The evaluation budget's verdict is the one `last` above foresaw.
    if (const std::optional<StopReason> stop =
            stop_before_next_step(current.index + 1 >= config.budget.generations, no_room_after(evaluations),
                                  config.budget, clock, options.stop_requested)) {
      // Whatever stopped the run, the last generation is saved whole and checkpointed.
      const GenerationStats stats = summarize(current, evaluations);
      store.write_checkpoint({current, evaluations, wall(), {}});
      store.save_generation(current);
      outcome.stopped_because = *stop;
      outcome.evaluations = evaluations;
      if (stats.best_index >= 0) {
        outcome.best_id = current.individuals[static_cast<std::size_t>(stats.best_index)].id;
        outcome.best_fitness = stats.best;
      }
      return outcome;
    }
    Generation next = roles.algorithm->next(current);
    schedule_race(config, current, next);
    current = std::move(next);
  }
}

} // namespace sodaevo
