// AskTellEvaluator: an Evaluator that never evaluates. The run's own loop
// (run_evolution, run_map_elites) is driven from outside, by someone who
// evaluates elsewhere: the page's Web Workers (web/evolve_api.cpp) or a Python
// caller (python/optimiser.cpp). An evaluation it has no answer for is thrown out
// of the loop as NeedEvaluation, after which the creatures, the problem and the
// estimator are pending; once told the results, the loop is run again from the
// run folder's checkpoint and this time the evaluator answers from what it was
// told. The loop stops itself after every generation (its polite stop, which
// checkpoints), so a run again replays at most the current generation's
// variation, never an evaluation. Answers are keyed by the whole request's bytes
// and told by index, so whoever evaluated them never changes a result.
#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "evolve/evaluators/evaluator.hpp"

namespace sodaevo {

/// Thrown out of the run loop when the evaluator has no answer yet.
struct NeedEvaluation {};

class AskTellEvaluator final : public Evaluator {
 public:
  /// The told answer for this request, or throws NeedEvaluation leaving it pending.
  std::vector<Evaluation> evaluate(const std::vector<const soda::ModelDef*>& creatures, const Problem& problem,
                                   const Estimator& estimator) override;

  /// The pending request's creatures [first, last) as a worker reads them: the
  /// problem, the estimator, the count and the creatures in the wire format.
  [[nodiscard]] std::vector<char> chunk(std::size_t first, std::size_t last) const;
  [[nodiscard]] std::size_t pending_count() const { return pending_.size(); }
  [[nodiscard]] const std::vector<soda::ModelDef>& pending() const { return pending_; }

  /// Answers for the pending creatures from `first` on (a count, then evaluations
  /// in the wire format); true once all are told. Throws WireError if malformed.
  bool tell(std::size_t first, const char* bytes, std::size_t size);
  /// Forgets the answers (a generation is done: they are in the run folder).
  void forget() { answers_.clear(); }

 private:
  std::map<std::string, std::vector<Evaluation>> answers_;
  std::string pending_key_;
  std::vector<char> pending_head_;
  std::vector<soda::ModelDef> pending_;
  std::vector<std::optional<Evaluation>> told_;
};

} // namespace sodaevo
