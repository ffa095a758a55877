// Race fitness (/fitness/kind "race", evolve/problems/race_problem.hpp) and the fast race
// runner (core/race_lane.hpp run_race_fast): the fast runner against the original
// racer's golden results (tests/data/terrain/races.tsv, copied from
// ../shared/models/soda/golden/terrain) and against the reference runner; a race
// run's exported creature raced again from its file; the config keys and their
// errors; the problem over the wire.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "app/run_report.hpp"
#include "core/input_error.hpp"
#include "core/race_lane.hpp"
#include "core/step.hpp"
#include "evolve/problems/fitness_kind.hpp"
#include "evolve/runs/evolution_run.hpp"
#include "evolve/runs/map_elites_run.hpp"
#include "evolve/problems/race_problem.hpp"
#include "evolve/estimators/replica_estimator.hpp"
#include "evolve/store/run_reader.hpp"
#include "evolve/store/run_store.hpp"
#include "evolve/runs/run_roles.hpp"
#include "evolve/problems/wire_format.hpp"
#include "formats/atomic_file.hpp"
#include "formats/model_file.hpp"
#include "formats/race_file.hpp"
#include "test_support.hpp"

using namespace sodaevo;
using namespace sodaevo::test;
namespace fs = std::filesystem;

namespace {

fs::path golden_file(const std::string& p) {
  const std::string terrain = "shared/models/soda/golden/terrain/";
  const std::string soda = "shared/models/soda/";
  if (p.rfind(terrain, 0) == 0) return data_dir() / "terrain" / p.substr(terrain.size());
  if (p.rfind(soda, 0) == 0) return data_dir() / "soda" / p.substr(soda.size());
  return p;
}

struct GoldenResult {
  std::string race, contender;
  double result = 0.0;
};

/// races.tsv rows whose contender path contains `contender`.
std::vector<GoldenResult> golden_rows(const std::string& contender) {
  std::ifstream in(data_dir() / "terrain" / "races.tsv");
  std::string line;
  std::getline(in, line);
  std::vector<GoldenResult> out;
  GoldenResult r;
  while (in >> r.race >> r.contender >> r.result) {
    if (r.contender.find(contender) != std::string::npos) out.push_back(r);
  }
  return out;
}

fs::path terrain(const std::string& name) { return models_dir() / "terrains" / (name + ".xml"); }

RunConfig race_config(const std::vector<std::string>& terrains, int timeout) {
  RunConfig c = walker_run_config("race", 1, 8, 2, 100, 0);
  c.fitness.kind = FitnessKind::Race;
  for (const std::string& t : terrains) c.fitness.race.terrains.push_back(terrain(t).string());
  c.fitness.race.timeout = timeout;
  c.world.evolve = world_parameter_names(); // the racer's CONTENDER rules: each brings its own world
  return c;
}

soda::ModelDef dainty_walker() { return soda::read_model_file(models_dir() / "dainty_walker.xml").def; }

} // namespace

// Independent: the original racer's results. The monster truck and the Dainty
// Walker as written reproduce on all 20 race files with the reference runner
// (test_race.cpp); the fast runner must give the same, to the last bit.
TEST_CASE("fitness kinds: one row each, saying how the kind's scores read", "[race][config]") {
  // configs/README.md, /fitness/kind: a walk's fitness is the px walked, more is
  // better; a race's is minus its frames to the finish, shown as frames.
  const FitnessKindInfo& walk = fitness_kind_info(FitnessKind::Walk);
  const FitnessKindInfo& race = fitness_kind_info(FitnessKind::Race);
  CHECK(std::string(walk.name) == "walk");
  CHECK(std::string(walk.unit) == "px");
  CHECK(walk.shown(12.5) == 12.5);
  CHECK(std::string(race.name) == "race");
  CHECK(std::string(race.unit) == "frames");
  CHECK(std::string(race.fitness_unit) == "-frames");
  CHECK(race.shown(-1234.5) == 1234.5);
  for (const FitnessKindInfo& k : kFitnessKinds) {
    CHECK(parse_fitness_kind(k.name) == k.kind);
    CHECK(&fitness_kind_info(k.kind) == &k);
  }
  CHECK_FALSE(parse_fitness_kind("climb").has_value());
  // Each Problem says its kind, and the wire tag is the kind's name.
  RunConfig config;
  CHECK(problem_of(config)->fitness_kind() == FitnessKind::Walk);
  CHECK(problem_of(config)->kind() == "walk");
}

