// How a run's scores read, for every report, summary and export line: a walk's
// fitness is px walked (more is better); a race's fitness is minus its result,
// shown as frames to the finish (fewer is better).
#pragma once

#include "evolve/config/run_config.hpp"

namespace sodaevo::app {

struct ScoreUnit {
  bool race = false;

  static ScoreUnit of(const RunConfig& config) { return {config.fitness.kind == FitnessKind::Race}; }
  /// A fitness as it is shown: px, or a race's frames.
  [[nodiscard]] double shown(double fitness) const { return race ? -fitness : fitness; }
  /// The unit of what `shown` gives, and of distances and checks.
  [[nodiscard]] const char* unit() const { return race ? "frames" : "px"; }
  /// The unit of a raw fitness column (a race's is minus its frames).
  [[nodiscard]] const char* fitness_unit() const { return race ? "-frames" : "px"; }
};

} // namespace sodaevo::app
