// The evolution benchmark's full run and report (`sodaevo bench evolve`): part 2,
// the config run in full with its champion beside the figures, and the files
// evolve.csv (every method and seed at the common budget), evolve.svg (median
// best-so-far curves) and evolve.md under results/bench/.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

#include "bench/evolve_bench.hpp"
#include "evolve/config/run_config.hpp"

namespace sodaevo::bench {

/// Part 2: the config run in full.
struct FullRun {
  bool done = false;
  double wall_seconds = 0.0;
  long long evaluations = 0;
  int generations = 0;
  double best_fitness = 0.0;
  std::string best_id;
  std::string run_dir;
};

/// Runs `config` in `out`/evolve-run-<name> (replacing an earlier one) on
/// `threads` threads (0 = all cores) and writes its champion as SodaConstructor XML
/// to `out`/evolve_champion.xml (the run folder is large and not kept in the
/// repository). `command` goes to the run's manifest; `say` gets progress lines.
FullRun run_full_evolution(const RunConfig& config, const std::filesystem::path& out, int threads,
                           const std::string& command, const std::function<void(const std::string&)>& say);

/// Everything evolve.md reports.
struct EvolveReport {
  std::string command;     ///< the command line that measured it
  std::string config_path; ///< as given
  RunConfig config;
  int seeds = 0;
  int generations = 0; ///< the GA's budget in part 1
  int threads = 0;     ///< 0 = all cores
  SearchComparison comparison;
  double comparison_seconds = 0.0;
  ClassicSpeed classic;
  FullRun full;
};

std::string evolve_markdown(const EvolveReport& report);

/// Writes evolve.csv, evolve.svg and evolve.md into `out` (created), each
/// atomically; returns evolve.md's text.
std::string write_evolve_files(const std::filesystem::path& out, const EvolveReport& report);

} // namespace sodaevo::bench
