// HandoffEvaluator: an Evaluator that hands each request to another thread and
// waits for its answers. The run's own loop (run_evolution, run_map_elites) runs
// on a thread of its own, exactly as `sodaevo evolve` runs it; whoever drives the
// run (Python's Optimiser, python/optimiser.cpp) takes each request, has it
// evaluated anywhere, and gives the evaluations back, after which the loop goes
// on where it waited.
//
// Why not AskTellEvaluator (ask_tell_evaluator.hpp): that one serves drivers
// without threads (the browser's page); it throws the loop out at every request
// and runs it again from the checkpoint once answered, which replays the
// generation's variation and rereads the checkpoint each time (a tenth of an
// ask/tell loop's time in Python). Here the loop simply waits, so nothing is
// replayed and the folder is the command's by construction.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <optional>
#include <vector>

#include "evolve/evaluators/evaluator.hpp"

namespace sodaevo {

/// Thrown out of a waiting evaluate() when the driver abandons the run.
struct RunAbandoned {};

class HandoffEvaluator final : public Evaluator {
 public:
  /// A request as the driver takes it: the problem and the estimator in the wire
  /// format (a copy the driver owns), and the creatures.
  struct Request {
    std::vector<char> head;
    std::vector<soda::ModelDef> creatures;
  };

  /// Loop thread: posts the request and blocks until answered (or throws
  /// RunAbandoned).
  std::vector<Evaluation> evaluate(const std::vector<const soda::ModelDef*>& creatures, const Problem& problem,
                                   const Estimator& estimator) override;

  /// Driver: blocks until the loop posts a request (returned) or ends (nullopt).
  std::optional<Request> wait_for_request();
  /// Driver: the answers of the pending request, in its order (their count is checked).
  void answer(std::vector<Evaluation> evaluations);
  /// Loop thread, when the loop has returned or thrown: wakes the driver.
  void loop_ended();
  /// Driver: a loop waiting in evaluate() throws RunAbandoned; no request is taken after.
  void abandon();

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::optional<Request> request_;           ///< posted, not yet taken by the driver
  std::size_t expected_ = 0;                  ///< the count of the request being evaluated
  std::optional<std::vector<Evaluation>> answers_;
  bool waiting_ = false;                      ///< the loop waits in evaluate()
  bool ended_ = false;
  bool abandoned_ = false;
};

} // namespace sodaevo
