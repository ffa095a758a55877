// The claims chart of a run report: each champion's claim (the estimate the run
// selected it on) against a check on fresh replicas (its median and 95 %
// prediction interval), one row each, as a dot-and-whisker SVG. Claims more than
// 5 % better than the checked mean are flagged: that is the winner's curse showing.
// A walk's score is px walked (more is better); a race's is its result in frames
// (fewer is better; the run's fitness is minus that, champions.json says
// "unit": "frames"), and the chart shows frames.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace sodaevo::app {

struct ClaimRow {
  std::string id;
  double claim = 0.0;          ///< selection mean, px (a race: frames)
  int claim_n = 0;
  double check_median = 0.0;   ///< px (a race: frames)
  double check_mean = 0.0;
  double check_lo = 0.0, check_hi = 0.0; ///< 95 % prediction interval, px (a race: frames)
  bool race = false;           ///< values are race results in frames: fewer is better
};

/// Whether `row` claims more than 5 % better than its checked mean (a walk: above
/// it, a race: below it).
bool claim_flagged(const ClaimRow& row);

/// The chart as self-contained SVG text.
std::string render_claims_chart(const std::vector<ClaimRow>& rows);

/// The rows of a champions.json file (evolve writes RUN/champions.json at the end
/// of a run, export writes DIR/champions.json); entries whose check failed are
/// left out. Throws soda::InputError naming the file for a malformed one.
std::vector<ClaimRow> read_claim_rows(const std::filesystem::path& champions_json);

/// The run report's section "Claimed against checked" for `run_dir`: the chart
/// and how many claims are flagged, or a note that the run has no check yet.
std::string claims_section_html(const std::filesystem::path& run_dir);

} // namespace sodaevo::app
