// MpiEvaluator: the Evaluator that spreads a generation over the ranks of an MPI
// job (the master side; workers run mpi_worker.hpp).
//
// Rank 0 evaluates too, on its own threads, while its main thread hands out
// chunks of creatures on demand: a worker gets its next chunk when it returns the
// last one, and chunks shrink as the generation drains (guided scheduling), so
// cheap and costly creatures even out. Evaluations come back with their index and
// are stored there, so the result is the same bit for bit whatever the number of
// ranks or threads. If a worker reports a failure, the chunks still out are
// collected, evaluate() throws and returns nothing: the run folder keeps its last
// checkpoint. The workers get the Problem and the Estimator in the wire format
// (once, and again only when they change), never the run's config.
#pragma once

#include <string>
#include <vector>

#include "evolve/evaluators/evaluator.hpp"
#include "evolve/mpi/mpi_session.hpp"

namespace sodaevo {

/// What went over the wire, for the scaling model (bytes are MPI payloads).
struct MpiTraffic {
  long long creatures_farmed = 0;  ///< evaluated on ranks other than 0
  long long creatures_local = 0;   ///< evaluated on rank 0
  long long work_messages = 0;
  long long bytes_sent = 0;        ///< Work messages
  long long bytes_received = 0;    ///< Results messages
};

class MpiEvaluator final : public Evaluator {
 public:
  /// `threads` as given to --threads (0 = this node's cores shared between its ranks).
  MpiEvaluator(MpiSession& session, int threads);
  std::vector<Evaluation> evaluate(const std::vector<const soda::ModelDef*>& creatures, const Problem& problem,
                                   const Estimator& estimator) override;

  [[nodiscard]] int local_threads() const { return local_threads_; }
  [[nodiscard]] int total_threads() const;
  [[nodiscard]] const MpiTraffic& traffic() const { return traffic_; }

 private:
  void set_up_workers(const Problem& problem, const Estimator& estimator);

  MpiSession& session_;
  int requested_threads_;
  int local_threads_;
  std::vector<int> worker_threads_; ///< by rank; [0] unused
  std::vector<char> setup_sent_;    ///< the problem and estimator the workers hold
  MpiTraffic traffic_;
};

} // namespace sodaevo
