// One creature run at one setting on R sine-jitter replicas: the work-precision
// benchmark's expected distances (bench/accuracy_bench.hpp).
//
// Why replicas: a walker is chaotic, so one rollout's distance is one draw; two
// settings (or the original and this engine) part at the first sine that differs in
// its last bit. A setting is judged on its expected distance, the mean over R
// replicas (replica 0 the exact engine, replica r >= 1 jittered with seed r,
// core/sine_jitter.hpp), whose standard error says how well R replicas know it; two
// settings differ by the difference of their means, with a Welch interval.
#pragma once

#include <cstdint>
#include <vector>

#include "core/model.hpp"
#include "core/sine_jitter.hpp"
#include "core/stepping.hpp"
#include "evolve/estimators/sample_summary.hpp"

namespace sodaevo::bench {

/// One rollout, recorded at checkpoint frames.
struct RunResult {
  std::vector<std::vector<double>> positions; ///< per checkpoint: x0 y0 x1 y1 ... of the free masses
  double seconds = 0.0;
  bool diverged = false; ///< non-finite state, or an implicit solve failed (positions NaN from there)
};

/// Runs from the initial state (with `jitter`) to each checkpoint frame (ascending)
/// with the plain reference step in soda mode (a scalar loop like the continuous
/// stepper, so that timings compare methods; it also applies the jitter).
RunResult run_with_checkpoints(const soda::Model& model, const soda::Stepping& stepping,
                               const std::vector<long long>& checkpoints, const soda::SineJitter& jitter = {});

/// Mean x of the masses in a checkpoint's positions.
double centroid_x(const std::vector<double>& positions);

/// What to run for an expected distance: the distance is the centroid's x
/// displacement from checkpoint `from` to checkpoint `to`.
struct ReplicaPlan {
  std::vector<long long> checkpoints; ///< ascending frames
  std::size_t from = 0, to = 0;       ///< indices into checkpoints
  int replicas = 8;                   ///< R: seeds 0 .. R-1
  double jitter = 0.002;              ///< share of sines a jittered replica moves by 1 ulp
  std::size_t keep = 0;               ///< checkpoint whose replica-0 positions are kept
};

struct ExpectedDistance {
  std::vector<double> distances; ///< [replica]; NaN where the replica diverged
  SampleSummary summary;         ///< of the finite distances (n = 0 if none)
  double standard_error = 0.0;   ///< sd / sqrt(n)
  double exact = 0.0;            ///< replica 0's distance: the single exact rollout
  int diverged = 0;              ///< replicas that diverged
  double seconds_per_frame = 0.0; ///< the fastest replica's (the machine may be shared)
  std::vector<double> exact_positions; ///< replica 0 at checkpoint `keep`
};

/// Runs the R replicas of `plan`.
ExpectedDistance expected_distance(const soda::Model& model, const soda::Stepping& stepping, const ReplicaPlan& plan);

/// a - b with its 95 % confidence interval (Welch: the two means' standard errors
/// combined, Student's t at the Welch-Satterthwaite degrees of freedom rounded
/// down). NaN when either has no finite replica.
struct DifferenceInterval {
  double difference = 0.0;
  double low = 0.0;
  double high = 0.0;
};
DifferenceInterval difference_interval(const ExpectedDistance& a, const ExpectedDistance& b);

} // namespace sodaevo::bench
