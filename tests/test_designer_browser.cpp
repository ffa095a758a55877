// The designer and its WebAssembly engine in real Chromium (headless; ./build.sh
// test installs Debian's chromium and emscripten and builds the engine):
//  - the engine in the browser steps every bundled model and every golden-trace
//    model to the native engine's bits (and the golden traces' numbers);
//  - a creature built by synthetic pointer events (three masses, three springs,
//    one made a muscle on the wave bar) is saved, read back natively, and is the
//    model the gestures describe;
//  - share links open (the page's own compressed link, and the plain one reports
//    write); a broken link shows the reader's message and keeps the design;
//  - no console message on any page. Screenshots of construct and simulate mode go
//    to <build>/browser_screenshots (docs/designer-*.png are copies).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <regex>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/designer_assets.hpp"
#include "app/designer_page.hpp"
#include "browser_support.hpp"
#include "formats/atomic_file.hpp"
#include "formats/model_file.hpp"
#include "core/step.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace sodaevo::test;

namespace {

std::string require_chromium() {
  const std::string chromium = find_chromium();
  if (chromium.empty()) {
    FAIL("Chromium not found (looked for `chromium` and `chromium-browser` on PATH): ./build.sh test installs "
         "Debian's chromium, or run `apt-get install chromium`.");
  }
  if (!sodaevo::app::designer_available()) FAIL(sodaevo::app::designer_unavailable_reason());
  return chromium;
}

/// The state as web/engine_api.cpp's soda_state_bits writes it.
std::string state_bits(const soda::State& s) {
  std::string out = "frame " + std::to_string(s.frame) + " wave " + hex_bits(s.wave_phase) + " " +
                    std::to_string(static_cast<int>(s.wave_mode)) + "\n";
  for (std::size_t p = 0; p < s.x.size(); ++p) {
    out += hex_bits(s.x[p]) + " " + hex_bits(s.y[p]) + " " + hex_bits(s.vx[p]) + " " + hex_bits(s.vy[p]) + "\n";
  }
  return out;
}

double from_hex(const std::string& h) {
  const std::uint64_t bits = std::stoull(h, nullptr, 16);
  double v;
  std::memcpy(&v, &bits, sizeof v);
  return v;
}

/// Text between <pre id="ID"> and </pre> in a dumped DOM (HTML-escaped as dumped).
std::string pre_text(const std::string& dom, const std::string& id) {
  const std::string open = "<pre id=\"" + id + "\">";
  const std::size_t a = dom.find(open);
  if (a == std::string::npos) return {};
  const std::size_t b = dom.find("</pre>", a);
  return dom.substr(a + open.size(), b - a - open.size());
}

std::string base64url_decode(const std::string& text) {
  static const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_";
  std::string out;
  unsigned value = 0;
  int bits = 0;
  for (char c : text) {
    const auto k = alphabet.find(c);
    REQUIRE(k != std::string::npos);
    value = value << 6 | static_cast<unsigned>(k);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out += static_cast<char>((value >> bits) & 255);
    }
  }
  return out;
}

void require_no_console(const DumpedPage& p) {
  std::string console;
  for (const std::string& l : p.console) console += l + "\n";
  INFO("console:\n" << console);
  CHECK(p.console.empty());
  CHECK(p.dom.find("data-errors=") == std::string::npos);
}

/// A page with the engine, its API and `script` (no designer UI).
std::string engine_page(const std::string& script) {
  return "<!DOCTYPE html><html><head><meta charset=\"utf-8\"></head><body><pre id=\"result\"></pre>\n<script>\n" +
         std::string(sodaevo::app::designer_engine_js()) + "\n</script>\n<script>\n" +
         std::string(sodaevo::app::designer_asset("soda_engine.js")) + "\n</script>\n<script>\n" + script +
         "\n</script></body></html>\n";
}

const std::vector<long long> kCheckpoints = {0, 1, 2, 10, 100, 300, 800, 2000};

} // namespace

