// The MAP-Elites branch of `sodaevo evolve` (a config with "algorithm": "map-elites"):
// progress lines, the run, the archive report, and the summary.
#pragma once

#include <atomic>

#include "evolve/evaluators/evaluator.hpp"
#include "evolve/store/run_store.hpp"

namespace sodaevo::app {

/// Runs (or resumes) the MAP-Elites run of `store`, evaluating on `evaluator`
/// (threads or MPI ranks; `threads` as given to --threads, for the checks at the
/// end); stops politely when `stop` becomes true. Writes RUN/archive.html.
void evolve_map_elites(const RunStore& store, Evaluator& evaluator, int threads, bool quiet,
                       const std::atomic<bool>* stop);

} // namespace sodaevo::app
