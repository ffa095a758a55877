// The SVG chart writer (charts/svg_chart.hpp): well-formed XML with the expected
// elements, log scales, escaping and robustness against odd data.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include <pugixml.hpp>

#include "charts/svg_chart.hpp"

using sodaevo::charts::BarChart;
using sodaevo::charts::LineChart;

namespace {

pugi::xml_document parse(const std::string& svg) {
  pugi::xml_document doc;
  const pugi::xml_parse_result r = doc.load_string(svg.c_str());
  INFO(r.description() << " at offset " << r.offset);
  REQUIRE(r);
  return doc;
}

int count(const pugi::xml_node& root, const char* xpath) {
  return static_cast<int>(root.select_nodes(xpath).size());
}

std::string text_of_class(const pugi::xml_node& root, const char* cls) {
  const std::string q = std::string("//text[@class='") + cls + "']";
  const pugi::xpath_node n = root.select_node(q.c_str());
  return n ? n.node().child_value() : std::string();
}

} // namespace

TEST_CASE("line chart: well-formed SVG with axes, ticks, legend and one polyline per series", "[svg_chart]") {
  LineChart c;
  c.title = "Speed <fast & exact>";
  c.x_axis = {"links", true};
  c.y_axis = {"updates/s", true};
  c.series.push_back({"fast", {10, 100, 1000, 100000}, {1e7, 1e8, 3e8, 4e8}});
  c.series.push_back({"seed", {10, 100, 1000, 100000}, {5e6, 6e6, 6e6, 5e6}, true, true});
  const std::string svg = render_line_chart(c);
  const pugi::xml_document doc = parse(svg);
  const pugi::xml_node root = doc.child("svg");
  REQUIRE(root);
  CHECK(std::string(root.attribute("xmlns").value()) == "http://www.w3.org/2000/svg");
  CHECK(root.attribute("width").as_int() == 760);
  CHECK(text_of_class(root, "title") == "Speed <fast & exact>"); // escaped in the file, intact when parsed
  CHECK(svg.find("&lt;fast &amp; exact&gt;") != std::string::npos);
  CHECK(count(root, "//g[@class='series']/polyline") == 2);
  CHECK(count(root, "//g[@class='series'][@data-name='fast']/circle") == 4);
  CHECK(count(root, "//polyline[@stroke-dasharray]") == 1);
  CHECK(count(root, "//g[@class='legend']/text") == 2);
  CHECK(count(root, "//text[@class='axis-label']") == 2);
  // Log x from 10 to 1e5: a tick per decade, labelled compactly.
  CHECK(count(root, "//g[@class='x-axis']/text[@class='tick']") == 5);
  CHECK(root.select_node("//g[@class='x-axis']/text[.='100k']"));
  CHECK(root.select_node("//g[@class='y-axis']/text[.='100M']"));
  // Every polyline point lies inside the canvas.
  for (const pugi::xpath_node& n : root.select_nodes("//polyline")) {
    std::string pts = n.node().attribute("points").value();
    for (char& ch : pts) ch = ch == ',' ? ' ' : ch;
    std::istringstream in(pts);
    double x = 0, y = 0;
    while (in >> x >> y) {
      CHECK(x >= 0);
      CHECK(x <= 760);
      CHECK(y >= 0);
      CHECK(y <= 460);
    }
  }
}

TEST_CASE("line chart: linear axes, non-finite and non-positive values are left out", "[svg_chart]") {
  LineChart c;
  c.title = "t";
  c.x_axis = {"x", false};
  c.y_axis = {"y", true};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  c.series.push_back({"s", {0, 1, 2, 3}, {nan, -1.0, 10.0, 100.0}});
  const pugi::xml_document doc = parse(render_line_chart(c));
  const pugi::xml_node root = doc.child("svg");
  CHECK(count(root, "//g[@class='series']/circle") == 2); // only the positive, finite points on a log y axis
  CHECK(count(root, "//g[@class='x-axis']/text[@class='tick']") >= 3);
}

TEST_CASE("line chart: empty input still renders", "[svg_chart]") {
  LineChart c;
  const pugi::xml_document doc = parse(render_line_chart(c));
  CHECK(doc.child("svg"));
}