TEST_CASE("designer: the WebAssembly engine steps every bundled and golden model to the native bits", "[browser][designer]") {
  const std::string chromium = require_chromium();
  const fs::path work = fresh_temp_dir("designer-engine");
  std::vector<fs::path> models;
  for (const fs::path& p : xml_files_under(models_dir())) {
    if (p.parent_path().filename() != "terrains") models.push_back(p); // race files, not models
  }
  for (const fs::path& p : xml_files_under(golden_dir())) models.push_back(p);
  REQUIRE(models.size() >= 10);

  // The page steps each model to every checkpoint and writes its state's bits.
  std::string list = "[";
  for (const fs::path& p : models) {
    list += std::string(list.size() > 1 ? "," : "") + "[\"" + p.filename().string() + "\",\"" +
            sodaevo::app::base64url(soda::read_whole_file(p)) + "\"]";
  }
  list += "]";
  std::string checkpoints = "[";
  for (long long c : kCheckpoints) checkpoints += (checkpoints.size() > 1 ? "," : "") + std::to_string(c);
  checkpoints += "]";
  const std::string script = "var MODELS = " + list + ", CHECKPOINTS = " + checkpoints + ";\n" + R"js(
function bytesOf(b64) {
  var s = atob(b64.replace(/-/g, '+').replace(/_/g, '/') + '==='.slice((b64.length + 3) % 4)), out = new Uint8Array(s.length);
  for (var i = 0; i < s.length; ++i) out[i] = s.charCodeAt(i);
  return out;
}
SodaEngine.create(createSodaEngine).then(function (engine) {
  var text = '';
  MODELS.forEach(function (m) {
    engine.loadXml(bytesOf(m[1]), m[0]);
    engine.reset();
    var at = 0;
    CHECKPOINTS.forEach(function (c) {
      engine.step(c - at);
      at = c;
      text += 'model ' + m[0] + '\n' + engine.stateBits();
    });
  });
  document.getElementById('result').textContent = text + 'end\n';
}).catch(function (e) { document.getElementById('result').textContent = 'failed: ' + e; });
)js";
  soda::write_file_atomically(work / "engine.html", engine_page(script));
  const DumpedPage page =
      dump_dom_until(chromium, "file://" + (work / "engine.html").string(), work, "--virtual-time-budget=60000",
                     [](const std::string& dom) { return pre_text(dom, "result").size() > 4; });
  require_no_console(page);
  const std::string result = pre_text(page.dom, "result");
  INFO(result.substr(0, 400));
  REQUIRE(result.size() > 4);
  REQUIRE(result.substr(result.size() - 4) == "end\n");

  // The same natively, model by model and checkpoint by checkpoint.
  std::istringstream in(result);
  std::string line;
  for (const fs::path& path : models) {
    INFO(path.filename().string());
    const Scene scene = load_scene(path);
    soda::State state = soda::make_state(scene.model);
    const fs::path trace = path.parent_path() / (path.stem().string() + ".trace.txt");
    const std::vector<GoldenRow> golden = fs::exists(trace) ? read_golden_trace(trace) : std::vector<GoldenRow>{};
    long long at = 0;
    for (long long c : kCheckpoints) {
      INFO("frame " << c);
      soda::run(scene.model, state, c - at);
      at = c;
      REQUIRE(std::getline(in, line));
      REQUIRE(line == "model " + path.filename().string());
      std::string browser;
      for (std::size_t p = 0; p <= state.x.size(); ++p) {
        REQUIRE(std::getline(in, line));
        browser += line + "\n";
      }
      REQUIRE(browser == state_bits(state));
      // And the original engine's numbers wherever a golden trace has this frame
      // (masses only): every row, with Java's sine (golden/README.md).
      if (c < static_cast<long long>(golden.size())) {
        std::istringstream rows(browser);
        std::getline(rows, line);
        for (int m = 0; m < scene.model.mass_count; ++m) {
          std::string x, y, vx, vy;
          rows >> x >> y >> vx >> vy;
          const auto& g = golden[static_cast<std::size_t>(c)].values;
          CHECK(same_bits(from_hex(x), g[4 * m]));
          CHECK(same_bits(from_hex(y), g[4 * m + 1]));
          CHECK(same_bits(from_hex(vx), g[4 * m + 2]));
          CHECK(same_bits(from_hex(vy), g[4 * m + 3]));
        }
      }
    }
  }
}

