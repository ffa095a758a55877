// The stability stress benchmark (`sodaevo bench stability`): how well the predicted
// margin of the step (core/stability.hpp) tells which of `bench stress`'s extreme
// creatures (extreme_creatures.hpp) diverge.
//
// Each creature is run `frames` frames in one stepping, watched every frame by the
// divergence monitor (non-finite state or energy runaway, as `bench stress` does).
// Two predictors: the margin at frame 0, and the smallest margin over the states
// sampled every `sample_every` frames before the run diverged (if it did). A margin
// below 1 predicts divergence (the confusion matrix); the ROC curve sweeps that
// threshold over every value. Not every divergence is a step instability: energy
// pumped in by a V-shaped potential (negative rest length through a coincident
// pair) or an overflow from an absurd rest length diverges at any step, and the
// linear prediction cannot see contact; the report counts such misses.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/stepping.hpp"

namespace sodaevo::bench {

struct StabilityBenchOptions {
  std::uint64_t seed = 1; ///< creature i = extreme_creature(Rng::stream(seed, i, 0, 0x57e55)), as bench stress
  long long creatures = 2000;
  long long frames = 200;
  long long sample_every = 10;
  soda::Stepping stepping;
  int threads = 1;
};

struct StabilityCase {
  long long creature = 0;
  int masses = 0;
  double margin_first = 0.0; ///< at frame 0 (+inf: no step is unstable)
  double margin_min = 0.0;   ///< smallest sampled before divergence
  bool diverged = false;
  long long diverged_frame = 0;
  std::string reason;
  /// Healthy runs: some mass ended at the 20 px/frame speed limit (times 1 - f), where
  /// the syrup holds an unstable mode's growth, or on the container's edge.
  bool speed_limited = false;
  bool touching = false;
};

struct Confusion {
  long long true_positive = 0;  ///< predicted unstable (margin < 1), diverged
  long long false_positive = 0; ///< predicted unstable, stayed healthy
  long long false_negative = 0; ///< predicted stable, diverged
  long long true_negative = 0;  ///< predicted stable, stayed healthy
};

struct RocPoint {
  double threshold = 0.0; ///< margins below it are called unstable
  double false_positive_rate = 0.0;
  double true_positive_rate = 0.0;
};

struct StabilityBenchReport {
  std::vector<StabilityCase> cases;
  Confusion first, lowest; ///< at margin threshold 1
  std::vector<RocPoint> roc_first, roc_lowest;
  double auc_first = 0.0, auc_lowest = 0.0; ///< area under the ROC curve (ties count half)
  double seconds = 0.0;
};

StabilityBenchReport run_stability_bench(const StabilityBenchOptions& options);

/// Confusion matrix of "margin < threshold predicts divergence".
Confusion confusion(const std::vector<double>& margins, const std::vector<bool>& diverged, double threshold);

/// ROC curve of the same rule over every threshold (from (0, 0) to (1, 1)) and its
/// area: the probability that a diverged creature has a smaller margin than a
/// healthy one (Mann-Whitney, ties half).
std::vector<RocPoint> roc_curve(const std::vector<double>& margins, const std::vector<bool>& diverged);
double roc_area(const std::vector<double>& margins, const std::vector<bool>& diverged);

} // namespace sodaevo::bench
