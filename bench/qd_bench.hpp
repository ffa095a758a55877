// bench qd: MAP-Elites against the GA at equal evaluations (issue 28).
//
// For each seed, the config is run twice from the same initial creatures: as
// MAP-Elites (its /map_elites settings), then as the GA (its /population and
// /selection) with /budget/evaluations set to the evaluations MAP-Elites made
// (both count estimates: a creature's first one and each further one). The GA's
// last population is put into an archive of the same grid (its creatures
// estimated with their descriptors, inserted by the same rule), so both get a
// QD-score, a coverage and a best fitness from the same definitions
// (evolve/algorithms/grid_archive.hpp). MAP-Elites' archive is also checked on fresh
// replicas (evolve/runs/archive_check.hpp), and so is the GA's best creature: the
// best elite against the GA's best as each would walk on replicas that selection
// never saw.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "evolve/algorithms/grid_archive.hpp"
#include "evolve/config/run_config.hpp"

namespace sodaevo::bench {

struct QdOptions {
  RunConfig config;               ///< a MAP-Elites config
  std::string config_name;        ///< for the report ("configs/map_elites.json")
  std::vector<std::uint64_t> seeds{1, 2, 3, 4, 5};
  int iterations = 0;             ///< 0: the config's
  int check_replicas = 8;         ///< fresh replicas of the checks
  int threads = 0;
  std::filesystem::path work_dir; ///< run folders (replaced)
  std::function<void(const std::string&)> progress;
};

struct QdRow {
  std::uint64_t seed = 0;
  std::string algorithm;   ///< "map-elites" or "ga"
  long long evaluations = 0;
  QdMetrics metrics;       ///< as the run estimated (the GA: its last population as an archive)
  double best_checked = 0.0; ///< the best creature's checked mean fitness (MAP-Elites: the best checked elite)
  double seconds = 0.0;
};

std::vector<QdRow> run_qd_bench(const QdOptions& options);

std::string qd_csv(const std::vector<QdRow>& rows);
std::string qd_markdown(const std::vector<QdRow>& rows, const QdOptions& options, const std::string& command);
std::string qd_svg(const std::vector<QdRow>& rows);

} // namespace sodaevo::bench