namespace {

/// The designer page with `script` run after its own (the page starts itself).
std::string designer_with(const std::string& script, const std::string& initial_xml = {}) {
  std::string page = sodaevo::app::designer_page(initial_xml, initial_xml.empty() ? "" : "dainty_walker.xml");
  const std::size_t body_end = page.rfind("</body>");
  REQUIRE(body_end != std::string::npos);
  return page.insert(body_end, "<pre id=\"test-result\"></pre>\n<script>\n" + script + "\n</script>\n");
}

// Synthetic pointer gestures, in canvas pixels, once the page is ready; the saved
// file (through the download hook) and the share link end up in #test-result.
const char* kConstructScript = R"js(
function at(canvas, x, y) {
  var r = canvas.getBoundingClientRect();
  return { clientX: r.left + x * r.width / canvas.width, clientY: r.top + y * r.height / canvas.height,
           bubbles: true, pointerId: 1, isPrimary: true, button: 0 };
}
function fire(canvas, type, x, y) { canvas.dispatchEvent(new PointerEvent(type, at(canvas, x, y))); }
function click(canvas, x, y) { fire(canvas, 'pointerdown', x, y); fire(canvas, 'pointerup', x, y); }
function drag(canvas, x0, y0, x1, y1) {
  fire(canvas, 'pointerdown', x0, y0);
  for (var k = 1; k <= 5; ++k) fire(canvas, 'pointermove', x0 + (x1 - x0) * k / 5, y0 + (y1 - y0) * k / 5);
  fire(canvas, 'pointerup', x1, y1);
}
var saved = null;
window.sodaDesignerHooks = { download: function (name, bytes) { saved = { name: name, bytes: bytes }; } };
function run() {
  var stage = document.getElementById('stage'), bar = document.getElementById('wave-bar');
  document.getElementById('new-design').click();
  click(stage, 300, 300);                 // mass A
  drag(stage, 300, 300, 400, 300);        // A to a new mass B, a spring
  drag(stage, 400, 300, 350, 220);        // B to a new mass C
  drag(stage, 350, 220, 300, 300);        // C back to A
  click(stage, 350, 300);                 // select the spring A-B
  // Its marker waits in the springs strip; drag it to phase 0.25, amplitude 0.5.
  var W = bar.width, H = bar.height, PAD = 14, base = H - 18;
  drag(bar, PAD + 20, base + 9, PAD + 0.25 * (W - 2 * PAD), base - 0.5 * (base - PAD));
  document.getElementById('save-xml').click();
  var figure = document.getElementById('fig-design').textContent;
  document.getElementById('share').click();
  setTimeout(function () {
    document.getElementById('test-result').textContent = JSON.stringify({
      name: saved && saved.name, xml: saved ? SodaShare.toBase64url(saved.bytes) : '', figure: figure,
      hash: location.hash, message: document.getElementById('message').textContent });
  }, 500);
}
(function wait() {
  if (document.documentElement.getAttribute('data-ready') === '1') run(); else setTimeout(wait, 50);
})();
)js";

/// The JSON value of "key" (a string without escapes) in the test's result.
std::string json_field(const std::string& json, const std::string& key) {
  const std::regex re("\"" + key + "\":\"([^\"]*)\"");
  std::smatch m;
  return std::regex_search(json, m, re) ? m[1].str() : std::string();
}

std::string shown_design(const std::string& dom) {
  const std::regex re("<dd id=\"fig-design\">([^<]*)</dd>");
  std::smatch m;
  return std::regex_search(dom, m, re) ? m[1].str() : std::string();
}

} // namespace