TEST_CASE("run_race_fast gives the original racer's results (classics on all 20 race files)", "[race][golden]") {
  int raced = 0;
  for (const char* who : {"golden/dw_v1_container651", "monster_truck_v2converted", "dw_v1_wavereverse"}) {
    for (const GoldenResult& g : golden_rows(who)) {
      const bool flat = g.race.find("lat") != std::string::npos || g.race.find("inc1_0") != std::string::npos;
      if (std::string(who) == "dw_v1_wavereverse" && !flat) continue; // reproduced on the flat terrains only
      const soda::RaceDef race = soda::read_race_file(golden_file(g.race));
      const soda::RaceLane lane = soda::build_lane(race.terrain, race.constraints,
                                                   soda::read_model_file(golden_file(g.contender)).def, g.contender);
      const soda::Model model = soda::build_lane_model(lane);
      soda::State state = soda::make_state(model);
      const soda::RaceOutcome o = soda::run_race_fast(lane, model, race.timeout, state);
      INFO(g.race << " " << g.contender << ": original " << g.result << ", ours " << o.result);
      CHECK(o.result == g.result);
      ++raced;
    }
  }
  CHECK(raced == 43);
}

TEST_CASE("run_race_fast equals the reference race to the last bit of the final state, on every bundled terrain",
          "[race]") {
  const soda::ModelDef walker = dainty_walker();
  for (const fs::path& file : xml_files_under(models_dir() / "terrains")) {
    INFO(file.filename().string());
    const soda::RaceDef race = soda::read_race_file(file);
    const soda::RaceLane lane = soda::build_lane(race.terrain, race.constraints, walker, "dainty_walker");
    const soda::Model model = soda::build_lane_model(lane);
    constexpr int kTimeout = 600; // long enough to fall, walk and meet the bars
    soda::State reference;
    long long frames = 0;
    const soda::RaceOutcome slow = soda::run_race(lane, model, kTimeout, [&](const soda::State& s) {
      reference = s;
      ++frames;
    });
    soda::State fast = soda::make_state(model);
    const soda::RaceOutcome quick = soda::run_race_fast(lane, model, kTimeout, fast);
    CHECK(same_bits(quick.result, slow.result));
    CHECK(quick.updates == slow.updates);
    CHECK(quick.finished == slow.finished);
    CHECK(compare_states(model, fast, reference) == "");
    CHECK(fast.bar_memory == reference.bar_memory);
  }
}

TEST_CASE("run_race_fast: a jittered replica races as the reference step with the same jitter", "[race]") {
  const soda::RaceDef race = soda::read_race_file(terrain("TerrainFlat"));
  const soda::RaceLane lane = soda::build_lane(race.terrain, race.constraints, dainty_walker(), "dainty_walker");
  const soda::Model model = soda::build_lane_model(lane);
  soda::State jittered = soda::make_state(model);
  jittered.jitter = {12345, 0.05};
  soda::State by_hand = jittered;
  const soda::RaceOutcome o = soda::run_race_fast(lane, model, 400, jittered);
  soda::run(model, by_hand, o.updates);
  CHECK(compare_states(model, jittered, by_hand) == "");
  soda::State exact = soda::make_state(model);
  soda::run(model, exact, o.updates);
  CHECK_FALSE(compare_states(model, jittered, exact) == ""); // the jitter did act
}

namespace {

Evaluation estimate_one(const Problem& problem, const RunConfig& config, const soda::ModelDef& creature) {
  return roles_of(config).estimator->estimate(problem, {&creature}).front();
}

} // namespace

