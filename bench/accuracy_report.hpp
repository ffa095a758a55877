// The accuracy benchmark's report as files (`sodaevo bench accuracy` writes them
// under results/bench/): accuracy.csv (every row), log-log work-precision charts
// (accuracy_classics.svg, accuracy_walkers.svg, accuracy_walkers_all.svg and one per
// analytic scene) and accuracy.md: per setting its time and error, the settings no
// other beats in both (Pareto), and the cheapest setting within 1 %.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "bench/accuracy_bench.hpp"

namespace sodaevo::bench {

struct AccuracyFiles {
  std::string markdown;             ///< accuracy.md's text
  std::vector<std::string> written; ///< file names, in the order written
};

/// Writes the files into `out` (created), each atomically; `command` is the
/// command line that measured the report.
AccuracyFiles write_accuracy_files(const std::filesystem::path& out, const AccuracyReport& report,
                                   const std::string& command);

} // namespace sodaevo::bench
