// Replica ensembles: one creature run several times, each replica with its own
// sine jitter (core/sine_jitter.hpp), to see the spread of its walk that another
// machine's sine would show and how soon the runs part.
//
// Distances are centroid x displacements from frame `settle` to `settle +
// frames`, frames counted from the state as loaded, as the fitness and `simulate`
// measure them. The replicas step frame by frame with the reference step (or
// the continuous mode): the horizon compares them after every frame, where the
// fast steppers' cost of switching states would dominate.
#pragma once

#include <cstdint>
#include <vector>

#include "core/model.hpp"
#include "core/stepping.hpp"

namespace sodaevo {

struct ReplicaSettings {
  std::vector<std::uint64_t> seeds; ///< one replica per seed; seed 0 is the exact engine
  double probability = 0.002;       ///< share of sines each jittered replica moves by 1 ulp
  long long settle = 0;             ///< frames run before the distance is measured
  long long frames = 1000;          ///< frames measured
  soda::Stepping stepping;
};

struct ReplicaResults {
  std::vector<double> distances; ///< [replica] centroid x displacement (NaN where the run turned non-finite)
  /// The first frame (counted from the state as loaded) at which some replica's
  /// masses are more than kHorizonTolerance px away from the first replica's; -1
  /// if they never part within settle + frames.
  long long horizon = -1;
};

inline constexpr double kHorizonTolerance = 1e-9;

/// Runs the replicas. Throws std::invalid_argument for no seeds, a probability
/// outside [0, 1] or negative frame counts.
ReplicaResults run_replicas(const soda::Model& model, const ReplicaSettings& settings);

/// Seeds 0, 1, ..., count - 1: replica 0 exact, replica r jittered with seed r.
std::vector<std::uint64_t> consecutive_seeds(int count);

} // namespace sodaevo