TEST_CASE("race problem: the exported creature races in `race` as the run scored it, at the racer's own scale",
          "[race][evolve]") {
  RunConfig config = race_config({"TerrainFlat"}, 800);
  config.fitness.replicas = 1;
  const RaceProblem problem = race_problem_of(config);
  const soda::ModelDef walker = dainty_walker();
  const Evaluation e = estimate_one(problem, config, walker);
  REQUIRE(e.ok());
  CHECK(e.fitness == -e.distance);
  CHECK(e.distance > 0.0);
  // Through the file, as a user hands it to the original racer.
  const fs::path dir = fresh_temp_dir("race_export");
  const soda::ModelDef exported = problem.export_form(walker, "c1", e);
  CHECK(exported.height == 422); // the racer scales by half the contender's container height
  soda::write_model_file(dir / "c1.xml", exported);
  const soda::ModelDef read = soda::read_model_file(dir / "c1.xml").def;
  const soda::RaceDef race = soda::read_race_file(terrain("TerrainFlat"));
  const soda::RaceLane lane = soda::build_lane(race.terrain, race.constraints, read, "c1.xml");
  CHECK(std::fabs(lane.scale - 1.0) < 1e-12); // prepared at racing size
  const soda::Model model = soda::build_lane_model(lane);
  soda::State state = soda::make_state(model);
  CHECK(soda::run_race_fast(lane, model, 800, state).result == e.distance);
  // And as the command line races it.
  const ShellResult r = run_sodaevo("race " + terrain("TerrainFlat").string() + " " + (dir / "c1.xml").string() +
                                    " --timeout 800 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.output.substr(r.output.find('{')));
  CHECK(j["contenders"][0]["frames"].get<double>() == e.distance);
}

TEST_CASE("race problem: several terrains score the mean or the worst of their races", "[race][evolve]") {
  const soda::ModelDef walker = dainty_walker();
  RunConfig one = race_config({"TerrainFlat"}, 300);
  one.fitness.replicas = 1;
  RunConfig other = race_config({"TerrainHilly"}, 300);
  other.fitness.replicas = 1;
  const double flat = estimate_one(*problem_of(one), one, walker).distance;
  const double hilly = estimate_one(*problem_of(other), other, walker).distance;
  REQUIRE(flat != hilly);
  RunConfig both = race_config({"TerrainFlat", "TerrainHilly"}, 300);
  both.fitness.replicas = 1;
  CHECK(estimate_one(*problem_of(both), both, walker).distance == (flat + hilly) / 2.0);
  both.fitness.race.combine = RaceCombine::Worst;
  CHECK(estimate_one(*problem_of(both), both, walker).distance == std::max(flat, hilly));
  CHECK(estimate_one(*problem_of(both), both, walker).fitness == -std::max(flat, hilly));
}

TEST_CASE("race problem: the problem travels over the wire and races its rollouts alike", "[race][evolve]") {
  RunConfig config = race_config({"TerrainFlat"}, 600);
  config.fitness.replicas = 4;
  config.fitness.jitter = 0.2;
  const RaceProblem problem = race_problem_of(config);
  const soda::ModelDef prepared = problem.prepare(dainty_walker());
  std::vector<Rollout> runs;
  for (std::uint64_t seed : {0, 7, 8}) runs.emplace_back(&prepared, soda::SineJitter{seed, 0.2});
  const std::vector<Evaluation> here = problem.rollouts(runs);
  REQUIRE(here.size() == 3);
  for (const Evaluation& e : here) REQUIRE(e.ok());
  WireWriter w;
  problem.write(w);
  WireReader r(w.bytes());
  const std::unique_ptr<Problem> copy = read_problem(r);
  r.expect_end();
  REQUIRE(copy->kind() == "race");
  const std::vector<Evaluation> there = copy->rollouts(runs);
  for (std::size_t i = 0; i < runs.size(); ++i) CHECK(same_bits(there[i].distance, here[i].distance));
  CHECK(copy->prepare(dainty_walker()) == prepared);
}

TEST_CASE("race config: bundled terrain names, the resolved config, and errors naming the pointer", "[race][config]") {
  const fs::path configs = models_dir().parent_path() / "configs";
  const RunConfig c = parse_run_config(
      R"({"population": {"random_fraction": 1}, "fitness": {"kind": "race", "race": {"terrains": ["TerrainFlat", "race00.xml"], "combine": "worst", "timeout": 2000}}})",
      "r.json", configs);
  CHECK(c.fitness.kind == FitnessKind::Race);
  REQUIRE(c.fitness.race.terrains.size() == 2);
  CHECK(fs::equivalent(c.fitness.race.terrains[0], terrain("TerrainFlat")));
  CHECK(fs::equivalent(c.fitness.race.terrains[1], terrain("race00")));
  CHECK(c.fitness.race.combine == RaceCombine::Worst);
  CHECK(c.fitness.race.timeout == 2000);
  CHECK(parse_run_config(to_json(c).dump(), "resolved.json", "/nowhere") == c);
  const RunConfig staged = parse_run_config(
      R"({"population": {"random_fraction": 1}, "fitness": {"kind": "race", "race": {"timeout_factor": 1.5,
          "curriculum": [{"terrain": "TerrainFlat", "threshold": 150}, {"terrain": "TerrainHilly"}]}}})",
      "c.json", configs);
  REQUIRE(staged.fitness.race.curriculum.size() == 2);
  CHECK(fs::equivalent(staged.fitness.race.curriculum[1].terrain, terrain("TerrainHilly")));
  CHECK(staged.fitness.race.curriculum[0].threshold == 150.0);
  CHECK(staged.fitness.race.timeout_factor == 1.5);
  CHECK(parse_run_config(to_json(staged).dump(), "resolved.json", "/nowhere") == staged);
  const RunConfig flat = read_run_config(configs / "sodarace_flat.json");
  CHECK(flat.fitness.kind == FitnessKind::Race);
  REQUIRE(flat.fitness.race.terrains.size() == 1);
  CHECK(fs::equivalent(flat.fitness.race.terrains[0], terrain("TerrainFlat")));
  // A walk's resolved config does not mention races.
  const RunConfig walk = parse_run_config(R"({"population": {"random_fraction": 1}})", "w.json", configs);
  CHECK_FALSE(to_json(walk).at("fitness").contains("kind"));
  CHECK_FALSE(to_json(walk).at("fitness").contains("race"));

  const auto error_of = [&](const std::string& fitness, const std::string& more = "") {
    try {
      (void)parse_run_config(R"({"population": {"random_fraction": 1}, "fitness": )" + fitness + more + "}", "bad.json",
                             configs);
    } catch (const soda::InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  CHECK_THAT(error_of(R"({"kind": "race"})"),
             Catch::Contains("bad.json: /fitness/race/terrains: expected at least one race file"));
  CHECK_THAT(error_of(R"({"kind": "run"})"), Catch::Contains("/fitness/kind: expected one of \"walk\" or \"race\", got \"run\""));
  CHECK_THAT(error_of(R"({"kind": "race", "race": {"terrains": ["NoSuchTerrain"]}})"),
             Catch::Contains("/fitness/race/terrains/0: expected an existing race file"));
  CHECK_THAT(error_of(R"({"kind": "race", "race": {"terrains": ["../models/dainty_walker.xml"]}})"),
             Catch::Contains("/fitness/race/terrains/0: expected a race file, got one that does not read"));
  CHECK_THAT(error_of(R"({"kind": "race", "race": {"terrains": ["TerrainFlat"], "combine": "best"}})"),
             Catch::Contains("/fitness/race/combine: expected one of \"mean\" or \"worst\", got \"best\""));
  CHECK_THAT(error_of(R"({"kind": "race", "race": {"terrains": ["TerrainFlat"], "timeout": -5}})"),
             Catch::Contains("/fitness/race/timeout: expected an integer in [0, 49997]"));
  CHECK_THAT(error_of(R"({"kind": "race", "race": {"terrains": ["TerrainFlat"], "timeot": 5}})"),
             Catch::Contains("/fitness/race/timeot: unknown key"));
  CHECK_THAT(error_of(R"({"race": {"terrains": ["TerrainFlat"]}})"),
             Catch::Contains("/fitness/race: expected only with /fitness/kind \"race\""));
  CHECK_THAT(error_of(R"({"kind": "race", "race": {"curriculum": [{"terrain": "TerrainFlat"}, {"terrain": "nowhere"}]}})"),
             Catch::Contains("/fitness/race/curriculum/0/threshold: expected the frames under which the best racer "
                             "moves on to stage 1, got nothing") &&
                 Catch::Contains("/fitness/race/curriculum/1/terrain: expected an existing race file"));
  CHECK_THAT(error_of(R"({"kind": "race", "race": {"curriculum": [{"terrain": "TerrainFlat", "threshold": -3}]}})"),
             Catch::Contains("/fitness/race/curriculum/0/threshold: expected frames in (0, 49997], got -3"));
  CHECK_THAT(error_of(R"({"kind": "race", "race": {"terrains": ["TerrainFlat"], "curriculum": [{"terrain": "TerrainFlat"}]}})"),
             Catch::Contains("/fitness/race/terrains: expected no terrains with /fitness/race/curriculum"));
  CHECK_THAT(error_of(R"({"kind": "race", "race": {"terrains": ["TerrainFlat"], "timeout_factor": 0.5}})"),
             Catch::Contains("/fitness/race/timeout_factor: expected 0 (off) or a number in [1, 100], got 0.5"));
  CHECK_THAT(error_of(R"({"kind": "race", "race": {"terrains": ["TerrainFlat"], "timeout_factor": "2"}})"),
             Catch::Contains("/fitness/race/timeout_factor: expected 0 (off) or a number in [1, 100], got \"2\""));
  CHECK_THAT(error_of(R"({"kind": "race", "race": {"terrains": ["TerrainFlat"], "timeout_factor": 2}})",
                      R"(, "algorithm": "map-elites")"),
             Catch::Contains("/fitness/race/timeout_factor: expected 0 with /algorithm \"map-elites\""));
  CHECK_THAT(error_of(R"({"kind": "race", "race": {"terrains": ["TerrainFlat"]}})",
                      R"(, "algorithm": "map-elites", "map_elites": {"descriptors": ["width", "floor_contact"],
                          "bins": [4, 4], "ranges": [[0, 200], [0, 1]]})"),
             Catch::Contains("/map_elites/descriptors/1: expected one of \"mass_count\", \"muscle_share\", \"width\", "
                             "\"height\" with /fitness/kind \"race\"") &&
                 Catch::Contains("got \"floor_contact\""));
  CHECK_THAT(error_of(R"({"kind": "race", "mode": "continuous", "race": {"terrains": ["TerrainFlat"]}})"),
             Catch::Contains("/fitness/kind: expected \"walk\" with /fitness/mode \"continuous\""));
}

