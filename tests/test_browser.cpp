// The pictures in a real browser: headless Chromium (Debian package `chromium`,
// installed by ./build.sh test) opens a rendered player, a filmstrip and a run
// report written by `evolve`. Checked: no console message at all (script errors,
// failed loads and console.error all land there), every player started, and the
// canvas read back at two frames shows the creature (ink in its box) and shows
// it moving (the box's pixels differ). Screenshots go to
// <build>/browser_screenshots for people to look at.
#include <catch2/catch.hpp>

#include <algorithm>
#include <fstream>
#include <map>
#include <regex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "formats/atomic_file.hpp"

#include "browser_support.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using sodaevo::test::chromium_command;
using sodaevo::test::find_chromium;
using sodaevo::test::run_shell;
using sodaevo::test::run_sodaevo;

namespace {

/// Headless Chromium runs animation frames only in virtual time, and only a few.
const std::string kLetItPlay = "--virtual-time-budget=5000 --run-all-compositor-stages-before-draw";

struct Player {
  bool ready = false;
  long long shown = -1; ///< the frame in its info line
  long long frame = -1;
  long long ink = -1;
  std::string hash;
};

struct LoadedPage {
  std::string dom;
  std::vector<std::string> console; ///< CONSOLE lines of Chromium's log
  std::vector<Player> players;
};

/// The page's <html ...> start tag (where pages and tests leave data-* attributes).
std::string html_tag(const std::string& dom) {
  const std::size_t at = dom.find("<html");
  return at == std::string::npos ? std::string() : dom.substr(at, dom.find('>', at) - at);
}

std::string attribute(const std::string& tag, const std::string& name) {
  const std::regex re(" " + name + "=\"([^\"]*)\"");
  std::smatch m;
  return std::regex_search(tag, m, re) ? m[1].str() : std::string();
}

/// Opens `page` (at `frame` if >= 0, else playing as a user sees it) and dumps the DOM.
LoadedPage load(const std::string& chromium, const fs::path& page, long long frame, const fs::path& work,
                const std::string& extra_flags = "", const std::string& more_fragment = "") {
  static int runs = 0;
  const fs::path profile = work / ("profile" + std::to_string(++runs));
  const fs::path dom = work / ("dom" + std::to_string(runs) + ".html"), log = work / ("log" + std::to_string(runs) + ".txt");
  const std::string url = "file://" + fs::absolute(page).string() + (frame >= 0 ? "#frame=" + std::to_string(frame) + more_fragment : "");
  const auto r = run_shell("( " + chromium_command(chromium, profile) + " " + extra_flags + " --dump-dom '" + url + "' > " + dom.string() +
                           " 2> " + log.string() + " )");
  INFO("chromium on " << url << ":\n" << r.output);
  REQUIRE(r.exit_code == 0);
  LoadedPage p;
  p.dom = soda::read_whole_file(dom);
  std::ifstream in(log);
  for (std::string line; std::getline(in, line);) {
    if (line.find(":CONSOLE") != std::string::npos) p.console.push_back(line);
  }
  const std::regex player_tag("<div class=\"soda-player\"[^>]*>");
  const std::regex info("<div class=\"info\">frame ([0-9]+)");
  for (auto it = std::sregex_iterator(p.dom.begin(), p.dom.end(), player_tag); it != std::sregex_iterator(); ++it) {
    const std::string tag = it->str();
    Player pl;
    pl.ready = attribute(tag, "data-ready") == "1";
    const std::string f = attribute(tag, "data-frame"), ink = attribute(tag, "data-ink");
    pl.frame = f.empty() ? -1 : std::stoll(f);
    pl.ink = ink.empty() ? -1 : std::stoll(ink);
    pl.hash = attribute(tag, "data-hash");
    std::smatch m;
    const std::string rest = p.dom.substr(static_cast<std::size_t>(it->position()));
    if (std::regex_search(rest, m, info)) pl.shown = std::stoll(m[1].str());
    p.players.push_back(pl);
  }
  return p;
}

void screenshot(const std::string& chromium, const std::string& url, const fs::path& png, const std::string& size,
                const fs::path& work) {
  static int runs = 0;
  fs::remove(png);
  const auto r = run_shell(chromium_command(chromium, work / ("shot-profile" + std::to_string(++runs))) +
                           " --hide-scrollbars --window-size=" + size + " --screenshot=" + png.string() + " '" + url + "'");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  REQUIRE(fs::exists(png));
  CHECK(fs::file_size(png) > 1000);
}

void require_clean(const LoadedPage& p) {
  std::string console;
  for (const std::string& l : p.console) console += l + "\n";
  INFO("console:\n" << console);
  CHECK(p.console.empty());
  CHECK(p.dom.find("data-errors=") == std::string::npos);
  CHECK(p.dom.find("<pre id=\"page-errors\" hidden=\"\"></pre>") != std::string::npos);
}

/// Players at two frames: each drawn (ink in the creature's box) and moving.
void require_drawn_and_moving(const LoadedPage& a, const LoadedPage& b, long long frame_a, long long frame_b) {
  REQUIRE(!a.players.empty());
  REQUIRE(a.players.size() == b.players.size());
  for (std::size_t i = 0; i < a.players.size(); ++i) {
    INFO("player " << i);
    CHECK(a.players[i].ready);
    CHECK(b.players[i].ready);
    CHECK(a.players[i].frame <= frame_a);
    CHECK(a.players[i].frame > frame_a - 20);
    CHECK(b.players[i].frame <= frame_b);
    CHECK(a.players[i].ink > 50);
    CHECK(b.players[i].ink > 50);
    CHECK(!a.players[i].hash.empty());
    CHECK(a.players[i].hash != b.players[i].hash);
  }
}

} // namespace

