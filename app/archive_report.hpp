// The archive report of a MAP-Elites run (RUN/archive.html): one self-contained
// page with the archive as heat maps and a player for any elite.
//
// It reads the run folder (config.json, archive.json, qd.csv, elites/) and shows
// the QD metrics (and those of the corrected archive, archive_checked.json, when
// the run checked its elites), the QD-score and coverage over the iterations
// (svg_chart.hpp), and the archive: the first two descriptors on the axes, one
// small heat map per bin of the third (small multiples), each filled cell
// coloured by its elite's fitness; a selector shows one bin, or one map of the
// best elite over every bin of the third. Clicking a cell plays its elite in the
// player below (player_html.hpp);
// the motions are recorded from elites/ with few samples each, so a page of a
// thousand elites stays a few MB.
//
// For tests and screenshots: the fragment "#cell=N" clicks cell N after loading
// (a real click event on its visible square), "#third=K" selects K ("all",
// "best" or a bin) in the selector first, and "#frame=F" stops the player as in
// every player page.
#pragma once

#include <filesystem>
#include <string>

namespace sodaevo::app {

struct ArchiveReportOptions {
  int max_samples = 60; ///< pictures kept per elite's animation
};

/// Whether `run_dir` holds a MAP-Elites archive (archive.json).
bool has_archive(const std::filesystem::path& run_dir);

/// The page. Throws soda::InputError naming the file if the folder has no
/// readable archive.
std::string archive_report_html(const std::filesystem::path& run_dir, const ArchiveReportOptions& options = {});

/// Writes archive_report_html() atomically to `out`.
void write_archive_report(const std::filesystem::path& run_dir, const std::filesystem::path& out,
                          const ArchiveReportOptions& options = {});

/// RUN/archive.html.
std::filesystem::path default_archive_report_path(const std::filesystem::path& run_dir);

} // namespace sodaevo::app
