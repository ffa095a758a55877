// Random creatures with extreme but legal parameters, for stability stress tests:
// everything build_model accepts, pushed to its edges. Springyness 0.5 and gravity
// 4 (the original's maxima) are drawn often, friction 0 and 1, wave speeds beyond
// the UI's 0.1, hubs with dozens of links on one mass, zero, negative and (rarely)
// absurdly large rest lengths, coincident masses, masses outside the container,
// links listed twice, initial speeds above the 20 px/frame limit, fixed nodes and
// fixed bars, tiny containers.
//
// The stress run watches every frame with core/divergence.hpp and counts what it
// flags; a non-finite value that is not flagged at the frame it appears, or a
// fitness evaluation that reports Ok with a non-finite number, is an escape.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/divergence.hpp"
#include "core/model_def.hpp"
#include "core/stepping.hpp"
#include "evolve/algorithms/rng.hpp"

namespace sodaevo::bench {

/// One extreme creature (always accepted by build_model).
soda::ModelDef extreme_creature(Rng& rng);

struct StressOptions {
  std::uint64_t seed = 1;
  long long creatures = 1000;
  long long frames = 200;
  std::vector<soda::Stepping> steppings = {soda::Stepping{}};
  bool energy_check = true;
  int threads = 1;
};

struct StressCounts {
  std::string stepping;
  long long tried = 0;
  long long diverged_non_finite = 0; ///< a position, velocity or the wave became NaN or infinite
  long long diverged_energy = 0;     ///< energy ran away (or overflowed) while the state stayed finite
  long long escaped = 0; ///< must stay 0
  long long frames_stepped = 0;
  std::string first_escape;      ///< description of the first escape, if any
  std::string example_diverged;  ///< one flagged creature's reason and frame
};

/// Steps `creatures` extreme creatures (creature i from Rng::stream(seed, i))
/// `frames` frames in every stepping, watching every frame. Deterministic for any
/// thread count.
std::vector<StressCounts> run_stress(const StressOptions& options);

} // namespace sodaevo::bench