TEST_CASE("a race run: evolve, export, and `race` confirms the exported champion's result", "[race][evolve]") {
  const fs::path dir = fresh_temp_dir("race_run");
  std::ofstream(dir / "race.json")
      << R"({"name": "r", "seed": 3, "generations": 3, "preset": "sodarace",
             "population": {"size": 12, "random_fraction": 1, "random": {"masses_min": 2, "masses_max": 4}},
             "limits": {"min_masses": 2},
             "fitness": {"kind": "race", "race": {"terrains": [")"
      << terrain("TerrainFlat").string() << R"("], "timeout": 300}, "replicas": 2, "replicas_max": 4}})";
  const ShellResult evolved =
      run_sodaevo("evolve " + (dir / "race.json").string() + " --quiet --out " + (dir / "run").string());
  INFO(evolved.output);
  REQUIRE(evolved.exit_code == 0);
  CHECK_THAT(evolved.output, Catch::Contains("frames)"));
  const ShellResult exported =
      run_sodaevo("export " + (dir / "run").string() + " --best 1 --check-replicas 4 --out " + (dir / "best").string());
  INFO(exported.output);
  REQUIRE(exported.exit_code == 0);
  std::ifstream in(dir / "best" / "champions.json");
  const nlohmann::json champions = nlohmann::json::parse(in);
  REQUIRE(champions.size() == 1);
  CHECK(champions[0]["unit"] == "frames");
  CHECK(champions[0]["check"]["n"] == 4);
  const ShellResult raced = run_sodaevo("race " + terrain("TerrainFlat").string() + " " +
                                        (dir / "best" / champions[0]["file"].get<std::string>()).string() +
                                        " --timeout 300 --json");
  REQUIRE(raced.exit_code == 0);
  const auto j = nlohmann::json::parse(raced.output.substr(raced.output.find('{')));
  CHECK(j["contenders"][0]["frames"].get<double>() == champions[0]["exact_distance"].get<double>());
}

