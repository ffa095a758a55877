// RaceFitnessConfig: the /fitness/race object of a run config (configs/README.md,
// "Race fitness"), read and checked here and embedded in FitnessConfig.
//
// A race run scores a creature by racing it, as the original Sodarace racer does
// (core/race_lane.hpp), on one or more terrains: race files named by path (relative
// to the config file) or bundled terrains named as in models/terrains/
// ("TerrainFlat"). The resolved config holds absolute paths. Parsing follows
// run_config.cpp's rules: strict, every problem collected, each naming the JSON
// pointer, what was expected and what was found.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "evolve/config/map_elites_config.hpp"

namespace sodaevo {

/// /fitness/kind: what a creature is scored on.
enum class FitnessKind { Walk, Race };
/// /fitness/race/combine: the score over several terrains.
enum class RaceCombine { Mean, Worst };
/// /fitness/race/score: what a search ranks racers by (evolve/problems/race_progress.hpp).
/// Racer: the original racer's result (frames, or timeout + the fraction left at
/// the last frame). Progress: files finished first, then frames on the finished
/// ones and the furthest ground held on the others.
enum class RaceScore { Racer, Progress };
std::string fitness_kind_name(FitnessKind k); ///< "walk", "race"
std::string race_combine_name(RaceCombine c); ///< "mean", "worst"
std::string race_score_name(RaceScore s);     ///< "racer", "progress"

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

/// Where a /fitness/race/terrains entry names a file: a path (relative to
/// `base_dir`) if one exists there, else a bundled terrain of that name (".xml"
/// optional) in models/terrains/ beside the config folder or the working directory.
/// Empty when neither exists.
std::filesystem::path find_race_terrain(const std::string& entry, const std::filesystem::path& base_dir);

/// Reads the /fitness/race object `value` over the defaults in `config`; appends
/// every problem (pointers absolute, "/fitness/race/..."). Each terrain is read as
/// a race file, so a bad one is reported with its pointer.
void read_race_fitness(const nlohmann::json& value, const std::filesystem::path& base_dir, RaceFitnessConfig& config,
                       std::vector<ConfigProblem>& problems);

/// What a race config contradicts: no terrains, /fitness/race with a walk, a race
/// with a step other than the original's (the racer runs its own: soda mode, no
/// energy or honesty check), or with MAP-Elites (`map_elites`, null for the GA)
/// placing creatures by a descriptor a race does not measure (race_describes).
std::vector<ConfigProblem> race_fitness_conflicts(FitnessKind kind, const RaceFitnessConfig& race, bool race_given,
                                                  const MapElitesConfig* map_elites, bool soda_mode);

/// The resolved /fitness/race object (every key).
nlohmann::json to_json(const RaceFitnessConfig& config);

} // namespace sodaevo
