// Pictures of creatures and runs: the recorded motion (against the reference
// step), the SVG filmstrip (parsed as XML), the HTML player and the run report
// (their embedded data and charts), and the render/report commands' errors.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <pugixml.hpp>

#include "app/filmstrip_svg.hpp"
#include "app/motion.hpp"
#include "app/player_html.hpp"
#include "app/run_report.hpp"
#include "core/continuous_step.hpp"
#include "core/input_error.hpp"
#include "core/model.hpp"
#include "core/step.hpp"
#include "evolve/evaluators/evaluator.hpp"
#include "evolve/runs/evolution_run.hpp"
#include "evolve/runs/replica_check.hpp"
#include "evolve/runs/run_roles.hpp"
#include "evolve/store/run_store.hpp"
#include "evolve/algorithms/variation.hpp"
#include "formats/atomic_file.hpp"
#include "formats/model_file.hpp"
#include "test_support.hpp"

using namespace sodaevo;
using namespace sodaevo::app;
namespace fs = std::filesystem;

namespace {

soda::ModelDef render_dainty() { return soda::read_model_file(test::models_dir() / "dainty_walker.xml").def; }

int count_kind(const soda::ModelDef& def, soda::LinkKind kind) {
  return static_cast<int>(std::count_if(def.links.begin(), def.links.end(), [&](const soda::LinkDef& l) { return l.kind == kind; }));
}
int count_masses(const soda::ModelDef& def) {
  return static_cast<int>(std::count_if(def.nodes.begin(), def.nodes.end(), [](const soda::NodeDef& n) { return !n.fixed; }));
}

/// The JSON inside <script type="application/json" id="ID">.
nlohmann::json embedded_json(const std::string& html, const std::string& id) {
  const std::string open = "<script type=\"application/json\" id=\"" + id + "\">";
  const std::size_t a = html.find(open);
  REQUIRE(a != std::string::npos);
  const std::size_t b = html.find("</script>", a);
  REQUIRE(b != std::string::npos);
  return nlohmann::json::parse(html.substr(a + open.size(), b - a - open.size()));
}

/// Every <svg>...</svg> fragment of an HTML page.
std::vector<std::string> svg_fragments(const std::string& html) {
  std::vector<std::string> out;
  for (std::size_t a = 0; (a = html.find("<svg", a)) != std::string::npos;) {
    const std::size_t b = html.find("</svg>", a);
    REQUIRE(b != std::string::npos);
    out.push_back(html.substr(a, b + 6 - a));
    a = b;
  }
  return out;
}

/// Checks that every element of an HTML page is closed in order (void elements
/// and self-closed SVG elements aside); script and style bodies are skipped.
/// Returns an empty string if so, else what is wrong and where.
std::string unbalanced_html(const std::string& html) {
  static const std::set<std::string> kVoid = {"meta", "input", "br", "img", "link", "hr", "wbr", "source"};
  std::vector<std::string> open;
  for (std::size_t p = html.find('<'); p != std::string::npos; p = html.find('<', p + 1)) {
    if (html.compare(p, 4, "<!--") == 0) {
      p = html.find("-->", p);
      if (p == std::string::npos) return "unclosed comment";
      continue;
    }
    if (html.compare(p, 2, "<!") == 0 || html.compare(p, 2, "<?") == 0) continue;
    const std::size_t end = html.find('>', p);
    if (end == std::string::npos) return "unclosed tag at " + std::to_string(p);
    const bool closing = html[p + 1] == '/';
    const std::size_t name_start = p + (closing ? 2 : 1);
    std::size_t name_end = name_start;
    while (name_end < end && (std::isalnum(static_cast<unsigned char>(html[name_end])) || html[name_end] == '-')) ++name_end;
    const std::string name = html.substr(name_start, name_end - name_start);
    if (name.empty()) return "stray '<' at " + std::to_string(p);
    if (closing) {
      if (open.empty() || open.back() != name) {
        return "</" + name + "> at " + std::to_string(p) + " closes <" + (open.empty() ? std::string("nothing") : open.back()) + ">";
      }
      open.pop_back();
    } else if (html[end - 1] != '/' && kVoid.count(name) == 0) {
      if (name == "script" || name == "style") { // raw text up to the closing tag
        const std::size_t close = html.find("</" + name + ">", end);
        if (close == std::string::npos) return "unclosed <" + name + ">";
        p = close + name.size() + 2;
        continue;
      }
      open.push_back(name);
    }
    p = end;
  }
  return open.empty() ? std::string() : "unclosed <" + open.back() + ">";
}

int render_count_of(const std::string& text, const std::string& needle) {
  int n = 0;
  for (std::size_t p = 0; (p = text.find(needle, p)) != std::string::npos; p += needle.size()) ++n;
  return n;
}

/// A run of `config` evolved to its end in a fresh folder named `name`.
/// The highest "best" of a run's generations.csv.
double best_of_generations_csv(const fs::path& dir) {
  double best = -INFINITY;
  std::istringstream in(soda::read_whole_file(dir / "generations.csv"));
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ls(line);
    std::string cell;
    while (std::getline(ls, cell, ',')) cells.push_back(cell);
    best = std::max(best, std::stod(cells[2]));
  }
  return best;
}

