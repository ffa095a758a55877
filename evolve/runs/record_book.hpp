// The record book (`sodaevo records`, results/records/): for every race file, the
// best of our racers against every public contender, raced as the original racer
// races them (evolve/runs/race_entries.hpp), and one generalist over all files.
//
// Why records are chosen this way: a record must hold on another machine's sine,
// not only on this one's. So on each file our racers that finish are taken fastest
// first, and the first whose jittered replicas finish at least `qualify` of the
// time (16 replicas, core/sine_jitter.hpp) holds the record; when none does, the
// fastest finisher is listed as not qualified. The generalist is the racer that
// finishes the most files (then the fewest frames over them), with its replicas on
// every file.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "evolve/runs/race_entries.hpp"
#include "evolve/estimators/sample_summary.hpp"

namespace sodaevo {

struct RecordBookInputs {
  std::vector<std::string> race_files; ///< race files, in the book's order
  std::vector<std::string> candidates; ///< our racers (contender files)
  std::vector<std::string> publics;    ///< public contenders (contender files, or race files: their contenders)
  int replicas = 16;                   ///< jittered replicas per record racer and file
  double jitter = 0.002;               ///< share of sines a replica moves by 1 ulp
  double qualify = 0.9;                ///< share of replicas that must finish for a record
  int threads = 0;                     ///< 0: all cores
};

/// A racer's jittered replicas on one file.
struct ReplicaRecord {
  std::vector<soda::RaceOutcome> outcomes;
  SampleSummary summary;
  double finished_share = 0.0;
};

/// One race file of the book.
struct FileRecord {
  std::string race_file; ///< as given
  int timeout = 0;       ///< the race file's
  std::vector<RaceEntry> candidates, publics; ///< raced, in input order
  int record = -1;       ///< index into candidates; -1: none of ours finishes
  bool qualified = false; ///< the record's replicas finish at least `qualify` of the time
  ReplicaRecord record_replicas;
  int best_public = -1;  ///< index into publics of the least result (finished or not); -1: none raced
};

struct Generalist {
  int candidate = -1; ///< index into RecordBookInputs::candidates; -1: no candidates
  int files_finished = 0;
  std::vector<ReplicaRecord> replicas; ///< per file (empty: replicas not run)
};

struct RecordBook {
  std::vector<FileRecord> files;
  Generalist generalist;
};

/// Races the book. `progress(done, total, what)` is told as files are raced.
/// Readers' warnings go to `warnings`. Throws soda::InputError for a file that
/// does not read.
RecordBook compile_record_book(const RecordBookInputs& inputs, std::vector<std::string>& warnings,
                               const std::function<void(int, int, const std::string&)>& progress = {});

} // namespace sodaevo
