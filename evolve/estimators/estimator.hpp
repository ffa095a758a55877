// Estimator: how a creature's score is estimated from simulations (the role
// between the Problem, which scores one rollout, and the Evaluator, which decides
// where the work runs). It prepares each creature through the Problem, asks the
// Problem for the rollouts it wants and makes one Evaluation of them: `fitness`
// is its statistic, `estimate` the count and spread of the rollouts.
//
// Runs use ReplicaEstimator (evolve/estimators/replica_estimator.hpp): K rollouts of each
// prepared model (states differing only in their sine jitter), summarised as a
// mean, median or lower confidence bound. SingleRollout, one exact rollout whose
// score is the fitness, is the plain case. An estimator's settings travel to the
// MPI workers by `write`.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/model_def.hpp"
#include "evolve/problems/evaluation.hpp"
#include "evolve/problems/problem.hpp"

namespace sodaevo {

class Estimator {
 public:
  virtual ~Estimator() = default;

  /// The kind's name, also its tag in the wire format ("single").
  [[nodiscard]] virtual std::string kind() const = 0;

  /// Evaluations of `creatures` under `problem`, on this thread, in one batch
  /// (the Problem steps their rollouts together where it can). Result i belongs to
  /// *creatures[i] and equals what it gets alone or in any other batch. A creature
  /// the Problem refuses is Invalid with the reason; never throws for a creature.
  [[nodiscard]] virtual std::vector<Evaluation> estimate(const Problem& problem,
                                                         const std::vector<const soda::ModelDef*>& creatures) const = 0;

  /// Adaptive resampling: how many rollouts a creature that survives with
  /// evaluation `kept` should be estimated on now, or 0 to keep `kept` as it is.
  [[nodiscard]] virtual int resample_to(const Evaluation& /*kept*/) const { return 0; }
  /// Confirmation at the end of a run: how many rollouts a creature with
  /// evaluation `kept` should be estimated on before it is handed over as one of
  /// the best, or 0 when `kept` is as sharp as this estimator makes it.
  [[nodiscard]] virtual int confirm_to(const Evaluation& /*kept*/) const { return 0; }
  /// This estimator with `rollouts` rollouts per creature (asked only where
  /// resample_to gave that count; estimators that never resample give null).
  [[nodiscard]] virtual std::unique_ptr<Estimator> with_rollouts(int /*rollouts*/) const { return nullptr; }

  /// Writes the settings, kind tag first, for read_estimator.
  virtual void write(WireWriter& out) const = 0;
};

/// One rollout per creature; fitness = its score, estimate {1, score, 0, score}.
class SingleRollout final : public Estimator {
 public:
  [[nodiscard]] std::string kind() const override { return "single"; }
  [[nodiscard]] std::vector<Evaluation> estimate(const Problem& problem,
                                                 const std::vector<const soda::ModelDef*>& creatures) const override;
  void write(WireWriter& out) const override;
};

/// The Estimator `write` wrote. Throws WireError for an unknown kind.
std::unique_ptr<Estimator> read_estimator(WireReader& in);

} // namespace sodaevo
