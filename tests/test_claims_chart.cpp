// The run report's "Claimed against checked" chart (app/claims_chart.hpp): its
// axis ticks fall on round numbers and no text runs off the picture.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include <pugixml.hpp>

#include "app/claims_chart.hpp"
#include "charts/svg_chart.hpp"

using sodaevo::app::ClaimRow;
using sodaevo::charts::round_ticks;
using sodaevo::charts::text_width_estimate;

namespace {

/// Whether `step` is 1, 2 or 5 times a power of ten.
bool round_step(double step) {
  if (!(step > 0)) return false;
  const double mantissa = step / std::pow(10.0, std::floor(std::log10(step) + 1e-9));
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    if (std::fabs(mantissa - m) < 1e-6) return true;
  }
  return false;
}

/// Ticks are round: equally spaced by a 1-2-5 step, each a whole multiple of it.
void require_round_ticks(const std::vector<double>& ticks) {
  INFO("ticks: " << Catch::Detail::stringify(ticks));
  REQUIRE(ticks.size() >= 2);
  const double step = ticks[1] - ticks[0];
  CHECK(round_step(step));
  for (std::size_t k = 0; k < ticks.size(); ++k) {
    CHECK(std::fabs(ticks[k] / step - std::round(ticks[k] / step)) < 1e-6);
    if (k > 0) CHECK(std::fabs(ticks[k] - ticks[k - 1] - step) < 1e-6 * step);
  }
}

/// A tick label's value: format_tick's "7.5k", "-5k", "250", "1.2M".
double label_value(const std::string& text) {
  char* end = nullptr;
  double v = std::strtod(text.c_str(), &end);
  const std::string suffix = end;
  if (suffix == "k") v *= 1e3;
  else if (suffix == "M") v *= 1e6;
  else REQUIRE(suffix.empty());
  return v;
}

ClaimRow row(const std::string& id, double claim, double median, double lo, double hi) {
  ClaimRow r;
  r.id = id;
  r.claim = claim;
  r.claim_n = 32;
  r.check_median = r.check_mean = median;
  r.check_lo = lo;
  r.check_hi = hi;
  return r;
}

} // namespace

TEST_CASE("round_ticks: 1-2-5 steps inside the range", "[svg_chart][report]") {
  // The ranges of the chart (ticks were -6510.1, 761.1, 8032.3) and others.
  for (const auto& [lo, hi] : std::vector<std::pair<double, double>>{
           {-6510.1, 8032.3}, {643.2, 12493.1}, {0.0013, 0.0037}, {-3.0, -2.5}, {7578.8, 8201.1}, {1e6, 3.3e7}}) {
    INFO(lo << " to " << hi);
    const std::vector<double> ticks = round_ticks(lo, hi);
    require_round_ticks(ticks);
    CHECK(ticks.front() >= lo - 1e-9 * (hi - lo));
    CHECK(ticks.back() <= hi + 1e-9 * (hi - lo)); // round_ticks allows a rounding error at the end
    CHECK(ticks.size() <= 7);
  }
  CHECK(round_ticks(1.0, 1.0).empty());
}

TEST_CASE("text_width_estimate is never narrower than Chromium draws DejaVu Sans", "[svg_chart][report]") {
  // Widths measured with getComputedTextLength() in headless Chromium (Debian 12,
  // sans-serif = DejaVu Sans), 12 px: the estimate may be wider, never narrower.
  const std::vector<std::pair<std::string, double>> measured{
      {"g199-123 (claim > check + 5 %)", 196.59}, {"0123456789", 76.36},
      {"mmmmwwwwWWWWMMMM", 174.89},               {"ABCDEFGHIJKLMNOPQRSTUVWXYZ", 209.67},
      {"abcdefghijklmnopqrstuvwxyz", 175.77},     {"dainty_walker_from_seed-g12-i7", 194.14},
      {"-6.5k", 30.38}};
  for (const auto& [text, px] : measured) {
    INFO(text);
    CHECK(text_width_estimate(text, 12) >= px);
    CHECK(text_width_estimate(text, 12) <= 1.3 * px); // and not so wide that charts waste room
  }
}

TEST_CASE("claims chart: round ticks, and every label inside the picture", "[svg_chart][report]") {
  // Long ids, a flagged claim (its label grows a note) and a wide range, as in the
  // issue's report: labels were cut off on the left.
  std::vector<ClaimRow> rows{row("g199-123", 7891.2, 7877.5, 7578.8, 8201.1),
                             row("g199-7", 7700.0, 7650.0, 7100.0, 8032.3),
                             row("dainty_walker_from_seed-g12-i7", 9000.0, 6000.0, -6510.1, 8000.0)};
  REQUIRE(sodaevo::app::claim_flagged(rows[2]));
  for (const bool race : {false, true}) {
    for (ClaimRow& r : rows) r.race = race;
    const std::string svg = sodaevo::app::render_claims_chart(rows);
    pugi::xml_document doc;
    INFO(svg);
    REQUIRE(doc.load_string(svg.c_str()));
    const pugi::xml_node root = doc.child("svg");
    const double width = root.attribute("width").as_double();
    CHECK(std::string(root.attribute("viewBox").value()) == "0 0 " + std::string(root.attribute("width").value()) +
                                                                  " " + root.attribute("height").value());
    std::vector<double> ticks;
    int labels = 0;
    for (const pugi::xpath_node& n : root.select_nodes("//text")) {
      const pugi::xml_node t = n.node();
      const std::string text = t.child_value();
      const double size = t.attribute("font-size") ? t.attribute("font-size").as_double()
                                                   : root.attribute("font-size").as_double();
      const double w = text_width_estimate(text, size), x = t.attribute("x").as_double();
      const std::string anchor = t.attribute("text-anchor").value();
      const double x0 = anchor == "end" ? x - w : anchor == "middle" ? x - w / 2 : x;
      INFO("text '" << text << "' from x " << x0 << " to " << x0 + w << " in width " << width);
      CHECK(x0 >= 0.0);
      CHECK(x0 + w <= width);
      if (std::string(t.attribute("class").value()) == "tick") ticks.push_back(label_value(text));
      if (std::string(t.attribute("class").value()) == "label") ++labels;
    }
    CHECK(labels == 3);
    require_round_ticks(ticks);
  }
}
