// The claims chart of a run report: each champion's claim (the estimate the run
// selected it on) against a check on fresh replicas (its median and 95 %
// prediction interval), one row each, as a dot-and-whisker SVG. Claims more than
// 5 % above the checked mean are flagged: that is the winner's curse showing.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace sodaevo::app {

struct ClaimRow {
  std::string id;
  double claim = 0.0;          ///< selection mean, px
  int claim_n = 0;
  double check_median = 0.0;   ///< px
  double check_mean = 0.0;
  double check_lo = 0.0, check_hi = 0.0; ///< 95 % prediction interval, px
};

/// Whether `row` claims more than 5 % above its checked mean.
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
