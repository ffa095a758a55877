// The MAP-Elites branch of `sodaevo evolve` (a config with "algorithm": "map-elites"):
// progress lines, the run, the archive report, and the summary.
#pragma once

#include <atomic>

#include "evolve/run_store.hpp"

namespace sodaevo::app {

/// Runs (or resumes) the MAP-Elites run of `store` on `threads` threads (0 = all
/// cores); stops politely when `stop` becomes true. Writes RUN/archive.html.
void evolve_map_elites(const RunStore& store, int threads, bool quiet, const std::atomic<bool>* stop);

} // namespace sodaevo::app
