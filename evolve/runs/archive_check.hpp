// The corrected archive: every elite of a MAP-Elites run re-run on fresh replicas
// (seeds of ReplicaPurpose::Check, never used in selection), as `export` checks
// the GA's champions (evolve/runs/replica_check.hpp).
//
// Why: an elite is the best of the challengers its cell saw, each a noisy
// estimate, so its estimate is biased up (the winner's curse), the more so for
// cells that saw many challengers. The insertion rule compares comparable replica
// counts, which shrinks the bias; the check measures what is left. The checked
// archive has each elite at its checked mean fitness (a failed check empties the
// cell), and its QD metrics stand beside the run's.
//
// Written to RUN/archive_checked.json:
//   format, check_replicas, metrics {selection, checked} (as archive.json's),
//   mean_winners_curse, and per filled cell: cell, checked_fitness and the
//   champions.json entry of the check (file: the elite's XML in the run folder).
#pragma once

#include <cstddef>
#include <filesystem>
#include <vector>

#include <nlohmann/json.hpp>

#include "evolve/algorithms/grid_archive.hpp"
#include "evolve/algorithms/population.hpp"
#include "evolve/problems/problem.hpp"
#include "evolve/runs/replica_check.hpp"
#include "evolve/config/run_config.hpp"

namespace sodaevo {

struct CheckedArchive {
  std::vector<std::size_t> cells;  ///< the filled cells, in order
  std::vector<ReplicaCheck> checks; ///< checks[i]: the elite of cells[i]
  QdMetrics selection;             ///< the archive as the run estimated it
  QdMetrics checked;               ///< each elite at its checked mean fitness
  double mean_winners_curse = 0.0; ///< over the elites checked
};

/// The elites as individuals (id, parents, genome), each evaluated with the
/// archive's estimate: fitness and estimate.mean the mean, estimate.rollouts and
/// sd its replicas', distance the exact run's.
std::vector<Individual> archive_individuals(const GridArchive& archive);

/// Checks every elite on `replicas` fresh replicas on `threads` threads (0 = all).
CheckedArchive check_archive(const GridArchive& archive, const Problem& problem, const ReplicaPlan& plan,
                             int replicas, int threads, double qd_offset);

/// The archive of a MAP-Elites run folder as its last checkpoint holds it (the
/// archive it stopped with). Throws InputError naming the file if there is none.
GridArchive read_run_archive(const std::filesystem::path& run_dir, const RunConfig& config);

/// Checks the archive of `run_dir` on /map_elites/check_replicas fresh replicas
/// and writes RUN/archive_checked.json.
CheckedArchive write_checked_archive(const std::filesystem::path& run_dir, int threads);

} // namespace sodaevo
