// The race's schedule over a GA run's generations, as wodka raced:
// - the adaptive timeout (/fitness/race/timeout_factor): generation g + 1 races
//   with a timeout of the factor times the frames of generation g's best racer
//   (rounded up), so slow creatures are cut off early while the best one still
//   finishes; never longer than /fitness/race/timeout or the race file's own;
// - the curriculum (/fitness/race/curriculum): generation g + 1 races the next
//   stage's terrain when generation g's best racer finished in fewer frames than
//   its stage's threshold; the first generation on a new terrain races with the
//   run's timeout (the old terrain's frames say nothing about the new one).
//
// Both are functions of the previous generation alone and are saved with each
// generation (Generation::race_timeout and race_stage, the saved generation's XML
// and so the checkpoint), so resume and replay race every generation as it was
// scored, on any thread or process count. When either changes, the elites are
// scored again: results under two timeouts or on two terrains do not compare.
#pragma once

#include <filesystem>
#include <memory>

#include "evolve/algorithms/population.hpp"
#include "evolve/problems/problem.hpp"
#include "evolve/config/run_config.hpp"

namespace sodaevo {

/// The timeout the generation after `evaluated` races with: ceil(factor x the
/// frames of its best creature), at least 1; evaluated.race_timeout when no
/// creature was scored; 0 (the run's) without a factor.
int next_race_timeout(const RunConfig& config, const Generation& evaluated);

/// The curriculum stage the generation after `evaluated` races.
int next_race_stage(const RunConfig& config, const Generation& evaluated);

/// Sets next.race_stage and race_timeout from `evaluated`; when either changed,
/// every individual of `next` is to be evaluated again.
void schedule_race(const RunConfig& config, const Generation& evaluated, Generation& next);

/// The problem generation `g` is scored with: null when it is `run_problem` itself
/// (stage 0, no adaptive timeout), else the RaceProblem on g's stage with g's timeout.
std::unique_ptr<Problem> scheduled_problem(const Problem& run_problem, const Generation& g);

/// The problem a finished run's champions are checked and exported on: the run's,
/// on the curriculum stage of its last saved generation (with the run's timeout).
std::unique_ptr<Problem> final_problem(const std::filesystem::path& run_dir, const RunConfig& config);

} // namespace sodaevo