TEST_CASE("designer: a creature built with the mouse saves, reads back natively, and shares by URL", "[browser][designer]") {
  const std::string chromium = require_chromium();
  const fs::path work = fresh_temp_dir("designer-ui");
  const fs::path shots = SODAEVO_SCREENSHOT_DIR;
  fs::create_directories(shots);
  const std::string dainty = soda::read_whole_file(models_dir() / "dainty_walker.xml");

  soda::write_file_atomically(work / "construct.html", designer_with(kConstructScript));
  const DumpedPage built = dump_dom(chromium, "file://" + (work / "construct.html").string(), work, "--virtual-time-budget=20000");
  require_no_console(built);
  const std::string result = pre_text(built.dom, "test-result");
  INFO("test result: " << result);
  REQUIRE(!result.empty());
  CHECK(json_field(result, "figure") == "3 masses, 0 fixed, 2 springs, 1 muscles, 0 bars");
  CHECK(json_field(result, "name") == "creature.xml");

  // The saved file, read by the native reader: the model the gestures describe.
  const std::string xml = base64url_decode(json_field(result, "xml"));
  const soda::LoadedModel loaded = soda::read_model_text(xml, "saved by the designer");
  const soda::ModelDef& d = loaded.def;
  REQUIRE(d.nodes.size() == 3);
  REQUIRE(d.links.size() == 3);
  for (const soda::NodeDef& n : d.nodes) CHECK(!n.fixed);
  // Canonical order: springs first, then the muscle; masses in the order made.
  const soda::NodeDef &a = d.nodes[0], &b = d.nodes[1], &c = d.nodes[2];
  CHECK(b.x - a.x == 100.0);
  CHECK(b.y == a.y);
  CHECK(c.x - a.x == 50.0);
  CHECK(c.y - a.y == 80.0);
  const soda::LinkDef& muscle = d.links[2];
  CHECK(muscle.kind == soda::LinkKind::Muscle);
  CHECK(((muscle.a == 0 && muscle.b == 1) || (muscle.a == 1 && muscle.b == 0)));
  CHECK(muscle.amplitude == 0.5);
  CHECK(muscle.phase == 0.25);
  CHECK(muscle.rest_length == 100.0);
  CHECK(d.links[0].kind == soda::LinkKind::Spring);
  CHECK(d.links[1].kind == soda::LinkKind::Spring);
  CHECK(d.links[0].rest_length == std::sqrt(50.0 * 50.0 + 80.0 * 80.0));
  // The page's writer wrote what the native writer writes for the same model.
  CHECK(soda::write_model_text(d) == xml);

  // The page's own share link (compressed) opens the same design in a new page.
  const std::string hash = json_field(result, "hash");
  REQUIRE(hash.rfind("#model=", 0) == 0);
  soda::write_file_atomically(work / "designer.html", sodaevo::app::designer_page(dainty, "dainty_walker.xml"));
  const std::string url = "file://" + (work / "designer.html").string();
  const DumpedPage shared = dump_dom_until(chromium, url + hash, work, "--virtual-time-budget=20000",
                                           [](const std::string& dom) { return shown_design(dom) != "–"; });
  require_no_console(shared);
  CHECK(shown_design(shared.dom) == "3 masses, 0 fixed, 2 springs, 1 muscles, 0 bars");

  // A report's plain link; a broken link keeps the page's own design and says why.
  const std::string plain = "#" + sodaevo::app::designer_model_fragment(dainty);
  soda::write_file_atomically(work / "empty.html", sodaevo::app::designer_page());
  const auto shown = [](const std::string& dom) { return shown_design(dom) != "–"; };
  const DumpedPage linked =
      dump_dom_until(chromium, "file://" + (work / "empty.html").string() + plain, work, "--virtual-time-budget=20000", shown);
  require_no_console(linked);
  CHECK(shown_design(linked.dom) == "10 masses, 0 fixed, 14 springs, 8 muscles, 0 bars");
  const std::string broken = "#" + sodaevo::app::designer_model_fragment("<model><node id=\"m0\"");
  const DumpedPage refused = dump_dom_until(chromium, url + broken, work, "--virtual-time-budget=20000", shown);
  require_no_console(refused);
  CHECK(shown_design(refused.dom) == "10 masses, 0 fixed, 14 springs, 8 muscles, 0 bars");
  CHECK(refused.dom.find("cannot open the model in this page's address: the shared link:1:") != std::string::npos);

  // Screenshots as a user sees the page: construct mode, and simulate mode at frame 600.
  for (const auto& [mode, suffix] : {std::pair<std::string, std::string>{"construct", ""}, {"simulate", "#mode=simulate&frame=600"}}) {
    const fs::path png = shots / ("designer-" + mode + ".png");
    fs::remove(png);
    const auto r = run_shell(chromium_command(chromium, work / ("shot-" + mode)) +
                             " --hide-scrollbars --window-size=1300,820 --virtual-time-budget=5000 --screenshot=" +
                             png.string() + " '" + url + suffix + "'");
    INFO(r.output);
    CHECK(fs::exists(png));
  }
}

