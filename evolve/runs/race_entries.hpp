// Races as `sodaevo race` runs them, as library calls: the contenders (files,
// race files' contenders or models in memory), their lanes on the race's terrain,
// the fused race of all of them, the replicas with sine jitter, the places and
// the JSON of `race --json`. The command line (app/race_command.cpp) and the
// Python module (python/) both call these, so both give the same results.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/model.hpp"
#include "core/model_def.hpp"
#include "core/race_def.hpp"
#include "core/race_lane.hpp"
#include "evolve/estimators/sample_summary.hpp"

namespace sodaevo {

struct RaceEntry {
  std::string file; ///< the contender's file, or the race file's contender "RACE#k"
  std::string name;
  soda::ModelDef model;
  soda::RaceOutcome outcome;
  std::string no_result; ///< why the racer gives this contender no result (contender_filter.hpp); empty: raced
  int place = 0;
  SampleSummary replicas; ///< the results of the jittered replicas, when asked for
  double replicas_finished = 0.0; ///< the share of those replicas that finish
};

/// The contenders of race file `race` read from `race_path`, or of the files
/// `contenders` (a model each, or a race file: its contenders). Readers' warnings
/// are appended to `warnings` (each a line for after "sodaevo: ", as the command
/// prints them). Throws soda::InputError.
std::vector<RaceEntry> load_race_entries(const std::string& race_path, const soda::RaceDef& race,
                                         const std::vector<std::string>& contenders,
                                         std::vector<std::string>& warnings);

/// An entry for a contender model held in memory, named `file` in results (and
/// by its model name, else `file`).
RaceEntry race_entry(const std::string& file, soda::ModelDef model);

/// Each entry's lane and lane model (empty for an entry the racer rejects).
struct RaceLanes {
  std::vector<soda::RaceLane> lanes;
  std::vector<soda::Model> models;
};

/// Builds the lanes. A contender the racer rejects gets `no_result` (or, with
/// `rejected_throws`, the rejection is thrown); a contender in several pieces
/// gets a warning. Throws soda::InputError when no contender can be raced.
RaceLanes build_race_lanes(const soda::RaceDef& race, std::vector<RaceEntry>& entries, bool rejected_throws,
                           std::vector<std::string>& warnings);

/// Races every entry that has a lane together (fused scenes: the same results as
/// one by one) and stores the outcomes.
void race_entries_together(const RaceLanes& lanes, int timeout, std::vector<RaceEntry>& entries);

/// The outcomes of `replicas` replicas of a lane with sine jitter `jitter` (seeds
/// of the check on fresh replicas, from the contender's genome: the same on every
/// run), on `threads` threads (0: all cores).
std::vector<soda::RaceOutcome> race_replica_outcomes(const soda::RaceLane& lane, const soda::Model& model, int timeout,
                                                     const soda::ModelDef& contender, int replicas, double jitter,
                                                     int threads);

/// The share of `outcomes` that finish (0 for none).
double finished_share(const std::vector<soda::RaceOutcome>& outcomes);

/// Races `replicas` jittered replicas of entry `e` (race_replica_outcomes) and
/// stores their summary and the share that finish.
void race_entry_replicas(RaceEntry& e, const soda::RaceLane& lane, const soda::Model& model, int timeout, int replicas,
                         double jitter, int threads);

/// The summary of replica outcomes' results (a race result is a frame count: the
/// interval is clipped at 0).
SampleSummary summarize_race_results(const std::vector<soda::RaceOutcome>& outcomes);

/// A result as `race` prints it: "123" frames to the finish, "10000.4600 (timeout)",
/// or "no result" (NaN).
std::string race_result_text(const soda::RaceOutcome& o);

/// Places: 1 for the lowest result; equal results share a place; no result, no place (0).
void assign_places(std::vector<RaceEntry>& entries);

/// What `race --json` prints: {"race", "timeout", "bar_engine", "contenders": [...]}.
nlohmann::json race_results_json(const std::string& race_path, int timeout, const std::vector<RaceEntry>& entries,
                                 int replicas, double jitter);

} // namespace sodaevo
