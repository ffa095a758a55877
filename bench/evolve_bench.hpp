// The evolution benchmark: is the genetic algorithm worth having, and how good
// a walker does the default config find?
//
// Part 1 compares three search methods at an equal number of evaluations, each
// from the same initial distribution (the config's seed models and random
// creatures) and the same fitness, over several seeds:
//  - the GA of the config (tournament, elitism, mutation, optional crossover);
//  - random search: that many creatures drawn from the GA's initial distribution;
//  - a (1+1) hill climber: start from the GA's first initial creature, mutate with
//    the GA's operators, keep the child when it is at least as good.
// The GA's evaluation count is a whole number of generations; the others get
// exactly the same count. Reported: best fitness per method and seed, the median
// over seeds, and the median best-so-far curve against evaluations.
//
// Part 2 runs the config itself (all its generations) and reports its wall time,
// its champion's speed, and the Dainty Walker's speed under the same fitness
// settings in whichever wave direction walks the configured way best.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/model_def.hpp"
#include "evolve/config/run_config.hpp"

namespace sodaevo::bench {

/// Best-so-far fitness after each evaluation count (a step curve).
struct SearchCurve {
  std::vector<long long> evaluations;
  std::vector<double> best;
};

struct SearchRun {
  std::string method;       ///< "ga", "random", "hill"
  std::uint64_t seed = 0;
  long long evaluations = 0;
  double best_fitness = 0.0;
  double best_px_per_frame = 0.0;
  SearchCurve curve;
};

struct SearchComparisonOptions {
  RunConfig config;                    ///< GA settings, fitness, world; config.seed is ignored
  std::vector<soda::ModelDef> seed_creatures;
  std::vector<std::uint64_t> seeds = {1, 2, 3, 4, 5};
  int generations = 30;                ///< the GA's budget; the others get its evaluation count
  int threads = 0;                     ///< 0 = all cores
  std::function<void(const std::string&)> progress;
};

struct SearchComparison {
  std::vector<SearchRun> runs;
  long long evaluations = 0;           ///< per run, equal for all methods
};

SearchComparison compare_search_methods(const SearchComparisonOptions& options);

/// Best fitness a run had found after `evaluations` evaluations.
double best_after(const SearchRun& run, long long evaluations);

/// Median over the seeds of one method of best_after(run, evaluations).
double median_best(const SearchComparison& comparison, const std::string& method, long long evaluations);

/// The Dainty Walker (or any classic) under a config's fitness settings: its
/// speed with the wave as written and reversed, and the better of the two in the
/// configured direction.
struct ClassicSpeed {
  double forward_px_per_frame = 0.0;
  double reversed_px_per_frame = 0.0;
  double best_fitness_px_per_frame = 0.0; ///< best fitness / frames over both directions
};

ClassicSpeed classic_speed(const soda::ModelDef& classic, const RunConfig& config);

} // namespace sodaevo::bench
