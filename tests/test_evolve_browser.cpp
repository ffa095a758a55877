// Evolve mode of the designer in real Chromium (headless), against the command
// line: the page opened with "#evolve=<base64url config>&run" runs the config on
// its Web Workers (the evolution compiled to WebAssembly, web/evolve_api.cpp), and
// its champion must be `sodaevo evolve`'s for the same config: the same id, the
// same fitness bits and the same bytes of the XML `sodaevo export` writes. A
// config the command line refuses is refused in the page with its message. A
// worker that crashes mid-generation loses no finished generation: the run pauses,
// resumes, and ends with the same champion.
//
// The page is driven by web/chromium_wait.js (Node, the DevTools protocol on a
// pipe), which waits for <html data-evolve-done="1">: --dump-dom's virtual time
// does not wait for Web Workers.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstring>
#include <fstream>

#include <nlohmann/json.hpp>

#include "app/designer_assets.hpp"
#include "app/designer_page.hpp"
#include "browser_support.hpp"
#include "evolve/store/run_reader.hpp"
#include "formats/atomic_file.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace sodaevo::test;

namespace {

const fs::path kSourceDir = fs::path(SODAEVO_MODELS_DIR).parent_path();

/// What the page's #evolve-result says once the run (or its refusal) is done.
nlohmann::json run_in_page(const std::string& chromium, const fs::path& page, const std::string& config_text,
                           const fs::path& work, const std::string& more = "") {
  const std::string url = "file://" + page.string() + "#evolve=" + sodaevo::app::base64url(config_text) + "&run" + more;
  const std::string condition = "document.documentElement.getAttribute('data-evolve-done') === '1'";
  const std::string expression =
      "(function () { var r = document.getElementById('evolve-result'); return r && {id: r.getAttribute('data-id'), "
      "bits: r.getAttribute('data-fitness-bits'), sha256: r.getAttribute('data-xml-sha256'), "
      "error: r.getAttribute('data-error'), archive: r.getAttribute('data-archive-sha256'), resumed: r.getAttribute('data-resumed'), "
      "progress: document.getElementById('ev-progress').textContent, errors: window.sodaErrors || []}; })()";
  return nlohmann::json::parse(wait_in_page(chromium, url, condition, expression, work, 240, /*run_links=*/true));
}

std::string sha256_of(const fs::path& file) {
  const ShellResult r = run_shell("sha256sum " + shell_quoted(file.string()));
  REQUIRE(r.exit_code == 0);
  return r.output.substr(0, 64);
}

std::string require_browser_and_node() {
  const std::string chromium = find_chromium();
  if (chromium.empty()) FAIL("Chromium not found (./build.sh test installs Debian's chromium)");
  if (!sodaevo::app::designer_available()) FAIL(sodaevo::app::designer_unavailable_reason());
  if (sodaevo::app::designer_evolve_js().empty()) FAIL("this sodaevo was built without the evolution in WebAssembly");
  if (run_shell("command -v node").exit_code != 0) FAIL("node not found (Debian's nodejs, which emscripten needs)");
  return chromium;
}

} // namespace

TEST_CASE("Evolve mode runs configs/quick.json in Chromium to the command line's champion, bit for bit",
          "[browser][evolve]") {
  const std::string chromium = require_browser_and_node();
  const fs::path work = fresh_temp_dir("evolve-browser");
  const fs::path page = work / "designer.html";
  soda::write_file_atomically(page, sodaevo::app::designer_page());
  const fs::path config = kSourceDir / "configs" / "quick.json";

  // The command line: evolve, then export the champion as a user would.
  const fs::path native = work / "native";
  REQUIRE(run_sodaevo("evolve " + shell_quoted(config.string()) + " --out " + shell_quoted(native.string()) + " --quiet").exit_code == 0);
  REQUIRE(run_sodaevo("export " + shell_quoted(native.string()) + " --best 1 --out " + shell_quoted((work / "export").string()))
              .exit_code == 0);
  const std::vector<sodaevo::Individual> best = sodaevo::best_individuals(native, 1);
  REQUIRE(best.size() == 1);
  const fs::path champion = work / "export" / ("rank01_" + best[0].id + ".xml");
  REQUIRE(fs::exists(champion));

  const nlohmann::json got = run_in_page(chromium, page, soda::read_whole_file(config), work);
  INFO("page: " << got.dump());
  CHECK(got["errors"].empty());
  CHECK(got["error"].is_null());
  CHECK(got["id"] == best[0].id);
  CHECK(got["bits"] == hex_bits(best[0].evaluation.fitness));
  CHECK(got["sha256"] == sha256_of(champion));
  // Generations counted from 1, as the command line's "gen 10/10"; the champion
  // named as the command line and the report name it.
  const int generations = nlohmann::json::parse(soda::read_whole_file(config))["generations"];
  const std::string last = "generation " + std::to_string(generations) + " of " + std::to_string(generations) + ":";
  CHECK_THAT(got["progress"].get<std::string>(), Catch::Contains(last));
  CHECK_THAT(got["progress"].get<std::string>(), Catch::Contains("champion " + best[0].id + " (best of the last generation)"));

  // A worker crashes part way (its 5th chunk: generation 0 or 1): the generation is
  // dropped, the run pauses, Resume goes on from the last finished generation, and
  // the champion is the same.
  const nlohmann::json crashed = run_in_page(chromium, page, soda::read_whole_file(config), work, "&crash=5&resume");
  INFO("page with a crash: " << crashed.dump());
  CHECK(crashed["resumed"] == "1");
  CHECK(crashed["error"].is_null());
  CHECK(crashed["id"] == best[0].id);
  CHECK(crashed["bits"] == hex_bits(best[0].evaluation.fitness));
  CHECK(crashed["sha256"] == sha256_of(champion));
}

