// A Sodarace lane and its race, as the original headless racer (2004) runs them
// (docs/physics.md, "The lane"): the terrain's fixed nodes and bars moved
// to start at x = 50000 between two flat platforms, the contender scaled to half its
// own container's height and placed left of the start, then frames until the
// contender's integer box passes the finish or the timeout.
//
// A lane is a plain ModelDef (the racer's lane model at frame 0, as the golden lanes
// write it), stepped with the 2004 racer's bar rule (BarEngine::Racer2004).
#pragma once

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "contender_filter.hpp"
#include "model.hpp"
#include "race_def.hpp"

namespace soda {

/// The racer's platform on either side of the terrain (Racer.PLATFORM_WIDTH).
inline constexpr double kRacePlatformWidth = 50000.0;

struct RaceLane {
  ModelDef def;          ///< nodes: terrain, two platform nodes, the contender's masses
  double start_x = 0, start_y = 0;   ///< the start node, lane coordinates
  double finish_x = 0, finish_y = 0; ///< the finish node, lane coordinates
  double scale = 1.0;    ///< the contender's scale factor s (+inf: the kept links' lengths sum to 0)
  int contender_masses = 0; ///< free masses in the contender's file
  int contender_pieces = 0; ///< its connected pieces; the lane holds the largest (contender_filter.hpp)
};

/// Builds the lane for `contender` on `terrain` (a race's terrain model) under the
/// race constraints, the contender filtered as the racer does (contender_filter.hpp:
/// its largest piece, scaled). Throws ContenderRejected naming `contender_name`
/// where the racer gives no result (a fixed node last in <nodes>).
RaceLane build_lane(const ModelDef& terrain, const RaceConstraints& constraints, const ModelDef& contender,
                    const std::string& contender_name);

/// The lane's model, stepped with the racer's (2004) fixed-bar rule. The racer
/// checks no range: the lane's gravity may exceed 4 and a contender scaled by +inf
/// has infinite or NaN numbers; the model keeps them (the race then gives the
/// racer's timeout formula). Links from a mass to itself are left out of the model:
/// the engine skips a link of length 0.
Model build_lane_model(const RaceLane& lane);

struct RaceOutcome {
  double result = 0.0;   ///< the racer's float: frames to finish, or timeout + fraction
  bool finished = false;
  long long updates = 0; ///< physics updates run
  /// The furthest the contender's least x came in the race: the most of its free
  /// masses' least x over the frames raced, the state it started from included. Not
  /// part of the racer's result (which takes the last frame only); a search credits
  /// the ground a racer held before it slid back (evolve/problems/race_progress.hpp).
  double furthest_min_x = -std::numeric_limits<double>::infinity();
};

/// The least x of `model`'s free masses in `state` (the racer's box's left edge).
double least_x(const Model& model, const State& state);

/// Java's (int) of a double: truncation toward zero, NaN to 0, saturated.
int java_int(double v);

/// The racer's finish rule (docs/physics.md, "The finish and the result"): the
/// contender's least x, as Java's (int), is past the finish node's x + 6.
bool passed_finish(const RaceLane& lane, double min_x);

/// The race result after update `updates` if the race ends there (docs/physics.md,
/// "The finish and the result"), given the contender's min and max x. Finish first:
/// (int)min x > finish.x + 6 gives updates - 2; else updates - 2 > timeout gives (float)(timeout + fraction).
bool race_ends(const RaceLane& lane, int timeout, long long updates, double min_x, double max_x, RaceOutcome& out);

/// Runs the lane from frame 0 until the race ends. `on_frame`, if given, sees the
/// state after every update (for traces and drawings).
RaceOutcome run_race(const RaceLane& lane, const Model& model, int timeout,
                     const std::function<void(const State&)>& on_frame = {});

/// Runs the lane from `state` (a fresh state of `model`, possibly with sine
/// jitter) until the race ends, with the same result and final state as run_race
/// (the reference step) gives that state: the fast stepper, the finish watched
/// after every frame (FastStepper::run_until). A state partway through its race
/// (state.frame updates run) goes on from there. With `every` > 0 and `observe`,
/// `observe` sees the state after every `every` frames and after the last one (the
/// same result and final state).
RaceOutcome run_race_fast(const RaceLane& lane, const Model& model, int timeout, State& state, long long every = 0,
                          const std::function<void(const State&)>& observe = {});

/// run_race_fast for each of `states` (fresh states of `model`: race replicas, each
/// with its own sine jitter), the same results and final states, bit for bit: the
/// replicas in lockstep lanes (lockstep_batch.hpp; lockstep_share of them) where
/// the CPU has AVX2 or AVX-512, the rest one by one.
std::vector<RaceOutcome> run_races_fast(const RaceLane& lane, const Model& model, int timeout,
                                        const std::vector<State*>& states);

/// One race of run_races_together: a contender's lane, the lane's model, the
/// timeout, and a fresh state of the model (possibly with sine jitter).
struct LaneRace {
  const RaceLane* lane = nullptr;
  const Model* model = nullptr;
  int timeout = 0;
  State* state = nullptr;
};

/// run_race_fast for each race, the same results and final states, bit for bit,
/// the races run together: replicas (fresh states of one lane model: the same lane,
/// model and timeout) in lockstep lanes by whole groups where the CPU has AVX2 or AVX-512
/// (run_races_fast), the others, different contenders on any terrains, in fused
/// scenes (fused_scene.hpp), each stopping at its own finish or timeout. When fewer
/// than three quarters of a scene are still running, the rest go on in a smaller
/// scene; the last one alone.
std::vector<RaceOutcome> run_races_together(const std::vector<LaneRace>& races);

} // namespace soda
