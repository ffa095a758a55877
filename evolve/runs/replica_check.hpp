// The check on fresh replicas: what an exported creature walks on replicas that
// were never used to select it.
//
// Why: the estimate a run selects on is the best of many noisy estimates, so it
// is biased up (the winner's curse). Re-running the creature on M replicas whose
// seeds selection never saw (ReplicaPurpose::Check) gives an unbiased picture of
// what it will do in the original program, which is one more draw: the check's
// 95 % prediction interval should contain that run 95 % of the time.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "evolve/algorithms/population.hpp"
#include "evolve/config/run_config.hpp"
#include "evolve/problems/problem.hpp"
#include "evolve/estimators/replica_estimator.hpp"
#include "evolve/estimators/sample_summary.hpp"

namespace sodaevo {

struct ReplicaCheck {
  std::string id;
  bool ok = false;          ///< false: a run failed (reason says which and why)
  std::string reason;
  double exact_distance = 0.0; ///< replica 0, the exact engine: what `simulate` of the export gives
  Estimate selection;          ///< as the run logged it (fitness units)
  SampleSummary check;         ///< distances of the M fresh replicas
  /// selection mean minus the mean fitness of the fresh replicas (fitness units:
  /// the distance for runs scored to the right).
  double winners_curse = 0.0;
};

/// Runs `individual` (its prepared model under `problem`) exactly and on
/// `replicas` fresh replicas (seeds of ReplicaPurpose::Check, jitter probability
/// from `plan`).
ReplicaCheck check_on_fresh_replicas(const Problem& problem, const Individual& individual, const ReplicaPlan& plan,
                                     int replicas);

/// check_on_fresh_replicas for each of `individuals`, on `threads` threads
/// (0 = all cores); result i belongs to individuals[i].
std::vector<ReplicaCheck> check_all_on_fresh_replicas(const Problem& problem, const std::vector<Individual>& individuals,
                                                      const ReplicaPlan& plan, int replicas, int threads);

/// The champions.json entry of a check: file, id, settle_frames, frames,
/// exact_distance, selection {n, mean, sd}, check {n, mean, median, sd, min, max,
/// interval95: [lo, hi]}, winners_curse.
nlohmann::json champion_json(const ReplicaCheck& c, const std::string& file, long long settle_frames,
                             long long frames);

/// champion_json for a run of `config`: a race's entry has, instead of the walk's
/// frames, "unit": "frames" and its "race" (/fitness/race): exact_distance and the
/// check are then race results in frames.
nlohmann::json champion_json(const ReplicaCheck& c, const std::string& file, const RunConfig& config);

/// The check of a run's `count` best creatures on `replicas` fresh replicas each,
/// written to RUN/champions.json (file "" for each: nothing exported); what the run
/// report's "Claimed against checked" shows. Returns the checks.
std::vector<ReplicaCheck> write_run_champions(const std::filesystem::path& run_dir, int count, int replicas,
                                              int threads);

/// One line for the exported XML's comment: the checked median and interval, in
/// `unit` (the score's: px for a walk, frames for a race); numbers round-trip, or
/// with `digits` decimals for reading (digits >= 0).
std::string check_comment(const ReplicaCheck& c, const std::string& unit = "px", int digits = -1);

/// A run's champion as `sodaevo export` writes it: the problem's export form of the
/// creature (what was scored, prepared), its check in the comment, into
/// OUT_DIR/rankNN_ID.xml (`rank` from 1). The file's name and path, the creature as
/// written, and its champions.json entry (champion_json).
struct ExportedChampion {
  std::string name;
  std::filesystem::path file;
  soda::ModelDef prepared;
  nlohmann::json entry;
};
ExportedChampion export_ranked_champion(const Problem& problem, const Individual& individual, const ReplicaCheck& check,
                                        const RunConfig& config, const std::string& unit,
                                        const std::filesystem::path& out_dir, int rank);

} // namespace sodaevo
