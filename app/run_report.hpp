// The run report: one self-contained HTML page that shows how a run went.
//
// It reads the run folder (config.json, manifest.json, generations.csv, best/)
// and shows the config; best, mean and median fitness per generation and the
// invalid and diverged counts as inline SVG charts (svg_chart.hpp); a table of
// the best creatures with distance and speed (re-simulated from best/, so the
// table is also a check that they reproduce); animation players for the
// champion and the best of a few generations along the run, next to the Dainty
// Walker prepared and scored under the same fitness settings. Only best/ files
// and one classic are simulated, so writing a report is cheap (a few trials) and
// `evolve` can refresh it as the run goes.
#pragma once

#include <filesystem>
#include <string>

namespace sodaevo::app {

struct ReportOptions {
  int table_rows = 10;         ///< best distinct creatures listed
  int chosen_generations = 3;  ///< generations (first, ..., last) whose best is animated besides the champion
  int max_samples = 400;       ///< pictures kept per animation
};

/// The report page. Throws soda::InputError naming the file if the run folder
/// is not a readable run (no config.json, malformed generations.csv, ...).
std::string run_report_html(const std::filesystem::path& run_dir, const ReportOptions& options = {});

/// Writes run_report_html() atomically to `out`.
void write_run_report(const std::filesystem::path& run_dir, const std::filesystem::path& out,
                      const ReportOptions& options = {});

/// What the report says when (part of) the run was made with another muscle sine
/// than this engine's (evolve/store/run_sine.hpp); empty if none was. For the terminal.
std::string report_sine_note(const std::filesystem::path& run_dir);

/// The report's place in a run folder: RUN/report.html.
std::filesystem::path default_report_path(const std::filesystem::path& run_dir);

} // namespace sodaevo::app
