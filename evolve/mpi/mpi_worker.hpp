// The worker side of the MPI evaluator: what every rank except 0 runs.
//
// A worker never reads the command line, never touches the run folder and never
// prints progress. It waits for the master's setup (the Problem and the
// Estimator in the wire format), then evaluates the chunks of creatures it is
// sent on its own threads (a ThreadEvaluator) and sends the
// evaluations back by index, until told to stop. An exception while evaluating
// is sent to the master as a Failure message (the run then stops cleanly), not a
// crash.
//
// For the fault tests, SODAEVO_TEST_FAULT="kill:RANK:N" makes rank RANK kill
// itself (SIGKILL) when it receives its (N+1)-th chunk, and "fail:RANK:N" makes
// the evaluation of that chunk throw. Every worker gets at least one chunk per
// generation, so the fault lands in a known generation. Unset, it costs nothing.
#pragma once

#include "evolve/mpi/mpi_session.hpp"

namespace sodaevo {

/// Runs the worker loop; returns the process exit code (0 after Stop).
int run_mpi_worker(MpiSession& session);

} // namespace sodaevo
