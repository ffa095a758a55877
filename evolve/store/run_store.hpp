// RunStore: the run folder, the only place a run's results live.
//
//   config.json        the resolved config (every default filled in)
//   manifest.json      version, compiler, seed, start time, command line, and the
//                      engine's muscle sine (evolve/store/run_sine.hpp: replay, report and
//                      --resume check it)
//   generations.csv    generation,evaluations,best,mean,median,worst,invalid,diverged,best_id,
//                      best_replicas,best_sd,best_interval95_lo,best_interval95_hi (the best
//                      creature's replicas: their sd and the 95 % prediction interval of one more run)
//   timing.csv         generation,evaluations,wall_seconds,evaluations_per_second
//                      (apart, so everything else is byte-identical between runs)
//   best/gen_NNNNN.xml the best creature of each generation, prepared as evaluated
//                      (plain SodaConstructor XML the original runs the same way)
//   generations/gen_NNNNN.xml  whole saved generations: <generation> holding one
//                      SodaConstructor <model> per creature (the genome) with id,
//                      parents, status, fitness, distance and reason attributes
//   checkpoint.json    the last fully evaluated generation and the sine that scored
//                      it, for --resume
//
// Every file is written atomically (temporary file, then rename), so after a crash
// each file is either the old or the new version, complete.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/model_def.hpp"
#include "evolve/algorithms/population.hpp"
#include "evolve/config/run_config.hpp"

namespace sodaevo {

struct Checkpoint {
  Generation generation;       ///< evaluated
  long long evaluations = 0;   ///< cumulative
  double wall_seconds = 0.0;   ///< cumulative
  /// The sine that scored `generation` (core/sine_identity.hpp); empty: not
  /// recorded (written before the engine recorded it). Writing always records
  /// the engine's.
  std::string sine;
};

class RunStore {
 public:
  /// A new run folder. Refuses an existing non-empty folder unless `force` (then
  /// its run files are replaced). Writes config.json and manifest.json, and copies
  /// the seed models into seeds/, which config.json names relative to the folder:
  /// the folder is self-contained.
  static RunStore create(const std::filesystem::path& dir, const RunConfig& config, bool force,
                         const std::string& command_line);
  /// An existing run folder: reads config.json; the rows of the CSV logs after the
  /// checkpoint (written before a crash) are dropped.
  static RunStore open(const std::filesystem::path& dir);

  [[nodiscard]] const RunConfig& config() const { return config_; }
  [[nodiscard]] const std::filesystem::path& dir() const { return dir_; }

  /// Logs an evaluated generation: CSV rows, the whole generation if
  /// `save_whole`, and `best_file` (the best creature as its Problem exports it;
  /// none when no creature was scored) as best/gen_NNNNN.xml.
  void record_generation(const Generation& g, const GenerationStats& stats, double wall_seconds,
                         double generation_seconds, long long generation_evaluations, bool save_whole,
                         const std::optional<soda::ModelDef>& best_file);
  /// Writes generations/gen_NNNNN.xml for an evaluated generation.
  void save_generation(const Generation& g) const;
  void write_checkpoint(const Checkpoint& checkpoint);
  /// The checkpoint, or nullopt if none was written yet. Throws InputError if corrupt.
  [[nodiscard]] std::optional<Checkpoint> read_checkpoint() const;
  /// Drops log rows of generations after `generation` (used on resume).
  void truncate_logs_after(int generation);

 private:
  RunStore(std::filesystem::path dir, RunConfig config) : dir_(std::move(dir)), config_(std::move(config)) {}
  void write_logs() const;

  std::filesystem::path dir_;
  RunConfig config_;
  std::vector<std::pair<int, std::string>> generation_rows_; ///< (generation, csv row)
  std::vector<std::pair<int, std::string>> timing_rows_;
};

/// The current time in UTC as ISO 8601 ("2026-11-27T18:30:00Z"), for manifests.
std::string now_iso8601();

/// File name of generation g ("gen_00042.xml").
std::string generation_file_name(int generation);

/// A whole generation as XML text, and back. Creatures round-trip exactly.
std::string generation_to_xml(const Generation& g);
/// Throws InputError naming `source`, the line and column, the element, expected and got.
Generation generation_from_xml(const std::string& text, const std::string& source);

/// Parses the text of checkpoint.json. Strict: every key present with the right
/// type and range, no unknown or duplicate keys, the population a valid saved
/// generation. Throws InputError ("<source>: corrupt checkpoint: <pointer>: ...").
Checkpoint parse_checkpoint(const std::string& text, const std::string& source);

} // namespace sodaevo
