#include "app/claims_chart.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>

#include "charts/svg_chart.hpp"
#include "core/input_error.hpp"
#include "formats/atomic_file.hpp"

namespace sodaevo::app {

bool claim_flagged(const ClaimRow& row) {
  const double better_by = row.race ? row.check_mean - row.claim : row.claim - row.check_mean;
  return better_by > 0.05 * std::fabs(row.check_mean);
}

namespace {

std::string svg_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", v);
  return buf;
}

/// A row's label: its id, and for a flagged claim which way it is off.
std::string row_label(const ClaimRow& r) {
  if (!claim_flagged(r)) return r.id;
  return r.id + (r.race ? " (claim < check - 5 %)" : " (claim > check + 5 %)");
}

} // namespace

std::string render_claims_chart(const std::vector<ClaimRow>& rows) {
  constexpr int kFont = 12, kLabelGap = 8, kMargin = 10;
  // The labels' column is as wide as its longest label, so none is cut off.
  double label_width = 0.0;
  for (const ClaimRow& r : rows) label_width = std::max(label_width, charts::text_width_estimate(row_label(r), kFont));
  const int left = std::max(60, kMargin + kLabelGap + static_cast<int>(std::ceil(label_width)));
  const int right = 30, top = 40, row_height = 26, bottom = 50;
  const int width = std::max(760, left + 400 + right); // at least 400 px of plot
  const int height = top + row_height * static_cast<int>(std::max<std::size_t>(rows.size(), 1)) + bottom;
  double lo = 0.0, hi = 1.0;
  bool first = true;
  for (const ClaimRow& r : rows) {
    for (double v : {r.claim, r.check_lo, r.check_hi, r.check_median}) {
      if (!std::isfinite(v)) continue;
      lo = first ? v : std::min(lo, v);
      hi = first ? v : std::max(hi, v);
      first = false;
    }
  }
  const double span = hi > lo ? hi - lo : 1.0;
  lo -= 0.05 * span;
  hi += 0.05 * span;
  const double plot = width - left - right;
  auto x_of = [&](double v) { return left + (v - lo) / (hi - lo) * plot; };
  const bool race = std::any_of(rows.begin(), rows.end(), [](const ClaimRow& r) { return r.race; });
  const char* unit = race ? "frames" : "px";

  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height
    << "\" viewBox=\"0 0 " << width << ' ' << height << "\" font-family=\"sans-serif\" font-size=\"" << kFont << "\">\n";
  o << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  o << "<text x=\"" << width / 2 << "\" y=\"20\" text-anchor=\"middle\" font-size=\"14\">Claimed (diamond) against "
       "checked on fresh replicas (dot: median, bar: 95 % interval)</text>\n";
  const int axis_y = top + row_height * static_cast<int>(rows.size()) + 5;
  o << "<line x1=\"" << left << "\" y1=\"" << axis_y << "\" x2=\"" << width - right << "\" y2=\"" << axis_y
    << "\" stroke=\"#444\"/>\n";
  // Ticks at round values (1, 2 or 5 times a power of ten), as the other charts.
  for (const double v : charts::round_ticks(lo, hi)) {
    const double x = x_of(v);
    o << "<line x1=\"" << svg_number(x) << "\" y1=\"" << top - 5 << "\" x2=\"" << svg_number(x) << "\" y2=\"" << axis_y
      << "\" stroke=\"#eee\"/>\n<text class=\"tick\" x=\"" << svg_number(x) << "\" y=\"" << axis_y + 16
      << "\" text-anchor=\"middle\">" << charts::svg_escape(charts::format_tick(v)) << "</text>\n";
  }
  o << "<text x=\"" << left + plot / 2 << "\" y=\"" << axis_y + 36
    << "\" text-anchor=\"middle\">"
    << (race ? "race result, frames to the finish (fewer is better)" : "distance walked over the scored frames, px")
    << "</text>\n";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const ClaimRow& r = rows[i];
    const double y = top + row_height * (static_cast<double>(i) + 0.5);
    const bool flag = claim_flagged(r);
    o << "<text class=\"label\" x=\"" << left - kLabelGap << "\" y=\"" << svg_number(y + 4) << "\" text-anchor=\"end\""
      << (flag ? " fill=\"#b00\"" : "") << ">" << charts::svg_escape(row_label(r)) << "</text>\n";
    o << "<line x1=\"" << svg_number(x_of(r.check_lo)) << "\" y1=\"" << svg_number(y) << "\" x2=\"" << svg_number(x_of(r.check_hi))
      << "\" y2=\"" << svg_number(y) << "\" stroke=\"#1f77b4\" stroke-width=\"2\"/>\n";
    o << "<circle cx=\"" << svg_number(x_of(r.check_median)) << "\" cy=\"" << svg_number(y)
      << "\" r=\"4\" fill=\"#1f77b4\"><title>checked median " << svg_number(r.check_median) << " "
      << unit << ", interval [" << svg_number(r.check_lo) << ", " << svg_number(r.check_hi) << "]</title></circle>\n";
    const double cx = x_of(r.claim);
    o << "<path d=\"M" << svg_number(cx) << ' ' << svg_number(y - 6) << " L" << svg_number(cx + 6) << ' ' << svg_number(y) << " L"
      << svg_number(cx) << ' ' << svg_number(y + 6) << " L" << svg_number(cx - 6) << ' ' << svg_number(y) << " Z\" fill=\""
      << (flag ? "#d62728" : "#ff7f0e") << "\"><title>claim " << svg_number(r.claim) << " " << unit << " (" << r.claim_n
      << " replicas)</title></path>\n";
  }
  o << "</svg>\n";
  return o.str();
}