TEST_CASE("Evolve mode refuses a config the command line refuses, with its message", "[browser][evolve]") {
  const std::string chromium = require_browser_and_node();
  const fs::path work = fresh_temp_dir("evolve-browser-refused");
  const fs::path page = work / "designer.html";
  soda::write_file_atomically(page, sodaevo::app::designer_page());
  // Two problems at once (a population of one; random_fraction with no seeds).
  const std::string text = "{\"name\": \"bad\", \"population\": {\"size\": 1}}\n";
  soda::write_file_atomically(work / "config.json", text);
  const ShellResult cli = run_shell("cd " + shell_quoted(work.string()) + " && " + sodaevo_command("evolve config.json --out run"));
  REQUIRE(cli.exit_code != 0);
  const std::string prefix = "sodaevo: error: ";
  REQUIRE(cli.output.rfind(prefix, 0) == 0);
  std::string message = cli.output.substr(prefix.size());
  while (!message.empty() && message.back() == '\n') message.pop_back();
  REQUIRE(message.find("/population/size") != std::string::npos);

  const nlohmann::json got = run_in_page(chromium, page, text, work);
  INFO("page: " << got.dump());
  CHECK(got["errors"].empty());
  REQUIRE(got["error"].is_string());
  CHECK(got["error"].get<std::string>() == message);
}

TEST_CASE("Evolve mode runs a MAP-Elites config to the command line's archive, byte for byte", "[browser][evolve]") {
  const std::string chromium = require_browser_and_node();
  const fs::path work = fresh_temp_dir("evolve-browser-map-elites");
  const fs::path page = work / "designer.html";
  soda::write_file_atomically(page, sodaevo::app::designer_page());
  // A small archive; the seed named by an absolute path, which the page resolves by
  // its file name among its bundled models.
  const std::string text = "{\"name\": \"me_small\", \"seed\": 3, \"algorithm\": \"map-elites\", \"population\": {\"size\": 40, "
                           "\"seed_models\": [\"" + (kSourceDir / "models" / "dainty_walker.xml").string() + "\"], "
                           "\"random_fraction\": 0.9, \"random\": {\"masses_min\": 3, \"masses_max\": 8}}, "
                           "\"fitness\": {\"frames\": 600, \"settle_frames\": 100, \"replicas\": 2, \"replicas_max\": 4}, "
                           "\"map_elites\": {\"descriptors\": [\"width\", \"height\"], \"bins\": [10, 10], "
                           "\"ranges\": [[40, 300], [0, 100]], \"iterations\": 8, \"batch_size\": 30, \"check_replicas\": 0}}\n";
  soda::write_file_atomically(work / "me.json", text);
  const fs::path native = work / "native";
  REQUIRE(run_sodaevo("evolve " + shell_quoted((work / "me.json").string()) + " --out " + shell_quoted(native.string()) + " --quiet")
              .exit_code == 0);

  const nlohmann::json got = run_in_page(chromium, page, text, work);
  INFO("page: " << got.dump());
  CHECK(got["errors"].empty());
  CHECK(got["error"].is_null());
  CHECK(got["archive"] == sha256_of(native / "archive.json"));
}

