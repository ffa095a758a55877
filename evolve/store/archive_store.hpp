// ArchiveStore: the MAP-Elites files of a run folder (beside RunStore's
// config.json and manifest.json):
//
//   archive.json            the archive: its grid, QD metrics, the sine that scored
//                           it (evolve/store/run_sine.hpp), and per filled cell
//                           the elite's id, bins, fitness estimate (n, mean, sd),
//                           exact-run distance, descriptor means and its XML file
//   elites/<id>.xml         every elite of the final archive, prepared as evaluated
//                           (plain SodaConstructor XML)
//   snapshots/archive_NNNNN.json  archive.json as it was after iteration N, every
//                           /map_elites/snapshot_every iterations
//   qd.csv                  one row per iteration: iteration, evaluations, filled,
//                           coverage_percent, qd_score, normalized_qd_score, best,
//                           mean_fitness, entered, replaced, rollouts (cumulative
//                           replicas simulated), resampled (further estimates this
//                           iteration), evicted
//   archive_checkpoint.json everything --resume needs: the iteration, evaluations,
//                           wall time, the sine that scored it and every elite with its estimates (doubles
//                           written to round-trip exactly) and genome
//
// Every file is written atomically, as RunStore's.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "evolve/algorithms/grid_archive.hpp"
#include "evolve/algorithms/map_elites.hpp"
#include "evolve/config/run_config.hpp"
#include "evolve/problems/problem.hpp"

namespace sodaevo {

struct ArchiveCheckpoint {
  int iteration = 0;           ///< the last finished iteration (0 = initial population)
  long long evaluations = 0;   ///< cumulative
  long long rollouts = 0;      ///< cumulative
  double wall_seconds = 0.0;   ///< cumulative
};

/// QD metrics as archive.json's /metrics holds them.
nlohmann::json metrics_to_json(const QdMetrics& m);

/// The archive as archive.json holds it (cells in order).
nlohmann::json archive_to_json(const GridArchive& archive, const MapElitesConfig& me, int iteration);

/// File name of an elite's XML ("elites/i3-17.xml" relative to the run folder).
std::string elite_file(const std::string& id);

class ArchiveStore {
 public:
  explicit ArchiveStore(std::filesystem::path dir) : dir_(std::move(dir)) {}

  /// Appends the row of an iteration to qd.csv (rewritten whole, atomically).
  void record_iteration(int iteration, const ArchiveCheckpoint& totals, const QdMetrics& m,
                        const InsertionCounts& counts);
  /// Drops qd.csv rows after `iteration` (resume), keeping the others in memory.
  void truncate_after(int iteration);
  void write_snapshot(const GridArchive& archive, const MapElitesConfig& me, int iteration) const;
  /// archive.json and elites/ (replaced whole: elites no longer in the archive go),
  /// each elite as `exporter` (the run's Problem) gives its file: the store never
  /// prepares a creature itself.
  void write_archive(const GridArchive& archive, const Problem& exporter, const RunConfig& config,
                     const MapElitesConfig& me, int iteration) const;
  void write_checkpoint(const GridArchive& archive, const ArchiveCheckpoint& c) const;
  /// The checkpoint's state, its elites placed into `archive` (empty, of the run's
  /// grid); nullopt if there is none. Throws InputError naming the file if corrupt.
  [[nodiscard]] std::optional<ArchiveCheckpoint> read_checkpoint(GridArchive& archive) const;

 private:
  std::filesystem::path dir_;
  std::vector<std::pair<int, std::string>> rows_; ///< (iteration, qd.csv row)
};

} // namespace sodaevo