TEST_CASE("browser: the player, the filmstrip and the run report work in headless Chromium", "[browser]") {
  const std::string chromium = find_chromium();
  if (chromium.empty()) {
    FAIL("Chromium not found (looked for `chromium` and `chromium-browser` on PATH). The browser test needs the "
         "Debian package `chromium`: ./build.sh test installs it, or run `apt-get install chromium`.");
  }
  const fs::path work = sodaevo::test::fresh_temp_dir("browser");
  const fs::path shots = SODAEVO_SCREENSHOT_DIR;
  fs::create_directories(shots);
  const fs::path dainty = fs::absolute(sodaevo::test::models_dir() / "dainty_walker.xml");

  // Catch runs the body once per section: each section makes only what it opens.
  SECTION("render: one player, drawn and moving, no console messages") {
    const auto r = run_sodaevo("render " + dainty.string() + " --frames 800 -o " + (work / "dainty.html").string());
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    const LoadedPage a = load(chromium, work / "dainty.html", 100, work);
    const LoadedPage b = load(chromium, work / "dainty.html", 700, work);
    require_clean(a);
    require_clean(b);
    REQUIRE(a.players.size() == 1);
    require_drawn_and_moving(a, b, 100, 700);
    // As a user opens it: playing. Virtual time lets a few animation frames run.
    // On a busy machine headless Chromium may end the virtual-time budget before
    // the first animation frame, so the page gets up to four loads with growing
    // budgets; a player that never moves past frame 0 still fails.
    LoadedPage playing;
    for (int budget = 5000; budget <= 40000; budget *= 2) {
      playing = load(chromium, work / "dainty.html", -1, work,
                     "--virtual-time-budget=" + std::to_string(budget) + " --run-all-compositor-stages-before-draw");
      if (playing.players.size() == 1 && playing.players[0].shown > 0) break;
    }
    require_clean(playing);
    REQUIRE(playing.players.size() == 1);
    CHECK(playing.players[0].ready);
    CHECK(playing.players[0].shown > 0);
    const std::string url = "file://" + (work / "dainty.html").string();
    screenshot(chromium, url + "#frame=100", shots / "render_frame100.png", "800,520", work);
    screenshot(chromium, url + "#frame=700", shots / "render_frame700.png", "800,520", work);
    CHECK(soda::read_whole_file(shots / "render_frame100.png") != soda::read_whole_file(shots / "render_frame700.png"));
  }
  SECTION("render and race: a creature's name cannot open or close an element; the player plays, nothing runs") {
    // Names that ended the player's <script type="application/json"> early (a
    // "</script>") or kept it open past its end tag ("<!--<script>": the HTML
    // parser's escaped script state), swallowing the player's own script.
    const std::string dainty_xml = soda::read_whole_file(dainty);
    const std::string payload = "document.documentElement.setAttribute('data-injected','1')";
    // As written in the XML (&lt; is <; &#x2028; is U+2028, which ends a line in old JavaScript).
    const std::vector<std::string> names = {"&lt;!--&lt;script>", "&lt;/script>&lt;script>" + payload + "&lt;/script>",
                                            "&lt;!--&lt;script>&#x2028;&lt;/script>&lt;script>" + payload + "//&amp;"};
    for (std::size_t k = 0; k < names.size(); ++k) {
      INFO("name " << names[k]);
      const std::string escaped = names[k];
      std::string xml = dainty_xml;
      const std::string old_name = "<name>Dainty Walker - Ed Burton</name>";
      REQUIRE(xml.find(old_name) != std::string::npos);
      xml.replace(xml.find(old_name), old_name.size(), "<name>" + escaped + "</name>");
      const fs::path model = work / ("named" + std::to_string(k) + ".xml");
      const fs::path page = work / ("named" + std::to_string(k) + ".html");
      soda::write_file_atomically(model, xml);
      const auto r = run_sodaevo("render " + model.string() + " --frames 800 -o " + page.string());
      INFO(r.output);
      REQUIRE(r.exit_code == 0);
      const LoadedPage a = load(chromium, page, 100, work);
      const LoadedPage b = load(chromium, page, 700, work);
      require_clean(a);
      require_clean(b);
      REQUIRE(a.players.size() == 1);
      require_drawn_and_moving(a, b, 100, 700);
      // The payload's text is in the page (the title shows the name); its effect is not.
      CHECK(html_tag(a.dom).find("data-injected") == std::string::npos);
      CHECK(html_tag(b.dom).find("data-injected") == std::string::npos);
    }
    const fs::path flat = fs::absolute(sodaevo::test::models_dir() / "terrains" / "TerrainFlat.xml");
    const auto r = run_sodaevo("race " + flat.string() + " " + (work / "named1.xml").string() + " --render " +
                               (work / "named_race.html").string());
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    const LoadedPage race = load(chromium, work / "named_race.html", 20, work);
    require_clean(race);
    REQUIRE(race.players.size() == 1);
    CHECK(race.players[0].ready);
    CHECK(race.players[0].ink > 50);
    CHECK(html_tag(race.dom).find("data-injected") == std::string::npos);
  }
  SECTION("race render: the info line counts down to the finish, then says it is past") {
    const fs::path flat = fs::absolute(sodaevo::test::models_dir() / "terrains" / "TerrainFlat.xml");
    const fs::path racer = fs::absolute(sodaevo::test::models_dir() / "wodka_ga109.xml"); // 118 frames
    const auto r = run_sodaevo("race " + flat.string() + " " + racer.string() + " --render " + (work / "race.html").string());
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    const LoadedPage early = load(chromium, work / "race.html", 20, work);
    const LoadedPage done = load(chromium, work / "race.html", 100000, work); // the last sample
    require_clean(early);
    require_clean(done);
    const auto info_line = [](const std::string& dom) {
      std::smatch m;
      return std::regex_search(dom, m, std::regex("<div class=\"info\">([^<]*)</div>")) ? m[1].str() : std::string();
    };
    INFO("info lines: " << info_line(early.dom) << " | " << info_line(done.dom));
    CHECK(info_line(early.dom).find(" px to the finish") != std::string::npos);
    CHECK(info_line(early.dom).find("px/frame") == std::string::npos); // a race counts frames
    CHECK(info_line(done.dom).find("past the finish") != std::string::npos);
  }
  SECTION("race render: the terrain lies on the ruler's floor; a long name wraps instead of stretching the controls") {
    const fs::path flat = fs::absolute(sodaevo::test::models_dir() / "terrains" / "TerrainFlat.xml");
    std::string xml = soda::read_whole_file(dainty);
    const std::string old_name = "<name>Dainty Walker - Ed Burton</name>";
    REQUIRE(xml.find(old_name) != std::string::npos);
    xml.replace(xml.find(old_name), old_name.size(), "<name>" + std::string(150, 'W') + "</name>");
    soda::write_file_atomically(work / "long.xml", xml);
    const auto r = run_sodaevo("race " + flat.string() + " " + (work / "long.xml").string() + " --render " + (work / "long.html").string());
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    // Measured in the page once the player drew: in two columns clear of the
    // creature, the rows where the bar colour and the floor (its line or the ground
    // under it) begin; and how much wider than the canvas the controls are.
    const std::string measure = R"js(<script>
(function () {
  var S = JSON.parse(document.getElementById('soda-style').textContent);
  var root = document.querySelector('.soda-player'), canvas = root.querySelector('canvas');
  var W = canvas.width, H = canvas.height, copy = document.createElement('canvas');
  copy.width = W; copy.height = H;
  var g = copy.getContext('2d', { willReadFrequently: true }); // read back twice: no console note
  g.drawImage(canvas, 0, 0);
  var px = g.getImageData(0, 0, W, H).data;
  function rgb(hex) { return [1, 3, 5].map(function (i) { return parseInt(hex.substr(i, 2), 16); }); }
  function near(k, c) { return Math.abs(px[k] - c[0]) + Math.abs(px[k + 1] - c[1]) + Math.abs(px[k + 2] - c[2]) < 40; }
  var gaps = [];
  [12, W - 12].forEach(function (x) {
    var bar = -1, floor = -1;
    for (var y = 0; y < H; ++y) {
      var k = 4 * (y * W + x);
      if (bar < 0 && near(k, rgb(S.bar))) bar = y;
      if (floor < 0 && (near(k, rgb(S.floor)) || near(k, rgb(S.ground)))) floor = y;
    }
    gaps.push(bar >= 0 && floor >= 0 ? Math.abs(bar - floor) : 999);
  });
  var controls = root.querySelector('.controls').getBoundingClientRect().width;
  document.documentElement.setAttribute('data-test-bar-gap', String(Math.min.apply(null, gaps)));
  document.documentElement.setAttribute('data-test-controls-excess', String(Math.round(controls - canvas.getBoundingClientRect().width)));
})();
</script>
)js";
    std::string page = soda::read_whole_file(work / "long.html");
    REQUIRE(page.rfind("</body>") != std::string::npos);
    page.insert(page.rfind("</body>"), measure);
    soda::write_file_atomically(work / "long_measured.html", page);
    const LoadedPage p = load(chromium, work / "long_measured.html", 20, work);
    require_clean(p);
    const std::string gap = attribute(html_tag(p.dom), "data-test-bar-gap");
    const std::string excess = attribute(html_tag(p.dom), "data-test-controls-excess");
    INFO("bar gap " << gap << " px, controls wider than the canvas by " << excess << " px");
    REQUIRE(!gap.empty());
    REQUIRE(!excess.empty());
    CHECK(std::stoi(gap) <= 5); // the bar's upper edge, half its 4 px above the floor line (37 px before)
    CHECK(std::stoi(excess) <= 2);
    screenshot(chromium, "file://" + (work / "long.html").string() + "#frame=60", shots / "race_long_name.png", "800,560", work);
  }
  SECTION("filmstrip: opens without console messages") {
    const auto r = run_sodaevo("render " + dainty.string() + " --frames 800 -o " + (work / "dainty.svg").string());
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    const LoadedPage p = load(chromium, work / "dainty.svg", -1, work);
    CHECK(p.console.empty());
    CHECK(p.dom.find("class=\"still\"") != std::string::npos);
    screenshot(chromium, "file://" + (work / "dainty.svg").string(), shots / "filmstrip.png", "1600,320", work);
  }
  SECTION("report: every player drawn and moving, no console messages") {
    // A short run; evolve writes its report.
    soda::write_file_atomically(work / "config.json",
                        "{\"name\": \"browser\", \"seed\": 3, \"generations\": 3,"
                        " \"population\": {\"size\": 8, \"seed_models\": [\"" + dainty.string() + "\"], \"random_fraction\": 0.5},"
                        " \"fitness\": {\"frames\": 400, \"settle_frames\": 50}, \"save\": {\"generation_every\": 1}}");
    const auto r = run_sodaevo("evolve " + (work / "config.json").string() + " --out " + (work / "run").string() + " --quiet --threads 1");
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    const fs::path report = work / "run" / "report.html";
    REQUIRE(fs::exists(report));
    const LoadedPage a = load(chromium, report, 60, work);
    const LoadedPage b = load(chromium, report, 400, work);
    require_clean(a);
    require_clean(b);
    CHECK(a.players.size() >= 2); // the champion and the Dainty Walker at least
    require_drawn_and_moving(a, b, 60, 400);
    CHECK(a.dom.find("<svg") != std::string::npos);
    const LoadedPage playing = load(chromium, report, -1, work, kLetItPlay);
    require_clean(playing);
    // Playing itself is checked on the render page above (same player code); in
    // the report, headless virtual time may not reach the players' first animation
    // frame on a busy machine, so only that each one started is required here.
    for (const Player& p : playing.players) CHECK(p.ready);
    const std::string url = "file://" + report.string();
    screenshot(chromium, url + "#frame=60", shots / "report_frame60.png", "1400,2000", work);
    screenshot(chromium, url + "#frame=400", shots / "report_frame400.png", "1400,2000", work);
    CHECK(soda::read_whole_file(shots / "report_frame60.png") != soda::read_whole_file(shots / "report_frame400.png"));
  }
  SECTION("MAP-Elites archive: a click on a cell plays its elite") {
    soda::write_file_atomically(work / "me.json",
                        "{\"name\": \"browser-me\", \"seed\": 2, \"algorithm\": \"map-elites\","
                        " \"population\": {\"size\": 12, \"seed_models\": [\"" + dainty.string() + "\"], \"random_fraction\": 0.75},"
                        " \"fitness\": {\"frames\": 400, \"settle_frames\": 50},"
                        " \"map_elites\": {\"iterations\": 4, \"batch_size\": 12}}");
    const auto r = run_sodaevo("evolve " + (work / "me.json").string() + " --out " + (work / "me").string() + " --quiet --threads 1");
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    const fs::path page = work / "me" / "archive.html";
    REQUIRE(fs::exists(page));
    const nlohmann::json archive = nlohmann::json::parse(soda::read_whole_file(work / "me" / "archive.json"));
    REQUIRE(archive["cells"].size() >= 2);
    const nlohmann::json& cell = archive["cells"][1];
    const std::string click = "&cell=" + std::to_string(cell["cell"].get<long long>());
    // The page keeps a player in a <template> that a click copies; only started ones count.
    const auto started = [](LoadedPage p) {
      p.players.erase(std::remove_if(p.players.begin(), p.players.end(), [](const Player& q) { return !q.ready; }),
                      p.players.end());
      return p;
    };
    const LoadedPage a = started(load(chromium, page, 60, work, "", click));
    const LoadedPage b = started(load(chromium, page, 400, work, "", click));
    require_clean(a);
    require_clean(b);
    REQUIRE(a.players.size() == 1);
    require_drawn_and_moving(a, b, 60, 400);
    // The player shows the elite of the clicked cell.
    CHECK_THAT(a.dom, Catch::Contains("<div id=\"player-slot\" data-id=\"" + cell["id"].get<std::string>() + "\">"));
    CHECK_THAT(a.dom, Catch::Contains("class=\"cell chosen\""));
    // Without a click: the heat maps and no player.
    const LoadedPage idle = started(load(chromium, page, 60, work));
    require_clean(idle);
    CHECK(idle.players.empty());
    screenshot(chromium, "file://" + page.string() + "#frame=300" + click, shots / "archive.png", "1400,1400", work);
    // The selector for the third descriptor: one map of the best over it, the bins hidden.
    const LoadedPage best = started(load(chromium, page, 60, work, "", "&third=best"));
    require_clean(best);
    CHECK_THAT(best.dom, Catch::Contains("<select id=\"third\">"));
    CHECK_THAT(best.dom, Catch::Contains("<div class=\"map\" data-panel=\"best\"><div>"));
    CHECK_THAT(best.dom, Catch::Contains("<div class=\"map\" data-panel=\"0\" hidden=\"\">"));
    // By default every bin is shown and the best map is not.
    CHECK_THAT(idle.dom, Catch::Contains("<div class=\"map\" data-panel=\"0\"><div>"));
    CHECK_THAT(idle.dom, Catch::Contains("<div class=\"map\" data-panel=\"best\" hidden=\"\">"));
  }
}