namespace {

// Draws the fitness chart of ten generations and records what was drawn: every
// text with its box, and the points of the data (the series and the band).
const char* kChartScript = R"js(
var texts = [], data = [], path = [];
var C = CanvasRenderingContext2D.prototype;
var fillText = C.fillText, moveTo = C.moveTo, lineTo = C.lineTo, beginPath = C.beginPath, stroke = C.stroke, fill = C.fill;
C.fillText = function (t, x, y) {
  var m = this.getTransform();
  texts.push({ t: String(t), x: x, y: y, w: this.measureText(t).width, align: this.textAlign, rotated: m.b !== 0 });
  return fillText.apply(this, arguments);
};
C.beginPath = function () { path = []; return beginPath.apply(this, arguments); };
C.moveTo = function (x, y) { path.push([x, y]); return moveTo.apply(this, arguments); };
C.lineTo = function (x, y) { path.push([x, y]); return lineTo.apply(this, arguments); };
C.stroke = function () { if (this.lineWidth > 1) data = data.concat(path); return stroke.apply(this, arguments); };
C.fill = function () { data = data.concat(path); return fill.apply(this, arguments); };
var rows = [];
for (var g = 0; g < 10; ++g) rows.push({ generation: g, best: 1500 + 80 * g, mean: 900 + 60 * g, median: 950 + 50 * g, best_sd: 60 });
var canvas = document.getElementById('chart');
SodaEvolveView.drawFitnessChart(canvas, rows, 'px', function (v) { return v; });
document.getElementById('result').textContent = JSON.stringify({ texts: texts, data: data, w: canvas.width, h: canvas.height });
)js";

} // namespace

TEST_CASE("Evolve mode's fitness chart: round ticks on both axes, the legend outside the data, nothing clipped",
          "[browser][evolve]") {
  const std::string chromium = find_chromium();
  if (chromium.empty()) FAIL("Chromium not found (./build.sh test installs Debian's chromium)");
  const fs::path work = fresh_temp_dir("evolve-chart");
  soda::write_file_atomically(work / "chart.html", "<!DOCTYPE html><html><body><canvas id=\"chart\" width=\"620\" height=\"260\"></canvas>"
                                                   "<pre id=\"result\"></pre><script>\n" +
                                                       std::string(sodaevo::app::designer_asset("evolve_chart.js")) +
                                                       "\n</script><script>\n" + kChartScript + "\n</script></body></html>\n");
  const DumpedPage page = dump_dom(chromium, "file://" + (work / "chart.html").string(), work, "--virtual-time-budget=2000");
  const std::size_t a = page.dom.find("<pre id=\"result\">"), b = page.dom.find("</pre>", a);
  REQUIRE(a != std::string::npos);
  const nlohmann::json got = nlohmann::json::parse(page.dom.substr(a + 17, b - a - 17));
  const double w = got["w"], h = got["h"];
  double x0 = w, x1 = 0, y0 = h, y1 = 0; // the data's box
  for (const auto& p : got["data"]) {
    x0 = std::min(x0, p[0].get<double>()), x1 = std::max(x1, p[0].get<double>());
    y0 = std::min(y0, p[1].get<double>()), y1 = std::max(y1, p[1].get<double>());
  }
  REQUIRE(x1 > x0);
  std::vector<std::string> below, left;
  bool x_title = false, y_title = false;
  for (const auto& t : got["texts"]) {
    const std::string text = t["t"];
    INFO("text '" << text << "' at " << t["x"] << "," << t["y"] << " (" << t["align"] << ", " << t["w"] << " wide)");
    if (t["rotated"].get<bool>()) { // the y axis' title
      y_title = text == "fitness (px)";
      continue;
    }
    const double width = t["w"], x = t["x"], y = t["y"];
    const double l = t["align"] == "center" ? x - width / 2 : t["align"] == "right" ? x - width : x;
    // Inside the canvas: no label cut at an edge.
    CHECK(l >= 0.0);
    CHECK(l + width <= w);
    CHECK(y - 10 >= 0.0);
    CHECK(y + 3 <= h);
    if (text == "generation") x_title = true;
    if (y - 10 > y1) below.push_back(text);
    if (l + width < x0) left.push_back(text);
    // The legend (and any other text) clear of the data.
    const bool overlaps = l < x1 && l + width > x0 && y - 10 < y1 && y + 2 > y0;
    CHECK_FALSE(overlaps);
  }
  CHECK(x_title);
  CHECK(y_title);
  // Generations counted from 1 (the tenth is 10), at round ticks (2, 4, ... 10).
  INFO("below the data: " << nlohmann::json(below).dump() << "; left of it: " << nlohmann::json(left).dump());
  CHECK(std::find(below.begin(), below.end(), "10") != below.end());
  CHECK(std::find(below.begin(), below.end(), "2") != below.end());
  CHECK(std::find(below.begin(), below.end(), "0") == below.end());
  CHECK(left.size() >= 3);
}