TEST_CASE("race problem with descriptors: the race's bits, descriptors sampled on the reference race", "[race][map-elites]") {
  RunConfig config = race_config({"TerrainFlat"}, 500);
  const RaceProblem plain = race_problem_of(config, 0), described = race_problem_of(config, 7);
  const soda::ModelDef prepared = plain.prepare(dainty_walker());
  const std::vector<Rollout> runs{Rollout(&prepared), Rollout(&prepared, soda::SineJitter{99, 0.2})};
  const std::vector<Evaluation> a = plain.rollouts(runs), b = described.rollouts(runs);
  for (std::size_t i = 0; i < runs.size(); ++i) {
    REQUIRE(b[i].ok());
    CHECK(same_bits(a[i].distance, b[i].distance)); // chunked, the race is the same race
    CHECK(a[i].descriptors.empty());
    REQUIRE(b[i].descriptors.size() == kDescriptorCount);
  }
  // By hand on the reference runner: the masses' x and y extents every 7th frame and after the last.
  const soda::RaceDef race = soda::read_race_file(terrain("TerrainFlat"));
  const soda::RaceLane lane = soda::build_lane(race.terrain, race.constraints, prepared, "c");
  const soda::Model model = soda::build_lane_model(lane);
  std::vector<soda::State> frames;
  const soda::RaceOutcome o = soda::run_race(lane, model, 500, [&](const soda::State& s) { frames.push_back(s); });
  CHECK(o.result == a[0].distance);
  double width = 0.0, height = 0.0;
  int samples = 0;
  for (std::size_t f = 0; f < frames.size(); ++f) {
    if ((f + 1) % 7 != 0 && f + 1 != frames.size()) continue;
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    for (int m = 0; m < model.mass_count; ++m) {
      x0 = std::min(x0, frames[f].x[m]), x1 = std::max(x1, frames[f].x[m]);
      y0 = std::min(y0, frames[f].y[m]), y1 = std::max(y1, frames[f].y[m]);
    }
    width += x1 - x0, height += y1 - y0, ++samples;
  }
  const std::vector<double>& d = b[0].descriptors;
  CHECK(d[static_cast<std::size_t>(Descriptor::Width)] == Approx(width / samples).epsilon(1e-12));
  CHECK(d[static_cast<std::size_t>(Descriptor::Height)] == Approx(height / samples).epsilon(1e-12));
  CHECK(d[static_cast<std::size_t>(Descriptor::MassCount)] == model.mass_count);
  CHECK(b[1].descriptors != b[0].descriptors); // the jittered race is another race
  // Over the wire, with the interval.
  WireWriter w;
  described.write(w);
  WireReader r(w.bytes());
  const std::unique_ptr<Problem> copy = read_problem(r);
  CHECK(copy->rollouts(runs)[0].descriptors == d);
}

