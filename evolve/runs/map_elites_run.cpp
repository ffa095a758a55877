#include "map_elites_run.hpp"

#include <algorithm>

#include <map>
#include <utility>

#include "evolve/runs/evolution_run.hpp"
#include "evolve/algorithms/genetic_algorithm.hpp"
#include "evolve/runs/run_roles.hpp"

namespace sodaevo {

WalkProblem map_elites_problem(const RunConfig& config, const MapElitesConfig& me) {
  return WalkProblem(config.fitness, config.world, config.limits, me.sample_every);
}


ResamplePlan map_elites_resample_plan(const ReplicaPlan& plan) { return {plan.replicas_max, plan.replicas}; }

ReplicaSampler replica_sampler(Evaluator& evaluator, const Problem& problem, const ReplicaEstimator& estimator) {
  return [&evaluator, &problem, &estimator](const std::vector<SampleRequest>& requests) {
    // One Estimator per replica range: its creatures are evaluated together.
    std::map<std::pair<long long, long long>, std::vector<std::size_t>> groups;
    for (std::size_t i = 0; i < requests.size(); ++i) groups[{requests[i].first, requests[i].count}].push_back(i);
    std::vector<Evaluation> results(requests.size());
    for (const auto& [range, who] : groups) {
      std::vector<const soda::ModelDef*> creatures;
      for (std::size_t i : who) creatures.push_back(requests[i].creature);
      const ReplicaEstimator more =
          estimator.on_replicas(static_cast<int>(range.first), static_cast<int>(range.second));
      std::vector<Evaluation> r = evaluator.evaluate(creatures, problem, more);
      for (std::size_t k = 0; k < who.size(); ++k) results[who[k]] = std::move(r[k]);
    }
    return results;
  };
}

namespace {

std::vector<Challenger> evaluate_children(std::vector<Individual> children, Evaluator& evaluator,
                                          const Problem& problem, const ReplicaEstimator& estimator) {
  std::vector<const soda::ModelDef*> creatures;
  for (const Individual& c : children) creatures.push_back(&c.creature);
  std::vector<Evaluation> results = evaluator.evaluate(creatures, problem, estimator);
  std::vector<Challenger> out;
  for (std::size_t i = 0; i < children.size(); ++i) out.push_back({std::move(children[i]), std::move(results[i])});
  return out;
}

} // namespace

MapElitesOutcome run_map_elites(const std::filesystem::path& dir, const RunConfig& config, const MapElitesConfig& me,
                                Evaluator& evaluator, const MapElitesOptions& options) {
  RunClock clock;
  ArchiveStore store(dir);
  GridArchive archive(me.axes);
  const std::unique_ptr<Problem> scored = problem_of(config, me.sample_every);
  const Problem& problem = *scored;
  const ReplicaEstimator estimator(replica_plan(config));
  const ResamplePlan resample = map_elites_resample_plan(estimator.plan());
  const ReplicaSampler sample = replica_sampler(evaluator, problem, estimator);
  // Evaluates a batch of children and inserts them, counting what it cost.
  auto evaluate_and_insert = [&](std::vector<Individual> children, int t, ArchiveCheckpoint& s) {
    std::vector<Challenger> challengers = evaluate_children(std::move(children), evaluator, problem, estimator);
    s.evaluations += static_cast<long long>(challengers.size());
    s.rollouts += static_cast<long long>(challengers.size()) * estimator.plan().replicas;
    const InsertionCounts counts = insert_challengers(archive, std::move(challengers), t, resample, sample);
    s.evaluations += counts.resampled;
    s.rollouts += counts.resampled_rollouts;
    return counts;
  };
  MapElitesOutcome outcome;
  ArchiveCheckpoint state;
  if (std::optional<ArchiveCheckpoint> checkpoint = store.read_checkpoint(archive)) {
    state = *checkpoint;
    store.truncate_after(state.iteration);
  } else {
    const InsertionCounts counts =
        evaluate_and_insert(initial_generation(config, load_seed_creatures(config)).individuals, 0, state);
    store.truncate_after(-1);
    store.record_iteration(0, state, archive.metrics(me.qd_offset), counts);
    store.write_snapshot(archive, me, 0);
    store.write_checkpoint(archive, state);
  }
  clock.carry_over(state.wall_seconds);
  auto wall = [&] { return clock.seconds(); };

  for (;;) {
    const bool no_room =
        config.budget.max_evaluations > 0 && state.evaluations + me.batch_size > config.budget.max_evaluations;
    if (const std::optional<StopReason> stop = stop_before_next_step(state.iteration >= me.iterations, no_room,
                                                                     config.budget, clock, options.stop_requested)) {
      state.wall_seconds = wall();
      store.write_checkpoint(archive, state);
      store.write_snapshot(archive, me, state.iteration);
      store.write_archive(archive, *problem_of(config, 0), config, me, state.iteration);
      outcome.stopped_because = *stop;
      outcome.last_iteration = state.iteration;
      outcome.evaluations = state.evaluations;
      outcome.rollouts = state.rollouts;
      outcome.metrics = archive.metrics(me.qd_offset);
      return outcome;
    }
    const int t = state.iteration + 1;
    const InsertionCounts counts = evaluate_and_insert(map_elites_children(config, me, archive, t), t, state);
    state.iteration = t;
    const QdMetrics metrics = archive.metrics(me.qd_offset);
    store.record_iteration(t, state, metrics, counts);
    if (me.snapshot_every > 0 && t % me.snapshot_every == 0) store.write_snapshot(archive, me, t);
    if (t % config.save.checkpoint_every == 0) {
      state.wall_seconds = wall();
      store.write_checkpoint(archive, state);
    }
    if (options.on_iteration) {
      options.on_iteration({t, me.iterations, state.evaluations, state.rollouts, metrics, counts, wall()});
    }
  }
}

} // namespace sodaevo