std::vector<ClaimRow> read_claim_rows(const std::filesystem::path& path) {
  std::vector<ClaimRow> rows;
  try {
    const nlohmann::json j = nlohmann::json::parse(soda::read_whole_file(path));
    for (const nlohmann::json& e : j) {
      if (!e.contains("check")) continue; // the check failed; its entry says why
      ClaimRow r;
      r.id = e.at("id").get<std::string>();
      // A race's fitness is minus its frames; its check is in frames.
      r.race = e.value("unit", std::string("px")) == "frames";
      r.claim = e.at("selection").at("mean").get<double>() * (r.race ? -1.0 : 1.0);
      r.claim_n = e.at("selection").at("n").get<int>();
      const nlohmann::json& c = e.at("check");
      r.check_median = c.at("median").get<double>();
      r.check_mean = c.at("mean").get<double>();
      r.check_lo = c.at("interval95").at(0).get<double>();
      r.check_hi = c.at("interval95").at(1).get<double>();
      rows.push_back(r);
    }
  } catch (const nlohmann::json::exception& ex) {
    throw soda::InputError(path.string() + ": not a champions file: " + ex.what());
  }
  return rows;
}

std::string claims_section_html(const std::filesystem::path& run_dir) {
  const std::filesystem::path file = run_dir / "champions.json";
  std::ostringstream o;
  o << "<h2>Claimed against checked</h2>\n";
  if (!std::filesystem::exists(file)) {
    o << "<p class=\"note\">Written when the run ends: the best creatures re-run on fresh replicas "
         "(champions.json).</p>\n";
    return o.str();
  }
  const std::vector<ClaimRow> rows = read_claim_rows(file);
  const auto flagged = std::count_if(rows.begin(), rows.end(), claim_flagged);
  o << "<p class=\"note\">Each creature's claim (its estimate in the run, over the replicas it gathered) against a "
       "check on replicas that selection never saw. A creature is chaotic: the original program's run is one more "
       "draw, which the interval should contain 95 % of the time. "
    << flagged << " of " << rows.size() << " claims are more than 5 % better than their check"
    << (std::any_of(rows.begin(), rows.end(), [](const ClaimRow& r) { return r.race; })
            ? " (race results in frames: fewer is better)"
            : "")
    << ".</p>\n"
    << render_claims_chart(rows);
  return o.str();
}

} // namespace sodaevo::app