namespace {

/// A creature of `columns` x `rows` masses 6 px apart, springs to the right and
/// down, a muscle along the bottom row: big enough that its replica figure (9,000
/// frames) takes seconds.
std::string grid_creature(int columns, int rows, const std::string& name) {
  std::ostringstream x;
  x << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<model>\n<name>" << name << "</name>\n"
    << "<container width=\"651\" height=\"422\"/>\n<nodes>\n";
  const auto id = [&](int c, int r) { return "m" + std::to_string(r * columns + c); };
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < columns; ++c) x << "<mass id=\"" << id(c, r) << "\" x=\"" << 20 + 6 * c << ".0\" y=\"" << 2 + 6 * r << ".0\" vx=\"0.0\" vy=\"0.0\"/>\n";
  }
  x << "</nodes>\n<links>\n";
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < columns; ++c) {
      if (c + 1 < columns) x << "<spring a=\"" << id(c, r) << "\" b=\"" << id(c + 1, r) << "\" restlength=\"6.0\"/>\n";
      if (r + 1 < rows) x << "<spring a=\"" << id(c, r) << "\" b=\"" << id(c, r + 1) << "\" restlength=\"6.0\"/>\n";
    }
  }
  x << "<muscle a=\"" << id(0, 0) << "\" b=\"" << id(columns - 1, 0) << "\" restlength=\"" << 6 * (columns - 1)
    << ".0\" amplitude=\"0.1\" phase=\"0.5\"/>\n</links>\n</model>\n";
  return x.str();
}

// The longest gap between animation frames (the page's main thread blocked) from
// before the big creature opens until its replica figure would be in, the name
// field through Open and New, and the replica figure (from the worker) against the
// page's own engine for the Dainty Walker.
const char* kResponsiveScript = R"js(
var gap = { max: 0, last: null, frames: 0 };
function frame() {
  var now = performance.now();
  if (gap.last !== null) gap.max = Math.max(gap.max, now - gap.last);
  gap.last = now;
  ++gap.frames;
  if (!window.testResult) requestAnimationFrame(frame);
}
requestAnimationFrame(frame);
function waitFor(test, then) { if (test()) then(); else setTimeout(function () { waitFor(test, then); }, 50); }
var $ = function (id) { return document.getElementById(id); };
waitFor(function () { return document.documentElement.getAttribute('data-ready') === '1'; }, function () {
  // The replica figure as the creature shows: its worker has only begun.
  var result = { bigName: $('design-name').value, bigFigure: $('fig-design').textContent, bigReplicas: $('fig-replicas').textContent };
  setTimeout(function () { // 3 s with the big creature open (its figure is being worked on)
    result.maxGap = gap.max;
    result.frames = gap.frames;
    var app = window.sodaDesigner;
    app.loadBytes(SodaShare.fromBase64url($('dainty').textContent), 'dainty_walker.xml');
    result.openedName = $('design-name').value;
    waitFor(function () { return /px\/frame/.test($('fig-replicas').textContent); }, function () {
      result.workerReplicas = $('fig-replicas').textContent;
      var r = app.engine.replicas(8, 1000, 0.002);
      result.pageReplicas = r.mean.toFixed(2) + ' \u00b1 ' + r.sd.toFixed(2) + ' px/frame';
      $('new-design').click();
      result.newName = $('design-name').value;
      window.testResult = result;
    });
  }, 3000);
});
)js";

} // namespace