TEST_CASE("MAP-Elites with race fitness: elites scored by their race, the same archive on 1 and 2 threads",
          "[race][map-elites]") {
  RunConfig config = race_config({"TerrainFlat"}, 300);
  config.algorithm = AlgorithmKind::MapElites;
  config.population.random_fraction = 0.5;
  config.fitness.replicas = 2;
  config.fitness.replicas_max = 4;
  MapElitesConfig& me = config.map_elites;
  me.axes = {{Descriptor::Width, 4, 0.0, 200.0}, {Descriptor::MassCount, 4, 2.5, 14.5}};
  me.iterations = 2;
  me.batch_size = 6;
  me.sample_every = 5;
  me.qd_offset = -310; // a timeout scores timeout + the share of the course left
  const fs::path one = fresh_temp_dir("race_me_one"), two = fresh_temp_dir("race_me_two");
  ThreadEvaluator threads1(1), threads2(2);
  const MapElitesOutcome a = run_map_elites(one, config, me, threads1, {});
  run_map_elites(two, config, me, threads2, {});
  CHECK(a.stopped_because == StopReason::Completed);
  REQUIRE(a.metrics.filled > 1);
  const std::string archive_text = soda::read_whole_file(one / "archive.json");
  CHECK(archive_text == soda::read_whole_file(two / "archive.json"));
  CHECK(soda::read_whole_file(one / "qd.csv") == soda::read_whole_file(two / "qd.csv"));
  // Each elite's file, raced again by the reference runner, gives its logged
  // result; its fitness is minus a race result (frames).
  const soda::RaceDef race = soda::read_race_file(terrain("TerrainFlat"));
  const nlohmann::json archive = nlohmann::json::parse(archive_text);
  for (const auto& cell : archive["cells"]) {
    const soda::ModelDef elite = soda::read_model_file(one / cell["file"].get<std::string>()).def;
    const soda::RaceLane lane = soda::build_lane(race.terrain, race.constraints, elite, "elite");
    CHECK(soda::run_race(lane, soda::build_lane_model(lane), 300).result == cell["distance"].get<double>());
    const double fitness = cell["fitness"]["mean"].get<double>();
    CHECK(fitness < 0.0);
  }
  CHECK(a.metrics.qd_score > 0.0); // fitness - (-310) per elite
  fs::remove_all(one);
  fs::remove_all(two);
}

namespace {

/// Runs `config` into `dir` (a new run, or resumed when it has a checkpoint) on
/// `threads` threads; stops after generation `stop_after` (-1: none).
void race_run(const fs::path& dir, const RunConfig& config, int threads, int stop_after = -1) {
  RunStore store = fs::exists(dir / "checkpoint.json") ? RunStore::open(dir) : RunStore::create(dir, config, true, "test");
  ThreadEvaluator evaluator(threads, threads == 8 ? 3 : 0);
  std::atomic<bool> stop{false};
  EvolutionOptions options;
  options.stop_requested = &stop;
  options.on_generation = [&](const Progress& p) { stop = p.generation == stop_after; };
  run_evolution(store, evaluator, options);
}

/// The best column of generations.csv, by generation.
std::vector<double> logged_best(const fs::path& dir) {
  std::istringstream in(soda::read_whole_file(dir / "generations.csv"));
  std::string line;
  std::getline(in, line);
  std::vector<double> best;
  while (std::getline(in, line)) {
    std::stringstream cells(line);
    std::string cell;
    for (int c = 0; c < 3; ++c) std::getline(cells, cell, ',');
    best.push_back(std::stod(cell));
  }
  return best;
}

} // namespace

TEST_CASE("race timeout factor: each generation races with the factor times the frames of the previous best, "
          "threads, resume and replay alike",
          "[race][evolve]") {
  RunConfig config = race_config({"TerrainFlat"}, 2000);
  config.budget.generations = 4;
  config.fitness.race.timeout_factor = 1.5;
  config.population.seed_models = {(models_dir() / "wodka_ga109.xml").string()}; // finishes in 118 frames
  config.limits.min_masses = 2;
  config.fitness.replicas = config.fitness.replicas_max = 2;
  config.save.generation_every = 1;
  config.save.checkpoint_every = 1;
  const fs::path one = fresh_temp_dir("race_tf_one"), two = fresh_temp_dir("race_tf_two"),
                 eight = fresh_temp_dir("race_tf_eight"), resumed = fresh_temp_dir("race_tf_resumed");
  race_run(one, config, 1);
  race_run(two, config, 2);
  race_run(eight, config, 8);
  race_run(resumed, config, 2, 2); // stopped after generation 2, then resumed across the switches
  race_run(resumed, config, 1);
  const std::vector<double> best = logged_best(one);
  REQUIRE(best.size() == 4);
  bool shorter = false;
  for (int g = 0; g < 4; ++g) {
    INFO("generation " << g);
    const Generation saved = read_saved_generation(one, g);
    // From the log: minus the previous generation's best fitness is its best racer's frames.
    const int expected = g == 0 ? 0 : static_cast<int>(std::ceil(1.5 * -best[static_cast<std::size_t>(g - 1)]));
    CHECK(saved.race_timeout == expected);
    // A creature cut off by the shorter timeout scores it + the share of the course left.
    for (const Individual& ind : saved.individuals) {
      shorter = shorter || (expected > 0 && ind.evaluation.ok() && ind.evaluation.distance > expected &&
                            ind.evaluation.distance < expected + 5);
    }
    for (const fs::path& other : {two, eight, resumed}) {
      CHECK(soda::read_whole_file(other / "generations" / generation_file_name(g)) ==
            soda::read_whole_file(one / "generations" / generation_file_name(g)));
    }
  }
  CHECK(shorter); // the switch happened: slow racers were cut off long before 2000 frames
  CHECK(soda::read_whole_file(resumed / "generations.csv") == soda::read_whole_file(one / "generations.csv"));
  // Replay races the saved generation with its own timeout.
  const ShellResult replayed = run_sodaevo("replay " + one.string() + " --generation 3");
  INFO(replayed.output);
  CHECK(replayed.exit_code == 0);
  CHECK_THAT(replayed.output, Catch::Contains(", 0 differ"));
  for (const fs::path& d : {one, two, eight, resumed}) fs::remove_all(d);
}

