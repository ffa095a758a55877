// The race's schedule over a GA run's generations: wodka's adaptive timeout
// (/fitness/race/timeout_factor). Generation g + 1 races with a timeout of the
// factor times the frames of generation g's best racer (rounded up), so slow
// creatures are cut off early while the best one still finishes; never longer
// than /fitness/race/timeout or the race file's own.
//
// The timeout is a function of the previous generation alone and is saved with
// each generation (Generation::race_timeout, the saved generation's XML and so the
// checkpoint), so resume and replay race every generation with the timeout it was
// scored with, on any thread or process count. When the timeout changes, the
// elites are scored again: results under two timeouts do not compare.
#pragma once

#include <memory>

#include "evolve/population.hpp"
#include "evolve/problem.hpp"
#include "evolve/run_config.hpp"

namespace sodaevo {

/// The timeout the generation after `evaluated` races with: ceil(factor x the
/// frames of its best creature), at least 1; evaluated.race_timeout when no
/// creature was scored; 0 (the run's) without a factor.
int next_race_timeout(const RunConfig& config, const Generation& evaluated);

/// Sets next.race_timeout from `evaluated`; when it changed, every individual of
/// `next` is to be evaluated again.
void schedule_race(const RunConfig& config, const Generation& evaluated, Generation& next);

/// The problem generation `g` is scored with: null when it is `run_problem` itself
/// (no adaptive timeout), else the RaceProblem with g's timeout.
std::unique_ptr<Problem> scheduled_problem(const Problem& run_problem, const Generation& g);

} // namespace sodaevo
