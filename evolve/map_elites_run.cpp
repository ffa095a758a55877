#include "map_elites_run.hpp"

#include <algorithm>
#include <chrono>

#include "core/batch_step.hpp"
#include "evolve/evaluator.hpp"
#include "evolve/evolution_run.hpp"
#include "evolve/genetic_algorithm.hpp"
#include "evolve/parallel_for.hpp"

namespace sodaevo {

DescribedEvaluator described_evaluator_on_threads(const RunConfig& config, const MapElitesConfig& me, int threads) {
  threads = resolve_thread_count(threads);
  return [config, sample_every = me.sample_every, threads](const std::vector<const soda::ModelDef*>& creatures) {
    std::vector<DescribedEvaluation> results(creatures.size());
    std::vector<int> links;
    for (const soda::ModelDef* c : creatures) links.push_back(static_cast<int>(c->links.size()));
    const std::vector<std::size_t> ends =
        soda::fused_batch_ends(links, evaluation_batch_size(creatures.size(), threads));
    parallel_for_index(ends.size(), threads, [&](std::size_t b) {
      const std::size_t first = b == 0 ? 0 : ends[b - 1], last = ends[b];
      const std::vector<const soda::ModelDef*> mine(creatures.begin() + static_cast<std::ptrdiff_t>(first),
                                                    creatures.begin() + static_cast<std::ptrdiff_t>(last));
      std::vector<DescribedEvaluation> scored = evaluate_described_creatures(mine, config, sample_every);
      for (std::size_t k = 0; k < scored.size(); ++k) results[first + k] = std::move(scored[k]);
    });
    return results;
  };
}

namespace {

/// Until replicas differ (the sine jitter of issue 26), every replica is the exact
/// run, so the archive compares one replica each.
constexpr long long kReplicaCap = 1;

std::vector<Challenger> evaluate_children(std::vector<Individual> children, const DescribedEvaluator& evaluate) {
  std::vector<const soda::ModelDef*> creatures;
  for (const Individual& c : children) creatures.push_back(&c.creature);
  std::vector<DescribedEvaluation> results = evaluate(creatures);
  std::vector<Challenger> out;
  for (std::size_t i = 0; i < children.size(); ++i) out.push_back({std::move(children[i]), std::move(results[i])});
  return out;
}

} // namespace

MapElitesOutcome run_map_elites(const std::filesystem::path& dir, const RunConfig& config, const MapElitesConfig& me,
                                const DescribedEvaluator& evaluate, const MapElitesOptions& options) {
  using Clock = std::chrono::steady_clock;
  const auto started = Clock::now();
  ArchiveStore store(dir);
  GridArchive archive(me.axes);
  const ReplicaSampler sample = [&](const soda::ModelDef& creature, long long, long long count) {
    return evaluate(std::vector<const soda::ModelDef*>(static_cast<std::size_t>(count), &creature));
  };
  MapElitesOutcome outcome;
  ArchiveCheckpoint state;
  if (std::optional<ArchiveCheckpoint> checkpoint = store.read_checkpoint(archive)) {
    state = *checkpoint;
    store.truncate_after(state.iteration);
  } else {
    std::vector<Challenger> first = evaluate_children(initial_generation(config, load_seed_creatures(config)).individuals,
                                                      evaluate);
    state.evaluations = static_cast<long long>(first.size());
    const InsertionCounts counts = insert_challengers(archive, std::move(first), 0, kReplicaCap, sample);
    state.evaluations += counts.resampled;
    store.truncate_after(-1);
    store.record_iteration(0, state.evaluations, archive.metrics(me.qd_offset), counts);
    store.write_snapshot(archive, me, 0);
    store.write_checkpoint(archive, state);
  }
  const double previous_wall = state.wall_seconds;
  auto wall = [&] { return previous_wall + std::chrono::duration<double>(Clock::now() - started).count(); };

  for (;;) {
    std::string stop;
    if (state.iteration >= me.iterations) stop = "completed";
    else if (config.budget.max_evaluations > 0 && state.evaluations + me.batch_size > config.budget.max_evaluations)
      stop = "evaluation budget";
    else if (config.budget.max_wall_seconds > 0 && wall() >= config.budget.max_wall_seconds) stop = "wall-time budget";
    else if (options.stop_requested != nullptr && options.stop_requested->load()) stop = "interrupted";
    if (!stop.empty()) {
      state.wall_seconds = wall();
      store.write_checkpoint(archive, state);
      store.write_snapshot(archive, me, state.iteration);
      store.write_archive(archive, config, me, state.iteration);
      outcome.stopped_because = stop;
      outcome.last_iteration = state.iteration;
      outcome.evaluations = state.evaluations;
      outcome.metrics = archive.metrics(me.qd_offset);
      return outcome;
    }
    const int t = state.iteration + 1;
    std::vector<Challenger> challengers = evaluate_children(map_elites_children(config, me, archive, t), evaluate);
    state.evaluations += static_cast<long long>(challengers.size());
    const InsertionCounts counts = insert_challengers(archive, std::move(challengers), t, kReplicaCap, sample);
    state.evaluations += counts.resampled;
    state.iteration = t;
    const QdMetrics metrics = archive.metrics(me.qd_offset);
    store.record_iteration(t, state.evaluations, metrics, counts);
    if (me.snapshot_every > 0 && t % me.snapshot_every == 0) store.write_snapshot(archive, me, t);
    if (t % config.save.checkpoint_every == 0) {
      state.wall_seconds = wall();
      store.write_checkpoint(archive, state);
    }
    if (options.on_iteration) {
      options.on_iteration({t, me.iterations, state.evaluations, metrics, counts, wall()});
    }
  }
}

} // namespace sodaevo