/// Whether the first row of the report's table of best creatures shows `value` (to 0.1).
bool first_table_row_holds(const std::string& html, double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f", value);
  const std::size_t table = html.find("<table class=\"best\">");
  const std::size_t first_row = html.find("<td class=\"n\">1</td>", table);
  if (table == std::string::npos || first_row == std::string::npos) return false;
  return html.find(std::string("<td class=\"n\">") + text + "</td>", first_row) < html.find("</tr>", first_row);
}

fs::path finished_run(const RunConfig& config, const std::string& name) {
  const fs::path dir = test::fresh_temp_dir(name);
  RunStore store = RunStore::create(dir, config, false, "test");
  ThreadEvaluator evaluator(1);
  run_evolution(store, evaluator, {});
  return dir;
}

} // namespace

TEST_CASE("motion: samples every k frames and the last, positions from the reference step", "[render]") {
  const soda::ModelDef def = render_dainty();
  const Motion m = record_motion(def, 1000, 7);
  REQUIRE(m.samples() == 1000 / 7 + 2); // 0, 7, ..., 994, then 1000
  CHECK(m.sample_frames.front() == 0);
  CHECK(m.sample_frames[1] == 7);
  CHECK(m.sample_frames.back() == 1000);
  CHECK(m.masses == count_masses(def));
  CHECK(static_cast<int>(m.links.size()) == static_cast<int>(def.links.size()));

  const soda::Model model = soda::build_model(def);
  soda::State state = soda::make_state(model);
  for (std::size_t s : {std::size_t{0}, std::size_t{50}, m.samples() - 1}) {
    soda::State at = soda::make_state(model);
    soda::run(model, at, m.sample_frames[s]);
    for (int i = 0; i < model.mass_count; ++i) {
      CHECK(m.mass_xy[s][2 * i] == Approx(at.x[i]).margin(0.05 + 1e-9));
      CHECK(m.mass_xy[s][2 * i + 1] == Approx(at.y[i]).margin(0.05 + 1e-9));
    }
    CHECK(m.centroid_x[s] == soda::mass_centroid(model, at).x);
  }
  CHECK(m.distance() != 0.0);
}

TEST_CASE("motion: in the continuous mode, the positions of the continuous stepper", "[render]") {
  const soda::ModelDef def = render_dainty();
  const soda::Stepping verlet{soda::PhysicsMode::Continuous, soda::Integrator::Verlet, 4};
  const Motion m = record_motion(def, 300, 50, verlet);
  const Motion original = record_motion(def, 300, 50);
  REQUIRE(m.samples() == original.samples());
  const soda::Model model = soda::build_model(def);
  soda::State at = soda::make_state(model);
  soda::ContinuousStepper stepper(model, {soda::Integrator::Verlet, 4});
  stepper.run(at, 300);
  for (int i = 0; i < model.mass_count; ++i) {
    CHECK(m.mass_xy.back()[2 * i] == Approx(at.x[i]).margin(0.05 + 1e-9));
    CHECK(m.mass_xy.back()[2 * i + 1] == Approx(at.y[i]).margin(0.05 + 1e-9));
  }
  CHECK(m.centroid_x.back() == soda::mass_centroid(model, at).x);
  CHECK(m.centroid_x.back() != original.centroid_x.back()); // a different integrator moves it differently
}

