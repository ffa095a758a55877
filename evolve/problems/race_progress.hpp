// The score a racer search ranks by (/fitness/race/score "progress"), beside the
// original racer's result, which stays what is logged, exported and reported.
//
// Why a second score: the racer's result for a racer that times out is timeout +
// the fraction of the way left, taken at the last frame only and with the racer's
// width in the denominator. A racer that climbs race08's ramp and slides back then
// scores like one that never moved, and stretching counts as progress. A mean of
// results over several files trades a finish on one for frames on another. So:
// - progress on a file is the furthest its trailing mass (the least x, which is
//   what must pass the finish) got along the track, from where it started to the
//   finish line, over the whole race (soda::RaceOutcome::furthest_min_x);
// - files are ordered lexicographically: more files finished always ranks higher;
//   then frames on the finished files plus, on each unfinished one, a cost between
//   one and two timeouts that falls as progress grows.
// With replicas, the estimator's mean over them keeps the same order for the share
// of replicas that finish, so a fragile racer ranks below a steady one.
#pragma once

#include <vector>

#include "core/race_lane.hpp"

namespace sodaevo {

/// One terrain's race as the progress score sees it.
struct TerrainRaceResult {
  double result = 0.0;  ///< the racer's result (frames, or timeout + fraction)
  bool finished = false;
  int timeout = 0;      ///< the timeout raced
  double progress = 0.0; ///< track_progress, in [0, 1]
};

/// How far along the track the racer got: (furthest least x - its least x at the
/// start) over (the finish line - its least x at the start), clamped to [0, 1];
/// 0 for a non-finite furthest. The finish line is the finish node's x + 6 (the
/// racer's finish rule, soda::passed_finish).
double track_progress(const soda::RaceLane& lane, double start_min_x, double furthest_min_x);

/// The search cost of one rollout over its terrains (lower is better):
/// unfinished x W + sum over terrains of (frames if finished, else
/// (timeout + 1) x (2 - progress)), with W = 1 + sum of 2 (timeout + 1), so one
/// more finished file outweighs everything else. Fitness is its negative.
double progress_cost(const std::vector<TerrainRaceResult>& races);

} // namespace sodaevo
