// RaceFitnessConfig: the /fitness/race object of a run config (configs/README.md,
// "Race fitness"), the settings a RaceProblem is constructed from: its terrains,
// how their results combine, its timeout and curriculum. config/race_fitness_config.hpp
// reads and checks it.
#pragma once

#include <string>
#include <vector>

#include "core/enum_names.hpp"

namespace sodaevo {

/// /fitness/race/combine: the score over several terrains.
enum class RaceCombine { Mean, Worst };
inline constexpr soda::EnumName<RaceCombine> kRaceCombineNames[] = {{RaceCombine::Mean, "mean"},
                                                                   {RaceCombine::Worst, "worst"}};
inline std::string race_combine_name(RaceCombine c) { return soda::name_of(kRaceCombineNames, c); }
/// /fitness/race/score: what a search ranks racers by (race_progress.hpp).
/// Racer: the original racer's result (frames, or timeout + the fraction left at
/// the last frame). Progress: files finished first, then frames on the finished
/// ones and the furthest ground held on the others.
enum class RaceScore { Racer, Progress };
inline constexpr soda::EnumName<RaceScore> kRaceScoreNames[] = {{RaceScore::Racer, "racer"},
                                                               {RaceScore::Progress, "progress"}};
inline std::string race_score_name(RaceScore s) { return soda::name_of(kRaceScoreNames, s); }

/// One stage of /fitness/race/curriculum: its terrain (a race file, absolute once
/// resolved) and the result (frames) under which the best racer moves the run on
/// to the next stage (unused on the last).
struct CurriculumStage {
  std::string terrain;
  double threshold = 0.0;

  bool operator==(const CurriculumStage&) const = default;
};

/// Most stages /fitness/race/curriculum takes (stage indices 0 to 63).
inline constexpr int kMaxCurriculumStages = 64;

struct RaceFitnessConfig {
  std::vector<std::string> terrains; ///< /fitness/race/terrains: race files, absolute paths once resolved
  RaceCombine combine = RaceCombine::Mean;
  /// /fitness/race/score. The logged frames (Evaluation::distance) are the racer's
  /// result under either; only the fitness differs.
  RaceScore score = RaceScore::Racer;
  /// /fitness/race/timeout: frames, [0, 49997]; 0 = each race file's own timeout.
  /// A shorter one makes evaluations cheaper: a creature that does not finish still
  /// scores timeout + the fraction of the way it had left.
  int timeout = 0;
  /// /fitness/race/timeout_factor: 0 (off) or [1, 100]. As wodka did, a generation
  /// races with a timeout of this factor times the frames of the previous
  /// generation's best racer (rounded up; never above `timeout` or the file's):
  /// slow creatures are cut off early. Its timeout is saved with each generation
  /// (evolve/runs/race_schedule.hpp).
  double timeout_factor = 0.0;
  /// /fitness/race/curriculum: 1 to 64 stages instead of `terrains` (as wodka's hill
  /// curriculum): the run races stage 0's terrain until a generation's best racer
  /// finishes in fewer frames than its threshold, then the next stage's. The stage
  /// is saved with each generation (evolve/runs/race_schedule.hpp).
  std::vector<CurriculumStage> curriculum;

  bool operator==(const RaceFitnessConfig&) const = default;
};

} // namespace sodaevo