TEST_CASE("motion: the sample interval keeps at most the asked number of samples", "[render]") {
  for (long long frames : {1LL, 2LL, 999LL, 1000LL, 2200LL, 123457LL}) {
    for (int max_samples : {2, 3, 400, 1000}) {
      const int every = sample_interval(frames, max_samples);
      const long long samples = (frames + every - 1) / every + 1;
      INFO(frames << " frames, at most " << max_samples << ": every " << every);
      CHECK(samples <= std::max<long long>(max_samples, 2));
      CHECK(every >= 1);
    }
  }
}

TEST_CASE("filmstrip: well-formed SVG, a panel per still, every mass and link drawn", "[render]") {
  soda::ModelDef def = render_dainty();
  def.name = "Dainty <& friends>";
  const Motion m = record_motion(def, 1200, 4);
  FilmstripOptions options;
  options.stills = 6;
  const std::string svg = render_filmstrip_svg(m, options);
  pugi::xml_document doc;
  const pugi::xml_parse_result r = doc.load_string(svg.c_str());
  INFO(r.description());
  REQUIRE(r);
  const pugi::xml_node root = doc.child("svg");
  REQUIRE(root);
  CHECK(std::string(root.attribute("xmlns").value()) == "http://www.w3.org/2000/svg");
  CHECK(std::string(root.select_node("//text[@class='title']").node().child_value()) == "Dainty <& friends>");
  const pugi::xpath_node_set stills = root.select_nodes("//g[@class='still']");
  REQUIRE(stills.size() == 6);
  std::vector<long long> frames;
  std::set<std::string> muscle_looks;
  for (const pugi::xpath_node& still : stills) {
    frames.push_back(still.node().attribute("data-frame").as_llong());
    CHECK(still.node().select_nodes(".//circle[@class='mass']").size() == static_cast<std::size_t>(count_masses(def)));
    CHECK(still.node().select_nodes(".//line[@class='muscle']").size() == static_cast<std::size_t>(count_kind(def, soda::LinkKind::Muscle)));
    CHECK(still.node().select_nodes(".//line[@class='spring']").size() == static_cast<std::size_t>(count_kind(def, soda::LinkKind::Spring)));
    CHECK(still.node().select_nodes(".//line[@class='floor']").size() == 1);
    CHECK(still.node().select_nodes(".//text[@class='mark']").size() >= 2);
    std::string look;
    for (const pugi::xpath_node& l : still.node().select_nodes(".//line[@class='muscle']")) {
      look += std::string(l.node().attribute("stroke").value()) + l.node().attribute("stroke-width").value();
    }
    muscle_looks.insert(look);
  }
  CHECK(frames.front() == 0);
  CHECK(frames.back() == 1200);
  for (std::size_t i = 1; i < frames.size(); ++i) CHECK(frames[i] > frames[i - 1]);
  CHECK(muscle_looks.size() > 1); // contraction shows: muscles look different between stills
  // No scripts, no external references: fine for a README.
  CHECK(svg.find("<script") == std::string::npos);
  CHECK(svg.find("href") == std::string::npos);
}

