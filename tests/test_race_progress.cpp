// The progress score a racer search ranks by (/fitness/race/score "progress",
// evolve/problems/race_progress.hpp): its order checked by hand-computed values, its config
// key, and the race problem's fitness under it against a reference race (run_race,
// the reference step) whose furthest least x test_race.cpp checks against the
// original racer's golden traces.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "core/input_error.hpp"
#include "core/race_lane.hpp"
#include "evolve/problems/race_problem.hpp"
#include "evolve/problems/race_progress.hpp"
#include "evolve/runs/run_roles.hpp"
#include "evolve/problems/wire_format.hpp"
#include "formats/model_file.hpp"
#include "formats/race_file.hpp"
#include "test_support.hpp"

using namespace sodaevo;
using namespace sodaevo::test;
namespace fs = std::filesystem;

TEST_CASE("race progress: the share of the way from the start to the finish line, clamped", "[race][progress]") {
  soda::RaceLane lane;
  lane.finish_x = 50994.0; // the line at 51000
  CHECK(track_progress(lane, 49900.0, 49900.0) == 0.0);
  CHECK(track_progress(lane, 49900.0, 50450.0) == 0.5);
  CHECK(track_progress(lane, 49900.0, 51000.0) == 1.0);
  CHECK(track_progress(lane, 49900.0, 52000.0) == 1.0); // past the line: a finish
  CHECK(track_progress(lane, 49900.0, 49000.0) == 0.0); // went back
  CHECK(track_progress(lane, 49900.0, NAN) == 0.0);     // diverged
}

TEST_CASE("race progress: files finished first, then frames and the ground held", "[race][progress]") {
  // One file, timeout 999: an unfinished race costs W + 1000 (2 - p), W = 1 + 2000.
  CHECK(progress_cost({{500.0, true, 999, 1.0}}) == 500.0);
  CHECK(progress_cost({{999.5, false, 999, 0.25}}) == 2001.0 + 1750.0);
  CHECK(progress_cost({{999.5, false, 999, 0.75}}) == 2001.0 + 1250.0);
  // Two files, timeouts 999 and 499: W = 1 + 2000 + 1000 = 3001.
  const double both = progress_cost({{900.0, true, 999, 1.0}, {450.0, true, 499, 1.0}});
  const double one_fast = progress_cost({{10.0, true, 999, 1.0}, {499.9, false, 499, 0.99}});
  const double one_slow = progress_cost({{990.0, true, 999, 1.0}, {499.9, false, 499, 0.99}});
  const double none = progress_cost({{999.2, false, 999, 0.99}, {499.9, false, 499, 0.99}});
  CHECK(both == 1350.0);
  CHECK(one_fast == 3001.0 + 10.0 + 500.0 * 1.01);
  CHECK(both < one_fast); // a second finish outweighs 890 frames saved on the first
  CHECK(one_fast < one_slow);
  CHECK(one_slow < none);
  CHECK(none == 2.0 * 3001.0 + 1000.0 * 1.01 + 500.0 * 1.01);
}

namespace {

fs::path bundled_terrain(const std::string& name) { return models_dir() / "terrains" / (name + ".xml"); }

RunConfig progress_config(const std::string& terrain_name, int timeout) {
  RunConfig c = walker_run_config("race", 1, 8, 2, 100, 0);
  c.fitness.kind = FitnessKind::Race;
  c.fitness.race.terrains.push_back(bundled_terrain(terrain_name).string());
  c.fitness.race.timeout = timeout;
  c.fitness.race.score = RaceScore::Progress;
  c.fitness.replicas = 1;
  c.limits.min_masses = 2; // wodka's racer has two
  c.world.evolve = world_parameter_names();
  return c;
}

} // namespace

TEST_CASE("race progress: the race problem's fitness is minus the cost of the reference race, the frames the racer's",
          "[race][progress]") {
  // wodka's GA racer: races TerrainFlat in 118 frames (the original racer's result of
  // GA_109_fastest), and makes ground on race08 before a 600-frame timeout.
  const soda::ModelDef walker = soda::read_model_file(models_dir() / "wodka_ga109.xml").def;
  for (const auto& [name, timeout] : {std::pair<std::string, int>{"race08", 600}, {"TerrainFlat", 3000}}) {
    INFO(name);
    RunConfig config = progress_config(name, timeout);
    const RaceProblem problem = race_problem_of(config);
    const Evaluation e = roles_of(config).estimator->estimate(problem, {&walker}).front();
    INFO(e.reason);
    REQUIRE(e.ok());
    // The reference: the lane built and raced by the reference step.
    const soda::RaceDef race = soda::read_race_file(bundled_terrain(name));
    const soda::RaceLane lane = soda::build_lane(race.terrain, race.constraints, problem.prepare(walker), "walker");
    const soda::Model model = soda::build_lane_model(lane);
    const soda::RaceOutcome o = soda::run_race(lane, model, timeout);
    const double start = soda::least_x(model, soda::make_state(model));
    CHECK(same_bits(e.distance, o.result)); // the racer's result is still what is logged
    const double p = track_progress(lane, start, o.furthest_min_x);
    const double expected = o.finished ? o.result : (1.0 + 2.0 * (timeout + 1.0)) + (timeout + 1.0) * (2.0 - p);
    CHECK(same_bits(e.fitness, -expected));
    if (name == "race08") {
      CHECK_FALSE(o.finished);
      CHECK(p > 0.0); // it moved forward before the timeout
    } else {
      CHECK(o.finished);
    }
    // Over the wire the problem keeps its score.
    WireWriter w;
    problem.write(w);
    WireReader r(w.bytes());
    const std::unique_ptr<Problem> copy = read_problem(r);
    const soda::ModelDef prepared = problem.prepare(walker);
    const std::vector<Evaluation> there = copy->rollouts({Rollout(&prepared, soda::SineJitter{})});
    CHECK(same_bits(there.front().fitness, -expected));
  }
}

TEST_CASE("race progress: /fitness/race/score read, resolved and refused with its pointer", "[race][config]") {
  const fs::path configs = models_dir().parent_path() / "configs";
  const RunConfig c = parse_run_config(
      R"({"population": {"random_fraction": 1}, "fitness": {"kind": "race", "race": {"terrains": ["race08"], "score": "progress"}}})",
      "p.json", configs);
  CHECK(c.fitness.race.score == RaceScore::Progress);
  CHECK(to_json(c).at("fitness").at("race").at("score") == "progress");
  CHECK(parse_run_config(to_json(c).dump(), "resolved.json", "/nowhere") == c);
  try {
    (void)parse_run_config(
        R"({"population": {"random_fraction": 1}, "fitness": {"kind": "race", "race": {"terrains": ["race08"], "score": "furthest"}}})",
        "bad.json", configs);
    FAIL("expected an error");
  } catch (const soda::InputError& e) {
    CHECK_THAT(std::string(e.what()),
               Catch::Contains("bad.json: /fitness/race/score: expected one of \"racer\" or \"progress\", got \"furthest\""));
  }
}

TEST_CASE("race progress: the record searches' configs read, race with the progress score", "[race][config]") {
  const fs::path dir = models_dir().parent_path() / "configs" / "records";
  int read = 0;
  for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
    if (e.path().extension() != ".json" || e.path().filename().string()[0] == '.') continue; // not the ablation's scratch
    INFO(e.path().string());
    const RunConfig c = read_run_config(e.path());
    CHECK(c.fitness.kind == FitnessKind::Race);
    CHECK(c.fitness.race.score == RaceScore::Progress);
    ++read;
  }
  CHECK(read >= 10);
}
