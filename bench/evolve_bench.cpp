#include "evolve_bench.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>

#include "evolve/evaluators/evaluator.hpp"
#include "evolve/algorithms/genetic_algorithm.hpp"
#include "evolve/evaluators/parallel_for.hpp"
#include "evolve/algorithms/rng.hpp"
#include "evolve/runs/run_roles.hpp"
#include "evolve/algorithms/variation.hpp"

namespace sodaevo::bench {

namespace {

/// Stream purpose of the hill climber's mutations (apart from the GA's).
constexpr std::uint64_t kHillClimbPurpose = 101;

double fitness_or_worst(const Evaluation& e) { return e.ok() ? e.fitness : kWorstFitness; }

/// Adds the generation's results, in index order, to a best-so-far curve.
void extend_curve(SearchRun& run, const Generation& g, bool only_new) {
  for (const Individual& ind : g.individuals) {
    if (only_new && !ind.evaluated) continue;
    ++run.evaluations;
    const double f = fitness_or_worst(ind.evaluation);
    const double before = run.curve.best.empty() ? kWorstFitness : run.curve.best.back();
    if (run.curve.best.empty() || f > before) run.best_px_per_frame = ind.evaluation.px_per_frame;
    run.best_fitness = std::max(f, before);
    run.curve.evaluations.push_back(run.evaluations);
    run.curve.best.push_back(run.best_fitness);
  }
}

SearchRun run_ga(const SearchComparisonOptions& o, std::uint64_t seed, int threads) {
  RunConfig config = o.config;
  config.seed = seed;
  SearchRun run{"ga", seed, 0, kWorstFitness, 0.0, {}};
  ThreadEvaluator evaluator(threads);
  const RunRoles roles = roles_of(config);
  Generation g = initial_generation(config, o.seed_creatures);
  for (int gen = 0;; ++gen) {
    // Mark which individuals this generation actually evaluates (not the elites).
    std::vector<bool> fresh(g.individuals.size());
    for (std::size_t i = 0; i < fresh.size(); ++i) fresh[i] = !g.individuals[i].evaluated;
    evaluate_generation(evaluator, g, *roles.problem, *roles.estimator);
    Generation counted = g;
    for (std::size_t i = 0; i < fresh.size(); ++i) counted.individuals[i].evaluated = fresh[i];
    extend_curve(run, counted, true);
    if (gen + 1 >= o.generations) break;
    g = next_generation(config, g);
  }
  return run;
}

SearchRun run_random_search(const SearchComparisonOptions& o, std::uint64_t seed, long long evaluations,
                            int threads) {
  // One "initial generation" as large as the budget: the GA's initial
  // distribution, sampled `evaluations` times.
  RunConfig config = o.config;
  config.seed = seed ^ 0x5eed5eedULL; // different creatures from the GA's own generation 0
  config.population.size = static_cast<int>(evaluations);
  Generation g = initial_generation(config, o.seed_creatures);
  ThreadEvaluator evaluator(threads);
  const RunRoles roles = roles_of(config);
  evaluate_generation(evaluator, g, *roles.problem, *roles.estimator);
  SearchRun run{"random", seed, 0, kWorstFitness, 0.0, {}};
  extend_curve(run, g, false);
  return run;
}

SearchRun run_hill_climber(const SearchComparisonOptions& o, std::uint64_t seed, long long evaluations) {
  RunConfig config = o.config;
  config.seed = seed;
  config.population.size = 1;
  Generation start = initial_generation(config, o.seed_creatures);
  soda::ModelDef current = start.individuals.front().creature;
  Evaluation current_eval = evaluate_creature(current, config);
  SearchRun run{"hill", seed, 0, kWorstFitness, 0.0, {}};
  Generation one;
  one.individuals.resize(1);
  one.individuals[0].evaluation = current_eval;
  extend_curve(run, one, false);
  for (long long step = 1; step < evaluations; ++step) {
    Rng rng = Rng::stream(seed, kHillClimbPurpose, static_cast<std::uint64_t>(step));
    soda::ModelDef child = current;
    mutate(child, config, rng);
    const Evaluation child_eval = evaluate_creature(child, config);
    one.individuals[0].evaluation = child_eval;
    extend_curve(run, one, false);
    if (fitness_or_worst(child_eval) >= fitness_or_worst(current_eval)) {
      current = std::move(child);
      current_eval = child_eval;
    }
  }
  return run;
}

} // namespace

SearchComparison compare_search_methods(const SearchComparisonOptions& o) {
  SearchComparison result;
  auto say = [&](const std::string& s) {
    if (o.progress) o.progress(s);
  };
  std::vector<SearchRun> ga_runs;
  for (std::uint64_t seed : o.seeds) {
    ga_runs.push_back(run_ga(o, seed, o.threads));
    say("ga seed " + std::to_string(seed) + ": best " + std::to_string(ga_runs.back().best_fitness) + " after " +
        std::to_string(ga_runs.back().evaluations) + " evaluations");
  }
  result.evaluations = ga_runs.empty() ? 0 : ga_runs.front().evaluations;
  for (const SearchRun& r : ga_runs) result.evaluations = std::min(result.evaluations, r.evaluations);

  std::vector<SearchRun> random_runs;
  for (std::uint64_t seed : o.seeds) {
    random_runs.push_back(run_random_search(o, seed, result.evaluations, o.threads));
    say("random seed " + std::to_string(seed) + ": best " + std::to_string(random_runs.back().best_fitness));
  }
  // The hill climber is sequential: one seed per thread.
  std::vector<SearchRun> hill_runs(o.seeds.size());
  std::mutex say_mutex;
  parallel_for_index(o.seeds.size(), o.threads, [&](std::size_t i) {
    hill_runs[i] = run_hill_climber(o, o.seeds[i], result.evaluations);
    const std::lock_guard<std::mutex> lock(say_mutex);
    say("hill seed " + std::to_string(o.seeds[i]) + ": best " + std::to_string(hill_runs[i].best_fitness));
  });
  for (auto* runs : {&ga_runs, &random_runs, &hill_runs}) {
    for (SearchRun& r : *runs) result.runs.push_back(std::move(r));
  }
  return result;
}

double best_after(const SearchRun& run, long long evaluations) {
  const auto it = std::upper_bound(run.curve.evaluations.begin(), run.curve.evaluations.end(), evaluations);
  if (it == run.curve.evaluations.begin()) return kWorstFitness;
  return run.curve.best[static_cast<std::size_t>(it - run.curve.evaluations.begin()) - 1];
}

double median_best(const SearchComparison& comparison, const std::string& method, long long evaluations) {
  std::vector<double> v;
  for (const SearchRun& r : comparison.runs) {
    if (r.method == method) v.push_back(best_after(r, evaluations));
  }
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

ClassicSpeed classic_speed(const soda::ModelDef& classic, const RunConfig& config) {
  const soda::ModelDef forward = creature_from_seed(classic, config);
  soda::ModelDef reversed = forward;
  reversed.wave.speed = -reversed.wave.speed;
  const Evaluation ef = evaluate_creature(forward, config);
  const Evaluation er = evaluate_creature(reversed, config);
  ClassicSpeed s;
  s.forward_px_per_frame = ef.px_per_frame;
  s.reversed_px_per_frame = er.px_per_frame;
  const double frames = static_cast<double>(config.fitness.frames);
  s.best_fitness_px_per_frame = std::max(fitness_or_worst(ef), fitness_or_worst(er)) / frames;
  return s;
}

} // namespace sodaevo::bench