TEST_CASE("player page: self-contained, controls present, every sample embedded", "[render]") {
  const soda::ModelDef def = render_dainty();
  const Motion m = record_motion(def, 600, 3);
  const std::string html = render_player_page(m, "Dainty </script> Walker", "subtitle");
  CHECK(html.rfind("<!DOCTYPE html>", 0) == 0);
  CHECK(unbalanced_html(html) == "");
  CHECK(unbalanced_html("<div><p>x</div></p>") != ""); // the checker itself can fail
  for (const char* part : {"<canvas", "class=\"play\"", "class=\"speed\"", "class=\"slider\"", "class=\"info\"", "id=\"page-errors\""}) {
    INFO(part);
    CHECK(html.find(part) != std::string::npos);
  }
  // Nothing is fetched: no external scripts, styles, images or links.
  CHECK(html.find("src=") == std::string::npos);
  CHECK(html.find("http://") == std::string::npos);
  CHECK(html.find("https://") == std::string::npos);
  CHECK(render_count_of(html, "</script>") == render_count_of(html, "<script")); // the title cannot end a script early
  const nlohmann::json j = embedded_json(html, "player-motion");
  CHECK(j["frames"].size() == 201); // 0, 3, ..., 600
  CHECK(j["frames"].back() == 600);
  CHECK(j["masses"] == count_masses(def));
  REQUIRE(j["xy"].size() == 201);
  for (const auto& row : j["xy"]) CHECK(row.size() == 2 * static_cast<std::size_t>(count_masses(def)));
  CHECK(j["links"].size() == 4 * def.links.size());
  // Positions are tenths of a px: frame 0 is the model as loaded.
  CHECK(j["xy"][0][0].get<double>() / 10 == Approx(def.nodes[0].x).margin(0.05 + 1e-9));
  const nlohmann::json style = embedded_json(html, "soda-style");
  CHECK(style.contains("mass"));
}

TEST_CASE("run report: config, charts, table and players for a finished run", "[render][report]") {
  RunConfig c = test::walker_run_config("report-test", 7, 10, 4, 300, 40);
  c.save.generation_every = 2;
  const fs::path dir = finished_run(c, "report_run");
  const std::string html = run_report_html(dir);
  CHECK(html.find("report-test") != std::string::npos);
  CHECK(unbalanced_html(html) == "");

  // Charts: well-formed SVG; fitness has best, mean and median with a point per generation.
  const std::vector<std::string> svgs = svg_fragments(html);
  REQUIRE(svgs.size() >= 2);
  pugi::xml_document chart;
  REQUIRE(chart.load_string(svgs[0].c_str()));
  CHECK(chart.select_nodes("//g[@class='series']").size() == 3);
  CHECK(chart.select_nodes("//g[@class='series'][@data-name='best']/circle").size() == 4);
  CHECK(chart.select_nodes("//text[@class='axis-label']").size() == 2);
  pugi::xml_document failures;
  REQUIRE(failures.load_string(svgs[1].c_str()));
  CHECK(failures.select_node("//g[@class='series'][@data-name='invalid']"));
  CHECK(failures.select_node("//g[@class='series'][@data-name='diverged']"));

  // Table: the best fitness of generations.csv comes first.
  CHECK(first_table_row_holds(html, best_of_generations_csv(dir)));

  // The Dainty Walker, scored as the run scores, in the table and as a player.
  const Evaluation classic = evaluate_creature(creature_from_seed(render_dainty(), c), c);
  REQUIRE(classic.ok());
  char classic_text[32];
  std::snprintf(classic_text, sizeof classic_text, "%.1f", classic.fitness);
  const std::size_t classic_row = html.find("<tr class=\"classic\">");
  REQUIRE(classic_row != std::string::npos);
  CHECK(html.find(classic_text, classic_row) < html.find("</tr>", classic_row));

  // Players: the champion first, the classic last; each the whole trial.
  const int players = render_count_of(html, "<div class=\"soda-player\"");
  REQUIRE(players >= 2);
  for (int p = 0; p < players; ++p) {
    const nlohmann::json j = embedded_json(html, "player" + std::to_string(p) + "-motion");
    CHECK(j["frames"].back() == c.fitness.settle_frames + c.fitness.frames);
    CHECK(j["scored_from"] == c.fitness.settle_frames);
  }
  CHECK(html.find("Champion") < html.find("Dainty Walker (classic, same fitness settings)"));
  // The champion as the CLI and the page name it, the best of the last generation,
  // with generations counted from 1.
  const std::string csv = soda::read_whole_file(dir / "generations.csv");
  const std::string last_line = csv.substr(csv.rfind('\n', csv.size() - 2) + 1);
  std::vector<std::string> cells;
  std::stringstream cell_stream(last_line);
  for (std::string cell; std::getline(cell_stream, cell, ',');) cells.push_back(cell);
  REQUIRE(cells.size() > 8);
  REQUIRE(cells[0] == "3");
  CHECK_THAT(html, Catch::Contains("Champion " + cells[8] + " (best of the last generation, 4 of 4: fitness "));
  CHECK(html.find("src=") == std::string::npos);
  CHECK(html.find("https://") == std::string::npos);
}

