// The racer's contender filter (core/contender_filter.hpp) against the original racer:
// the golden set tests/data/terrain/components (README there), 13 contenders that
// fall apart into pieces, hold fixed nodes, or scale by +inf. Expected values come
// only from the golden files: the lanes at frame 0 (easysoda.jar's own lane model),
// cases.tsv (pieces, kept masses, scale) and races.tsv (EasyRacer.run, T = 10000).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <deque>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <pugixml.hpp>

#include "core/contender_filter.hpp"
#include "core/race_lane.hpp"
#include "core/step.hpp"
#include "evolve/runs/run_roles.hpp"
#include "evolve/problems/race_problem.hpp"
#include "evolve/config/run_config.hpp"
#include "formats/model_file.hpp"
#include "formats/race_file.hpp"
#include "test_support.hpp"

using namespace sodaevo::test;
namespace fs = std::filesystem;

namespace {

fs::path components_dir() { return data_dir() / "terrain" / "components"; }

fs::path terrain_file(const std::string& terrain) {
  return data_dir() / "soda" / "wwagner4_wodka" / "lib_wodka_jar" / "terrain" / terrain;
}

struct Terrain {
  const char* file;  ///< race file, as races.tsv heads its column
  const char* lane;  ///< lane file infix
};
const Terrain kTerrains[] = {{"TerrainFlat.xml", "flat"}, {"TerrainHilly.xml", "hilly"}};

std::vector<std::vector<std::string>> read_tsv(const fs::path& path) {
  std::ifstream in(path);
  REQUIRE(in);
  std::vector<std::vector<std::string>> rows;
  std::string line;
  std::getline(in, line); // header
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::istringstream row(line);
    std::string cell;
    while (std::getline(row, cell, '\t')) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

/// A number as Java writes it (Double.toString: "Infinity", "-Infinity", "NaN" included).
double java_number(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  INFO("number '" << text << "'");
  REQUIRE((end != text.c_str() && *end == '\0'));
  return v;
}

/// The same double, NaN equal to NaN (Java writes every NaN as "NaN").
bool same_value(double a, double b) { return (std::isnan(a) && std::isnan(b)) || same_bits(a, b); }

/// A golden lane file read with its own small parser: c05, c10 and c13 hold
/// Infinity and NaN, which the model reader (rightly) refuses.
soda::ModelDef read_golden_lane(const fs::path& path) {
  pugi::xml_document doc;
  INFO(path.string());
  REQUIRE(doc.load_file(path.c_str()));
  const pugi::xml_node m = doc.child("model");
  soda::ModelDef d;
  d.width = m.child("container").attribute("width").as_int();
  d.height = m.child("container").attribute("height").as_int();
  const auto number = [](pugi::xml_node e, const char* a) { return java_number(e.attribute(a).value()); };
  d.environment = {number(m.child("environment"), "gravity"), number(m.child("environment"), "friction"),
                   number(m.child("environment"), "springyness")};
  d.collisions = {number(m.child("collisions"), "surface_friction"), number(m.child("collisions"), "surface_reflection")};
  d.wave = {number(m.child("wave"), "amplitude"), number(m.child("wave"), "phase"), number(m.child("wave"), "speed")};
  const pugi::xml_node s = m.child("settings");
  const std::string gravity = s.attribute("gravitydirection").value(), wave = s.attribute("wavedirection").value();
  d.settings.gravity_direction = gravity == "down" ? soda::GravityDirection::Down
                                 : gravity == "up" ? soda::GravityDirection::Up
                                                   : soda::GravityDirection::Off;
  d.settings.wave_direction = wave == "forward"   ? soda::WaveDirection::Forward
                              : wave == "reverse" ? soda::WaveDirection::Reverse
                                                  : soda::WaveDirection::Manual;
  d.settings.autoreverse = std::string(s.attribute("autoreverse").value()) == "on";
  std::map<std::string, int> index;
  for (pugi::xml_node n : m.child("nodes").children()) {
    soda::NodeDef node;
    node.id = n.attribute("id").value();
    node.fixed = std::string(n.name()) == "node";
    node.x = number(n, "x");
    node.y = number(n, "y");
    if (!node.fixed) {
      node.vx = number(n, "vx");
      node.vy = number(n, "vy");
    }
    index[node.id] = static_cast<int>(d.nodes.size());
    d.nodes.push_back(node);
  }
  for (pugi::xml_node l : m.child("links").children()) {
    soda::LinkDef link;
    const std::string kind = l.name();
    link.kind = kind == "spring" ? soda::LinkKind::Spring
                : kind == "muscle" ? soda::LinkKind::Muscle
                                   : soda::LinkKind::FixedBar;
    REQUIRE(index.count(l.attribute("a").value()) == 1);
    REQUIRE(index.count(l.attribute("b").value()) == 1);
    link.a = index[l.attribute("a").value()];
    link.b = index[l.attribute("b").value()];
    if (link.kind != soda::LinkKind::FixedBar) link.rest_length = number(l, "restlength");
    if (link.kind == soda::LinkKind::Muscle) {
      link.amplitude = number(l, "amplitude");
      link.phase = number(l, "phase");
    }
    d.links.push_back(link);
  }
  return d;
}

soda::RaceLane lane_of(const std::string& contender, const Terrain& terrain) {
  const soda::RaceDef race = soda::read_race_file(terrain_file(terrain.file));
  const soda::ModelDef c = soda::read_model_file(components_dir() / (contender + ".xml")).def;
  return soda::build_lane(race.terrain, race.constraints, c, contender);
}

/// Mass ids "m<i>" of a cases.tsv cell ("m2,m4,m6"), as node indices.
std::vector<int> mass_indices(const std::string& cell) {
  std::vector<int> out;
  std::istringstream in(cell);
  std::string id;
  while (std::getline(in, id, ',')) out.push_back(std::stoi(id.substr(1)));
  return out;
}

int piece_count(const std::string& cell) {
  int n = 0;
  for (char ch : cell) n += ch == '{' ? 1 : 0;
  return n;
}

} // namespace

TEST_CASE("contender filter: the lanes at frame 0 equal the racer's, bit for bit (pieces, fixed nodes, scale +inf)",
          "[race][golden][components]") {
  int compared = 0;
  for (const auto& row : read_tsv(components_dir() / "races.tsv")) {
    const std::string& name = row.at(0);
    if (row.at(1).rfind("rejected", 0) == 0) continue; // no lane: the next test case
    for (const Terrain& t : kTerrains) {
      INFO(name << " on " << t.file);
      const soda::RaceLane lane = lane_of(name, t);
      const soda::ModelDef gold = read_golden_lane(components_dir() / (name + "." + t.lane + ".lane.xml"));
      const soda::ModelDef& ours = lane.def;
      CHECK(ours.width == gold.width);
      CHECK(ours.height == gold.height);
      CHECK(same_value(ours.environment.gravity, gold.environment.gravity));
      CHECK(same_bits(ours.environment.friction, gold.environment.friction));
      CHECK(same_bits(ours.environment.springyness, gold.environment.springyness));
      CHECK(ours.collisions == gold.collisions);
      CHECK(ours.wave == gold.wave);
      CHECK(ours.settings == gold.settings);
      REQUIRE(ours.nodes.size() == gold.nodes.size());
      for (std::size_t i = 0; i < gold.nodes.size(); ++i) {
        INFO("node " << i << " (" << gold.nodes[i].id << ")");
        CHECK(ours.nodes[i].fixed == gold.nodes[i].fixed);
        CHECK(same_value(ours.nodes[i].x, gold.nodes[i].x));
        CHECK(same_value(ours.nodes[i].y, gold.nodes[i].y));
        CHECK(same_value(ours.nodes[i].vx, gold.nodes[i].vx));
        CHECK(same_value(ours.nodes[i].vy, gold.nodes[i].vy));
      }
      // Every link in the racer's order (bars are tested in link order).
      REQUIRE(ours.links.size() == gold.links.size());
      for (std::size_t i = 0; i < gold.links.size(); ++i) {
        INFO("link " << i);
        CHECK(ours.links[i].kind == gold.links[i].kind);
        CHECK(ours.links[i].a == gold.links[i].a);
        CHECK(ours.links[i].b == gold.links[i].b);
        if (gold.links[i].kind == soda::LinkKind::FixedBar) continue;
        CHECK(same_value(ours.links[i].rest_length, gold.links[i].rest_length));
        CHECK(same_bits(ours.links[i].amplitude, gold.links[i].amplitude));
        CHECK(same_bits(ours.links[i].phase, gold.links[i].phase));
      }
      ++compared;
    }
  }
  CHECK(compared == 24);
}

TEST_CASE("contender filter: pieces, kept masses and scale as cases.tsv lists them", "[race][golden][components]") {
  int compared = 0;
  for (const auto& row : read_tsv(components_dir() / "cases.tsv")) {
    const std::string& name = row.at(0);
    INFO(name);
    const soda::ModelDef c = soda::read_model_file(components_dir() / (name + ".xml")).def;
    const auto masses = std::count_if(c.nodes.begin(), c.nodes.end(), [](const soda::NodeDef& n) { return !n.fixed; });
    REQUIRE(std::to_string(masses) == row.at(1));
    REQUIRE(std::to_string(c.links.size()) == row.at(2));
    if (row.at(4) == "rejected") {
      CHECK_THROWS_AS(soda::filter_contender(c, name), soda::ContenderRejected);
      ++compared;
      continue;
    }
    const soda::FilteredContender f = soda::filter_contender(c, name);
    CHECK(f.pieces.pieces == piece_count(row.at(3)));
    CHECK(f.pieces.kept == mass_indices(row.at(4)));
    const std::string& links = row.at(5);
    CHECK(f.links.size() == (links == "-" ? 0u : static_cast<std::size_t>(std::count(links.begin(), links.end(), ',') + 1)));
    CHECK(same_bits(f.scale, java_number(row.at(6))));
    ++compared;
  }
  CHECK(compared == 13);
}

TEST_CASE("contender filter: a fixed node last in <nodes> gives no result, the reason naming the contender",
          "[race][golden][components]") {
  for (const Terrain& t : kTerrains) {
    INFO(t.file);
    try {
      (void)lane_of("c07_fixed_node_last_rejected", t);
      FAIL("no error");
    } catch (const soda::ContenderRejected& e) {
      CHECK_THAT(e.what(), Catch::Contains("c07_fixed_node_last_rejected") && Catch::Contains("no result") &&
                               Catch::Contains("fixed node"));
    }
  }
  soda::ModelDef empty;
  CHECK_THROWS_AS(soda::filter_contender(empty, "empty.xml"), soda::ContenderRejected);
}

namespace {

/// Every golden race of a terrain: the lanes built and raced by the reference step
/// (run_race), and all together as `race` and the race fitness run them
/// (run_races_together: fused scenes). Rejected contenders give no lane.
struct TerrainRaces {
  std::vector<std::string> names;
  std::vector<double> golden, reference, together;
};

TerrainRaces race_all(const Terrain& t, std::size_t column, const std::function<bool(const std::string&)>& wanted) {
  TerrainRaces r;
  std::deque<soda::RaceLane> lanes; // stable addresses for LaneRace
  std::deque<soda::Model> models;
  for (const auto& row : read_tsv(components_dir() / "races.tsv")) {
    const std::string& name = row.at(0);
    const std::string& cell = row.at(column);
    if (!wanted(name)) continue;
    INFO(name << " on " << t.file << ": original " << cell);
    if (cell.rfind("rejected", 0) == 0) {
      CHECK_THROWS_AS(lane_of(name, t), soda::ContenderRejected);
      continue;
    }
    lanes.push_back(lane_of(name, t));
    models.push_back(soda::build_lane_model(lanes.back()));
    r.names.push_back(name);
    r.golden.push_back(java_number(cell));
    r.reference.push_back(soda::run_race(lanes.back(), models.back(), 10000).result);
  }
  std::vector<soda::State> states;
  for (const soda::Model& m : models) states.push_back(soda::make_state(m));
  std::vector<soda::LaneRace> races;
  for (std::size_t i = 0; i < lanes.size(); ++i) races.push_back({&lanes[i], &models[i], 10000, &states[i]});
  for (const soda::RaceOutcome& o : soda::run_races_together(races)) r.together.push_back(o.result);
  return r;
}

void check_races(const TerrainRaces& r, const Terrain& t) {
  for (std::size_t i = 0; i < r.names.size(); ++i) {
    INFO(r.names[i] << " on " << t.file << ": original " << r.golden[i] << ", ours " << r.reference[i]
                    << " (reference step), " << r.together[i] << " (raced together)");
    CHECK(r.reference[i] == r.golden[i]);
    CHECK(r.together[i] == r.golden[i]);
  }
}

} // namespace

// Independent of the muscle sine: a contender scaled by +inf (c05, c10, c13) is NaN
// from the first update and gets the racer's timeout formula (10076.4052734375 flat,
// 10045.439453125 hilly), by every runner; c07 gets no result.
TEST_CASE("contender filter: a contender scaled by +inf gets the racer's timeout result, a rejected one none",
          "[race][golden][components]") {
  const auto nan_lane = [](const std::string& n) { return n.rfind("c05", 0) == 0 || n.rfind("c10", 0) == 0 ||
                                                           n.rfind("c13", 0) == 0 || n.rfind("c07", 0) == 0; };
  for (std::size_t k = 0; k < 2; ++k) {
    const TerrainRaces r = race_all(kTerrains[k], 1 + k, nan_lane);
    CHECK(r.names.size() == 3);
    check_races(r, kTerrains[k]);
  }
}

// All 24 races. They depend on the muscle sine too: the original's is Java's
// Math.sin. With glibc's sine 9 differ (flat: c03, c08, c09; hilly: c01, c02, c03,
// c06, c08, c09), each also raced alike by its walker alone (next test case), whose
// golden race in ../races.tsv differs the same way: an engine difference, not the filter's.
TEST_CASE("contender filter: race results equal the racer's (T = 10000, flat and hilly)",
          "[race][golden][components][java-sine]") {
  for (std::size_t k = 0; k < 2; ++k) {
    const TerrainRaces r = race_all(kTerrains[k], 1 + k, [](const std::string&) { return true; });
    CHECK(r.names.size() == 12);
    check_races(r, kTerrains[k]);
  }
}

// The README's consequence, whatever the sine: a contender in pieces races exactly as
// its kept piece alone. c01 and c06 keep walker_430, c02 walker_353, c03 walker_121
// (moved), c04 walker_560: the same lane, the same race as the walker's own file.
TEST_CASE("contender filter: a contender in pieces races as its kept walker alone, to the last bit",
          "[race][components]") {
  const std::vector<std::pair<std::string, std::string>> pairs = {{"c01_walker_plus_far_pair", "walker_430"},
                                                                  {"c06_fixed_nodes_dropped", "walker_430"},
                                                                  {"c02_tie_first_mass_wins", "walker_353"},
                                                                  {"c03_masses_beat_links", "walker_121"},
                                                                  {"c04_isolated_masses", "walker_560"}};
  for (const Terrain& t : kTerrains) {
    const soda::RaceDef race = soda::read_race_file(terrain_file(t.file));
    for (const auto& [pieces, walker] : pairs) {
      INFO(pieces << " and " << walker << " on " << t.file);
      const soda::RaceLane a = lane_of(pieces, t);
      const soda::ModelDef w = soda::read_model_file(data_dir() / "terrain" / "contenders" / (walker + ".xml")).def;
      const soda::RaceLane b = soda::build_lane(race.terrain, race.constraints, w, walker);
      CHECK(a.def.nodes == b.def.nodes);
      CHECK(a.def.links == b.def.links);
      const soda::Model ma = soda::build_lane_model(a), mb = soda::build_lane_model(b);
      soda::State sa = soda::make_state(ma), sb = soda::make_state(mb);
      CHECK(soda::run_race_fast(a, ma, 10000, sa).result == soda::run_race_fast(b, mb, 10000, sb).result);
      CHECK(compare_states(ma, sa, sb).empty());
    }
  }
}

// The race fitness races lanes built by the same filter: a rollout of a contender in
// pieces, or of one scaled by +inf (NaN from the first update), scores the racer's
// result, not an error. (The GA itself refuses creatures in pieces, check_creature;
// a rollout of a prepared model does not check.)
TEST_CASE("race problem: rollouts of filtered contenders score the racer's results", "[race][golden][components][evolve]") {
  sodaevo::RunConfig config = walker_run_config("race", 1, 8, 2, 100, 0);
  config.fitness.kind = sodaevo::FitnessKind::Race;
  config.fitness.race.terrains = {terrain_file("TerrainFlat.xml").string()};
  config.fitness.race.timeout = 10000;
  const sodaevo::RaceProblem problem = sodaevo::race_problem_of(config);
  std::map<std::string, double> golden;
  for (const auto& row : read_tsv(components_dir() / "races.tsv")) golden[row.at(0)] = std::strtod(row.at(1).c_str(), nullptr);
  const std::vector<std::string> names = {"c01_walker_plus_far_pair", "c13_zero_length_only", "c05_no_links"};
  std::vector<soda::ModelDef> contenders;
  for (const std::string& n : names) contenders.push_back(soda::read_model_file(components_dir() / (n + ".xml")).def);
  const std::vector<sodaevo::Evaluation> e =
      problem.rollouts({sodaevo::Rollout(&contenders[0]), sodaevo::Rollout(&contenders[1]), sodaevo::Rollout(&contenders[2])});
  for (std::size_t i = 0; i < names.size(); ++i) {
    INFO(names[i] << ": " << e[i].reason);
    REQUIRE(e[i].ok());
    CHECK(e[i].distance == golden.at(names[i]));
  }
}

TEST_CASE("race command: a rejected contender gets no result, the others race, pieces are warned about",
          "[race][components][cli]") {
  const std::string flat = terrain_file("TerrainFlat.xml").string();
  const std::string c07 = (components_dir() / "c07_fixed_node_last_rejected.xml").string();
  const std::string c01 = (components_dir() / "c01_walker_plus_far_pair.xml").string();
  const ShellResult both = run_sodaevo("race " + flat + " " + c07 + " " + c01 + " --timeout 800 --json");
  INFO(both.output);
  REQUIRE(both.exit_code == 0);
  CHECK_THAT(both.output, Catch::Contains("c01_walker_plus_far_pair.xml: not one connected piece") &&
                              Catch::Contains("largest piece: 4 of 6 masses"));
  const auto j = nlohmann::json::parse(both.output.substr(both.output.find('{')));
  REQUIRE(j["contenders"].size() == 2);
  CHECK(j["contenders"][0]["frames"].is_null());
  CHECK(j["contenders"][0]["place"].is_null());
  CHECK_THAT(j["contenders"][0]["no_result"].get<std::string>(), Catch::Contains("c07") && Catch::Contains("no result"));
  CHECK(j["contenders"][1]["frames"].get<double>() == 769.0); // races.tsv: c01 on TerrainFlat.xml
  CHECK(j["contenders"][1]["place"] == 1);
  const ShellResult table = run_sodaevo("race " + flat + " " + c07 + " " + c01 + " --timeout 800");
  CHECK_THAT(table.output, Catch::Contains("no result"));
  // Alone: an error naming it, no table.
  const ShellResult alone = run_sodaevo("race " + flat + " " + c07);
  CHECK(alone.exit_code != 0);
  CHECK_THAT(alone.output, Catch::Contains("c07_fixed_node_last_rejected.xml") && Catch::Contains("no result") &&
                               Catch::Contains("fixed node"));
}