TEST_CASE("race curriculum: the next terrain once the best racer finishes under the threshold, threads, resume and "
          "replay alike",
          "[race][evolve]") {
  RunConfig config = race_config({}, 600);
  config.fitness.race.curriculum = {{terrain("TerrainFlat").string(), 150.0}, {terrain("TerrainHilly").string(), 0.0}};
  config.population.seed_models = {(models_dir() / "wodka_ga109.xml").string()}; // 118 frames on TerrainFlat
  config.limits.min_masses = 2;
  config.budget.generations = 3;
  config.fitness.replicas = config.fitness.replicas_max = 2;
  config.save.generation_every = 1;
  config.save.checkpoint_every = 1;
  const fs::path one = fresh_temp_dir("race_cur_one"), eight = fresh_temp_dir("race_cur_eight"),
                 resumed = fresh_temp_dir("race_cur_resumed");
  race_run(one, config, 1);
  race_run(eight, config, 8);
  race_run(resumed, config, 2, 0); // stopped before the switch, then resumed across it
  race_run(resumed, config, 1);
  const std::vector<double> best = logged_best(one);
  REQUIRE(best.size() == 3);
  REQUIRE(-best[0] < 150.0); // the seed finishes TerrainFlat under the threshold
  CHECK(read_saved_generation(one, 0).race_stage == 0);
  const Generation second = read_saved_generation(one, 1);
  CHECK(second.race_stage == 1);
  CHECK(read_saved_generation(one, 2).race_stage == 1);
  for (int g = 0; g < 3; ++g) {
    for (const fs::path& other : {eight, resumed}) {
      CHECK(soda::read_whole_file(other / "generations" / generation_file_name(g)) ==
            soda::read_whole_file(one / "generations" / generation_file_name(g)));
    }
  }
  // Generation 1 raced TerrainHilly: its best scores there as a run on TerrainHilly alone scores it.
  RunConfig hilly = race_config({"TerrainHilly"}, 600);
  hilly.fitness.replicas = hilly.fitness.replicas_max = 2;
  hilly.limits.min_masses = 2;
  const Individual& top = *std::max_element(second.individuals.begin(), second.individuals.end(),
                                            [](const Individual& a, const Individual& b) {
                                              return a.evaluation.fitness < b.evaluation.fitness;
                                            });
  CHECK(estimate_one(*problem_of(hilly), hilly, top.creature).fitness == top.evaluation.fitness);
  CHECK(top.evaluation.fitness == best[1]);
  const ShellResult replayed = run_sodaevo("replay " + one.string() + " --generation 2");
  INFO(replayed.output);
  CHECK(replayed.exit_code == 0);
  CHECK_THAT(replayed.output, Catch::Contains(", 0 differ"));
  // The report races the last stage's terrain.
  CHECK_THAT(app::run_report_html(one), Catch::Contains("race on TerrainHilly"));
  for (const fs::path& d : {one, eight, resumed}) fs::remove_all(d);
}

// Issue 27: a creature's race replicas race together (run_races_fast: lockstep lanes
// where the CPU has AVX-512), each with the result it has raced alone.
TEST_CASE("race problem: replicas raced together give each replica's race alone, bit for bit", "[race][lockstep]") {
  RunConfig config = race_config({"TerrainFlat", "TerrainHilly"}, 600);
  const RaceProblem problem = race_problem_of(config);
  const soda::ModelDef prepared = problem.prepare(dainty_walker());
  std::vector<Rollout> runs;
  for (std::uint64_t seed = 0; seed < 11; ++seed) runs.emplace_back(&prepared, soda::SineJitter{seed, 0.2});
  const std::vector<Evaluation> together = problem.rollouts(runs);
  REQUIRE(together.size() == runs.size());
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const std::vector<Evaluation> alone = problem.rollouts({runs[i]}); // one replica: never in lockstep
    INFO("replica " << i);
    REQUIRE(alone[0].ok());
    CHECK(together[i].status == alone[0].status);
    CHECK(same_bits(together[i].distance, alone[0].distance));
    CHECK(same_bits(together[i].fitness, alone[0].fitness));
  }
}