TEST_CASE("run report: a race run reads in frames, fewer is better, and its players race on the terrain",
          "[render][report][race]") {
  RunConfig c = test::walker_run_config("race-report-test", 1, 8, 2, 100, 0);
  c.fitness.kind = FitnessKind::Race;
  c.fitness.race.terrains = {(test::models_dir() / "terrains" / "TerrainFlat.xml").string()};
  c.fitness.race.timeout = 400;
  c.fitness.replicas = c.fitness.replicas_max = 2;
  c.world.evolve = world_parameter_names(); // the racer's CONTENDER rules
  const fs::path dir = finished_run(c, "race_report_run");
  write_run_champions(dir, 2, 3, 1);
  const std::string html = run_report_html(dir);
  CHECK(unbalanced_html(html) == "");
  // A race's fitness is minus its frames: the page shows frames, never px.
  CHECK(html.find("fitness (px)") == std::string::npos);
  const std::size_t table = html.find("<table class=\"best\">");
  REQUIRE(table != std::string::npos);
  CHECK(html.substr(table, html.find("</table>", table) - table).find("px") == std::string::npos);
  const std::size_t champion = html.find("Champion ");
  REQUIRE(champion != std::string::npos);
  CHECK(html.substr(champion, html.find(')', champion) - champion).find(" frames") != std::string::npos);
  CHECK(html.find("distance walked") == std::string::npos);
  const std::vector<std::string> svgs = svg_fragments(html);
  REQUIRE(svgs.size() >= 3);
  CHECK_THAT(svgs[0], Catch::Contains("frames to the finish on TerrainFlat") && Catch::Contains("frames (fewer is better)"));
  CHECK_THAT(html, Catch::Contains("<th>race result (frames, fewer is better)</th>"));
  // The best row holds the fewest frames of generations.csv: minus its best fitness.
  const double best = best_of_generations_csv(dir);
  REQUIRE(best < 0.0);
  CHECK(first_table_row_holds(html, -best));
  // Claims: champions.json holds the selection's fitness (minus frames) and the
  // check in frames; the chart draws both in frames.
  const nlohmann::json champions = nlohmann::json::parse(soda::read_whole_file(dir / "champions.json"));
  REQUIRE(champions.size() >= 1);
  REQUIRE(champions[0].contains("check"));
  char claim[64];
  std::snprintf(claim, sizeof claim, "claim %.1f frames", -champions[0]["selection"]["mean"].get<double>());
  CHECK_THAT(svgs[2], Catch::Contains(claim) && Catch::Contains("race result, frames to the finish"));
  // Players: the race on the terrain, to its start and finish lines.
  const nlohmann::json player = embedded_json(html, "player0-motion");
  REQUIRE(player["marks"].size() == 2);
  CHECK(player["marks"][0]["label"] == "start");
  CHECK(player["marks"][1]["label"] == "finish");
  CHECK(html.find("race on TerrainFlat") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("run report: the players run in the run's physics mode", "[render][report]") {
  RunConfig c = test::walker_run_config("report-mode-test", 3, 6, 2, 200, 20);
  c.fitness.mode = soda::PhysicsMode::Continuous;
  c.fitness.integrator = soda::Integrator::Verlet;
  c.fitness.substeps = 2;
  const fs::path dir = finished_run(c, "report_mode_run");
  const std::string html = run_report_html(dir);
  CHECK(html.find("the run&apos;s physics mode: verlet/2") != std::string::npos);
  CHECK(html.find("soda mode, as the original") == std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("run report: bad run folders are named in the error", "[render][report]") {
  const fs::path dir = test::fresh_temp_dir("bad_run");
  CHECK_THROWS_WITH(run_report_html(dir / "missing"), Catch::Contains("missing") && Catch::Contains("no such run folder"));
  CHECK_THROWS_WITH(run_report_html(dir), Catch::Contains("config.json"));
  // A malformed generations.csv: named with its line.
  RunConfig c;
  c.name = "bad";
  c.population.random_fraction = 1.0;
  soda::write_file_atomically(dir / "config.json", to_json(c).dump());
  soda::write_file_atomically(dir / "generations.csv",
                              "generation,evaluations,best,mean,median,worst,invalid,diverged,best_id\n0,10,abc,1,1,1,0,0,g0-1\n");
  CHECK_THROWS_WITH(run_report_html(dir), Catch::Contains("generations.csv:2") && Catch::Contains("abc"));
  fs::remove(dir / "generations.csv");
  CHECK_THROWS_WITH(run_report_html(dir), Catch::Contains("generations.csv"));
}

TEST_CASE("render and report commands: outputs, and clear errors for bad input", "[render][cli]") {
  const fs::path dir = test::fresh_temp_dir("render_cli");
  const std::string model = (test::models_dir() / "carefulslug.xml").string();
  auto ok = test::run_sodaevo("render " + model + " --frames 300 -o " + (dir / "slug.svg").string());
  INFO(ok.output);
  CHECK(ok.exit_code == 0);
  CHECK(fs::file_size(dir / "slug.svg") > 1000);
  ok = test::run_sodaevo("render " + model + " --frames 300 --every 10 -o " + (dir / "slug.html").string());
  CHECK(ok.exit_code == 0);
  CHECK(embedded_json(soda::read_whole_file(dir / "slug.html"), "player-motion")["frames"].size() == 31);

  ok = test::run_sodaevo("render " + model + " --frames 300 --mode continuous --integrator rk4 --substeps 4 -o " +
                         (dir / "slug_rk4.html").string());
  CHECK(ok.exit_code == 0);
  CHECK(soda::read_whole_file(dir / "slug_rk4.html").find("rk4/4") != std::string::npos);

  auto bad = test::run_sodaevo("render " + model + " --substeps 4 -o " + (dir / "x.svg").string());
  CHECK(bad.exit_code != 0);
  CHECK(bad.output.find("--mode continuous") != std::string::npos);
  CHECK(!fs::exists(dir / "x.svg"));
  bad = test::run_sodaevo("render " + (dir / "nope.xml").string() + " -o " + (dir / "x.svg").string());
  CHECK(bad.exit_code != 0);
  CHECK(bad.output.find("nope.xml") != std::string::npos);
  CHECK(!fs::exists(dir / "x.svg"));
  soda::write_file_atomically(dir / "broken.xml", "<model><nodes><mass id=\"m0\" x=\"1\"");
  bad = test::run_sodaevo("render " + (dir / "broken.xml").string() + " -o " + (dir / "x.svg").string());
  CHECK(bad.exit_code != 0);
  CHECK(bad.output.find("broken.xml") != std::string::npos);
  bad = test::run_sodaevo("render " + model + " -o " + (dir / "x.png").string());
  CHECK(bad.exit_code != 0);
  CHECK(bad.output.find(".html") != std::string::npos);
  bad = test::run_sodaevo("render " + model + " -o " + (dir / "no" / "such" / "dir" / "x.svg").string());
  CHECK(bad.exit_code != 0);
  CHECK(bad.output.find("x.svg") != std::string::npos);
  bad = test::run_sodaevo("report " + (dir / "no_run").string());
  CHECK(bad.exit_code != 0);
  CHECK(bad.output.find("no_run") != std::string::npos);
  CHECK(bad.output.find("terminate") == std::string::npos);
}