TEST_CASE("bar chart: a group per category, a bar per series, values labelled", "[svg_chart]") {
  BarChart c;
  c.title = "fps";
  c.categories = {"dainty_walker", "carefulslug", "monster_truck"};
  c.y_axis = {"frames per second", true};
  c.series.push_back({"seed", {1e6, 5e5, 4e5}});
  c.series.push_back({"fast", {8e6, 3e6, 2.5e6}});
  const pugi::xml_document doc = parse(render_bar_chart(c));
  const pugi::xml_node root = doc.child("svg");
  CHECK(count(root, "//g[@class='series']/rect") == 6);
  CHECK(count(root, "//g[@class='series']/text[@class='value']") == 6);
  CHECK(count(root, "//g[@class='x-axis']/text[@class='tick']") == 3);
  CHECK(root.select_node("//g[@class='x-axis']/text[.='carefulslug']"));
  CHECK(count(root, "//g[@class='legend']/rect") == 2);
  for (const pugi::xpath_node& n : root.select_nodes("//g[@class='series']/rect")) {
    CHECK(n.node().attribute("height").as_double() >= 0);
  }
  // Taller bar for the larger value within a category.
  const double seed_h = root.select_node("//g[@data-name='seed']/rect").node().attribute("height").as_double();
  const double fast_h = root.select_node("//g[@data-name='fast']/rect").node().attribute("height").as_double();
  CHECK(fast_h > seed_h);
}

TEST_CASE("a long legend name stays inside the picture, in bar and line charts", "[svg_chart]") {
  // The width a name needs is judged with text_width_estimate, which its own test
  // checks against what Chromium draws; here the name must end inside the picture.
  const std::string long_name = "GA (last population as an archive, every creature kept)";
  auto check_legend_fits = [&](const std::string& svg) {
    const pugi::xml_document doc = parse(svg);
    const pugi::xml_node root = doc.child("svg");
    const double width = root.attribute("width").as_double();
    REQUIRE(width > 0);
    int names = 0;
    for (const pugi::xpath_node& n : root.select_nodes("//g[@class='legend']/text")) {
      const std::string text = n.node().child_value();
      const double right = n.node().attribute("x").as_double() + sodaevo::charts::text_width_estimate(text, 12.0);
      INFO(text << " ends at " << right << " in a picture " << width << " wide");
      CHECK(right <= width);
      ++names;
    }
    CHECK(names == 2);
  };
  BarChart bars;
  bars.title = "QD-score";
  bars.categories = {"seed 1", "seed 2"};
  bars.series.push_back({"MAP-Elites", {1e6, 9e5}});
  bars.series.push_back({long_name, {6e4, 8e4}});
  check_legend_fits(render_bar_chart(bars));
  LineChart lines;
  lines.title = "best";
  lines.series.push_back({"MAP-Elites", {1, 2, 3}, {4, 5, 6}});
  lines.series.push_back({long_name, {1, 2, 3}, {1, 2, 3}});
  check_legend_fits(render_line_chart(lines));
}

TEST_CASE("tick labels are compact", "[svg_chart]") {
  CHECK(sodaevo::charts::format_tick(0) == "0");
  CHECK(sodaevo::charts::format_tick(1500) == "1.5k");
  CHECK(sodaevo::charts::format_tick(2e7) == "20M");
  CHECK(sodaevo::charts::format_tick(999.4e6) == "999M");
  CHECK(sodaevo::charts::format_tick(999.96e6) == "1G"); // not "1e+03M"
  CHECK(sodaevo::charts::format_tick(-999.96) == "-1k");
  CHECK(sodaevo::charts::format_tick(3e9) == "3G");
  CHECK(sodaevo::charts::format_tick(0.25) == "0.25");
  CHECK(sodaevo::charts::svg_escape("a<b & \"c\"") == "a&lt;b &amp; &quot;c&quot;");
}

TEST_CASE("line chart: an integer axis has ticks at whole numbers only", "[svg_chart]") {
  LineChart c;
  c.x_axis.label = "generation";
  c.x_axis.integer = true;
  c.y_axis.label = "fitness";
  c.series.push_back({"best", {0, 1, 2}, {10, 20, 15}});
  const pugi::xml_document doc = parse(render_line_chart(c));
  const pugi::xpath_node_set ticks = doc.child("svg").select_nodes("//g[@class='x-axis']/text[@class='tick']");
  REQUIRE(ticks.size() == 3);
  for (const pugi::xpath_node& t : ticks) {
    const double v = std::stod(t.node().child_value());
    CHECK(v == std::round(v));
  }
}