// Issue 27: a batch of different creatures races together in fused lanes
// (run_races_together), among them a creature's replicas in lockstep lanes and a
// creature whose lane cannot be built; each run's evaluation is the one it gets alone.
TEST_CASE("race problem: different creatures raced together give each run's race alone, bit for bit",
          "[race][fused_bars]") {
  RunConfig config = race_config({"TerrainFlat", "TerrainHilly"}, 500);
  config.limits.min_masses = 2; // the slug has 2, the GA racer 60
  config.limits.max_masses = 60;
  config.limits.max_links = 400;
  const RaceProblem problem = race_problem_of(config);
  const soda::ModelDef walker = problem.prepare(dainty_walker());
  const soda::ModelDef racer = problem.prepare(soda::read_model_file(models_dir() / "wodka_ga109.xml").def);
  const soda::ModelDef slug = problem.prepare(soda::read_model_file(models_dir() / "carefulslug.xml").def);
  // No links: the racer keeps its first mass alone, scaled by +inf (NaN from the
  // first update): the timeout formula (tests/test_contender_filter.cpp), no error.
  soda::ModelDef unlinked = walker;
  unlinked.links.clear();
  std::vector<Rollout> runs;
  for (std::uint64_t seed = 0; seed < 8; ++seed) { // 8 replicas of the walker: lockstep lanes
    runs.emplace_back(&walker, soda::SineJitter{seed, 0.2});
    if (seed % 3 == 0) runs.emplace_back(&racer, soda::SineJitter{seed, 0.2});
    if (seed == 4) runs.emplace_back(&unlinked, soda::SineJitter{});
    if (seed == 5) runs.emplace_back(&slug, soda::SineJitter{});
  }
  const std::vector<Evaluation> together = problem.rollouts(runs);
  REQUIRE(together.size() == runs.size());
  int ok = 0;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const std::vector<Evaluation> alone = problem.rollouts({runs[i]});
    INFO("run " << i);
    CHECK(together[i].status == alone[0].status);
    CHECK(together[i].reason == alone[0].reason);
    CHECK(same_bits(together[i].distance, alone[0].distance));
    CHECK(same_bits(together[i].fitness, alone[0].fitness));
    ok += alone[0].ok() ? 1 : 0;
  }
  CHECK(ok == static_cast<int>(runs.size()));
}

// MAP-Elites races observe the state every few frames (the descriptors): the race
// must end where it ends unobserved, also when the finish falls on a chunk's last frame.
TEST_CASE("run_race_fast observed in chunks ends as unobserved, the finish on a chunk's end included", "[race]") {
  const soda::RaceDef race = soda::read_race_file(terrain("TerrainFlat"));
  const soda::RaceLane lane = soda::build_lane(race.terrain, race.constraints,
                                               soda::read_model_file(models_dir() / "wodka_ga109.xml").def, "racer");
  const soda::Model model = soda::build_lane_model(lane);
  soda::State plain = soda::make_state(model);
  const soda::RaceOutcome expected = soda::run_race_fast(lane, model, 2000, plain);
  REQUIRE(expected.finished);
  for (const long long every : {1LL, 7LL, expected.updates - 1, expected.updates, expected.updates + 5}) {
    INFO("every " << every);
    soda::State state = soda::make_state(model);
    long long seen = 0, last_seen = -1;
    const soda::RaceOutcome o = soda::run_race_fast(lane, model, 2000, state, every, [&](const soda::State& s) {
      ++seen;
      last_seen = s.frame;
    });
    CHECK(same_bits(o.result, expected.result));
    CHECK(o.updates == expected.updates);
    CHECK(compare_states(model, plain, state).empty());
    CHECK(seen == (expected.updates + every - 1) / every);
    CHECK(last_seen == expected.updates);
  }
}

TEST_CASE("run_races_fast: each replica's result and final state as run_race_fast's, bar memory included",
          "[race][lockstep]") {
  const soda::RaceDef race = soda::read_race_file(terrain("TerrainHilly"));
  const soda::RaceLane lane = soda::build_lane(race.terrain, race.constraints, dainty_walker(), "dainty_walker");
  const soda::Model model = soda::build_lane_model(lane);
  constexpr int kTimeout = 800;
  std::vector<soda::State> together, alone;
  for (std::uint64_t seed = 0; seed < 11; ++seed) { // 8 in lockstep, 3 one by one
    together.push_back(soda::make_state(model));
    together.back().jitter = {seed, 0.2};
  }
  alone = together;
  std::vector<soda::State*> pointers;
  for (soda::State& s : together) pointers.push_back(&s);
  const std::vector<soda::RaceOutcome> outcomes = soda::run_races_fast(lane, model, kTimeout, pointers);
  REQUIRE(outcomes.size() == alone.size());
  for (std::size_t k = 0; k < alone.size(); ++k) {
    const soda::RaceOutcome o = soda::run_race_fast(lane, model, kTimeout, alone[k]);
    INFO("replica " << k);
    CHECK(same_bits(outcomes[k].result, o.result));
    CHECK(outcomes[k].updates == o.updates);
    CHECK(outcomes[k].finished == o.finished);
    CHECK(compare_states(model, together[k], alone[k]).empty());
  }
  CHECK_FALSE(compare_states(model, together[0], together[1]).empty()); // the jitter parted them
}
