// The stress benchmark's report as files (`sodaevo bench stress` writes them under
// results/bench/): stress.csv and stress.md, a row per stepping with the creatures
// tried, the frames stepped, what the divergence detector flagged and what escaped
// it, then the first escape and one flagged creature of each stepping.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "bench/extreme_creatures.hpp"

namespace sodaevo::bench {

struct StressFiles {
  std::string markdown; ///< stress.md's text
  bool escaped = false; ///< a non-finite value escaped the detector in some stepping
};

/// Writes stress.csv and stress.md into `out` (created), each atomically.
/// `options` and `seconds` are the run's; `command` is its command line.
StressFiles write_stress_files(const std::filesystem::path& out, const std::vector<StressCounts>& counts,
                               const StressOptions& options, const std::string& command, double seconds);

} // namespace sodaevo::bench
