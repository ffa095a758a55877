// Evaluation: what the evaluation of one creature found, the record that the
// evaluators return, the algorithm ranks, the run store writes and the wire
// format carries between processes.
//
// A creature's score is an estimate (evolve/estimators/estimator.hpp) over one or more
// rollouts (evolve/problems/problem.hpp): `fitness` is the estimator's statistic, and
// `estimate` says how many rollouts it stands on and how they spread.
#pragma once

#include <limits>
#include <string>
#include <vector>

namespace sodaevo {

/// The fitness given to invalid or diverged creatures: below every real one.
inline constexpr double kWorstFitness = -std::numeric_limits<double>::infinity();

enum class EvaluationStatus { Ok, Invalid, Diverged };

/// The status as saved generations, run folders and the Python module name it.
constexpr const char* status_name(EvaluationStatus s) {
  switch (s) {
    case EvaluationStatus::Ok: return "ok";
    case EvaluationStatus::Invalid: return "invalid";
    case EvaluationStatus::Diverged: return "diverged";
  }
  return "invalid";
}

/// The rollouts behind a fitness. rollouts == 0: not known (a creature read back
/// from a file that does not record it, or one that was not scored).
struct Estimate {
  int rollouts = 0;
  double mean = 0.0;    ///< of the rollouts' scores
  double sd = 0.0;      ///< sample standard deviation (0 for one rollout)
  double median = 0.0;

  bool operator==(const Estimate&) const = default;
};

struct Evaluation {
  EvaluationStatus status = EvaluationStatus::Invalid;
  std::string reason;           ///< why invalid or diverged; empty when Ok
  double fitness = kWorstFitness;
  double distance = 0.0;        ///< centroid x displacement over the scored frames, px (a race: its result, frames)
  double px_per_frame = 0.0;    ///< distance / frames
  /// Honesty check (/fitness/honesty): relative change of the distance under the
  /// refined step (evolve/problems/honesty.hpp); 0 when the check is off.
  double honesty_change = 0.0;
  Estimate estimate;
  /// Behaviour descriptors of the same rollouts, the mean over the estimate's
  /// rollouts, when the Problem measures them (WalkProblem with a descriptor
  /// sample interval: every descriptor of evolve/problems/descriptors.hpp, in its order);
  /// empty otherwise. What MAP-Elites places a creature by.
  std::vector<double> descriptors;

  [[nodiscard]] bool ok() const { return status == EvaluationStatus::Ok; }
};

} // namespace sodaevo