namespace {

/// The designer opened with a 5,000-mass creature (kResponsiveScript's result).
nlohmann::json open_big_creature(const std::string& chromium, const fs::path& work) {
  const std::string big = grid_creature(100, 50, "Big Grid");
  std::string page = designer_with(kResponsiveScript, big);
  page.insert(page.rfind("<pre id=\"test-result\">"),
              "<script type=\"text/plain\" id=\"dainty\">" +
                  sodaevo::app::base64url(soda::read_whole_file(models_dir() / "dainty_walker.xml")) + "</script>\n");
  soda::write_file_atomically(work / "big.html", page);
  return nlohmann::json::parse(wait_in_page(
      chromium, "file://" + (work / "big.html").string(), "window.testResult !== undefined",
      "(function () { var r = window.testResult; r.errors = window.sodaErrors || []; return r; })()", work, 120));
}

} // namespace

TEST_CASE("designer: a 5,000-mass creature's replica figure comes from a worker, the name field follows the design",
          "[browser][designer]") {
  const std::string chromium = require_chromium();
  const nlohmann::json got = open_big_creature(chromium, fresh_temp_dir("designer-big"));
  INFO("page: " << got.dump());
  CHECK(got["errors"].empty());
  CHECK(got["bigFigure"] == "5000 masses, 0 fixed, 9850 springs, 1 muscles, 0 bars");
  CHECK(got["bigName"] == "Big Grid");
  // Frames kept coming while the figure was worked on (13 s on the page's thread before).
  CHECK(got["frames"].get<int>() >= 30);
  CHECK(got["bigReplicas"] == "working\u2026");
  // The name field follows what is opened, and New.
  CHECK(got["openedName"] == "Dainty Walker - Ed Burton");
  CHECK(got["newName"] == "");
  // The worker's figure is the page engine's.
  CHECK(got["workerReplicas"] == got["pageReplicas"]);
}

TEST_CASE("designer: opening a 5,000-mass creature blocks no animation frame for 200 ms", "[browser][designer]") {
  const std::string chromium = require_chromium();
  const nlohmann::json got = open_big_creature(chromium, fresh_temp_dir("designer-big-gap"));
  INFO("page: " << got.dump());
  CHECK(got["maxGap"].get<double>() < 200.0);
}

TEST_CASE("designer: an #evolve=...&run link asks before running, with its config as the start", "[browser][designer][evolve]") {
  const std::string chromium = require_chromium();
  const fs::path work = fresh_temp_dir("designer-evolve-link");
  soda::write_file_atomically(work / "designer.html", sodaevo::app::designer_page());
  const std::string config = soda::read_whole_file(fs::path(SODAEVO_MODELS_DIR).parent_path() / "configs" / "quick.json");
  const nlohmann::json given = nlohmann::json::parse(config);
  const std::string url = "file://" + (work / "designer.html").string() + "#evolve=" + sodaevo::app::base64url(config) + "&run";
  // The panel is built and the link read in one task: once #ev-progress exists.
  const nlohmann::json got = nlohmann::json::parse(wait_in_page(
      chromium, url, "document.getElementById('ev-progress') !== null",
      "(function () { var $ = function (id) { return document.getElementById(id); }; return {state: window.sodaEvolve.state, "
      "source: $('ev-source').value, sourceText: $('ev-source').selectedOptions[0].textContent, generations: $('ev-generations').value, "
      "population: $('ev-population').value, progress: $('ev-progress').textContent, errors: window.sodaErrors || []}; })()",
      work, 120));
  INFO("page: " << got.dump());
  CHECK(got["errors"].empty());
  CHECK(got["state"] == "idle"); // not running: it asks
  CHECK_THAT(got["progress"].get<std::string>(), Catch::StartsWith("This link asks to run the link's config (quick)"));
  CHECK(got["source"] == "link");
  CHECK(got["sourceText"] == "the link's config (quick)");
  CHECK(got["generations"] == std::to_string(given["generations"].get<int>()));
  CHECK(got["population"] == std::to_string(given["population"]["size"].get<int>()));
}
