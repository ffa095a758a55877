// The sections of `sodaevo bench speed`, one function each; run_speed_bench
// (speed_bench.cpp) runs those the options ask for, in its table's order. Each
// times its engines and adds its rows and figures to the report. A new section is
// a function here and a line in that table (and a flag in SpeedOptions).
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "bench/speed_bench.hpp"
#include "core/model.hpp"

namespace sodaevo::bench {

/// What every section gets.
struct SpeedSectionInput {
  const SpeedOptions& options;
  int runs = 0;        ///< timed runs (rounds) per engine
  double target = 0.0; ///< seconds one timed run should take
  /// The bundled creatures, built (SpeedOptions::creatures).
  const std::vector<std::pair<std::string, soda::Model>>& creatures;
  std::function<void(const std::string&)> say; ///< one progress line
};

/// 1. The bundled creatures, every engine.
void time_creature_section(const SpeedSectionInput& in, SpeedReport& report);
/// 2. Synthetic lattices of 10 to 100,000 links.
void time_size_section(const SpeedSectionInput& in, SpeedReport& report);
/// 4. The GA's own creatures from a saved run (none without SpeedOptions::ga_run).
void time_ga_section(const SpeedSectionInput& in, SpeedReport& report);
/// 3. Population throughput on 1 and all threads (population_speed.cpp).
void time_population_section(const SpeedSectionInput& in, SpeedReport& report);

} // namespace sodaevo::bench
