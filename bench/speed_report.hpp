// The speed benchmark's report as files (`sodaevo bench speed` writes them under
// results/bench/): speed.csv (every row), speed_rounds.csv (every timed run of the
// population section), speed.md (the tables and what they say, one part per
// section) and the charts speed.svg (size sweep) and speed_creatures.svg.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "bench/speed_bench.hpp"

namespace sodaevo::bench {

std::string speed_csv(const SpeedReport& report);
std::string speed_rounds_csv(const SpeedReport& report);
/// The Markdown report; `command` is the command line that measured it.
std::string speed_markdown(const SpeedReport& report, const std::string& command);
std::string speed_sweep_svg(const SpeedReport& report);
std::string speed_creatures_svg(const SpeedReport& report);

/// Writes speed.csv, speed.md (`markdown`) and the files of the sections `options`
/// ran into `out` (created), each atomically; returns the names written (speed.csv
/// and speed.md first).
std::vector<std::string> write_speed_files(const std::filesystem::path& out, const SpeedReport& report,
                                           const SpeedOptions& options, const std::string& markdown);

} // namespace sodaevo::bench
