// The GA's view of accuracy: the config selects mode, integrator and sub-steps;
// the fitness is the same bit for bit with continuous Euler at one step per frame;
// the honesty check flags creatures whose walk depends on the step; the command
// line exposes the same and never prints or writes a non-finite number.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "core/input_error.hpp"
#include "evolve/runs/run_roles.hpp"
#include "evolve/problems/walk_problem.hpp"
#include "evolve/problems/honesty.hpp"
#include "evolve/config/run_config.hpp"
#include "evolve/algorithms/variation.hpp"
#include "formats/atomic_file.hpp"
#include "formats/model_file.hpp"
#include "test_support.hpp"

using namespace sodaevo;
namespace fs = std::filesystem;

namespace {

RunConfig config_with(const std::string& fitness_json) {
  return parse_run_config(R"({"population": {"random_fraction": 1}, "fitness": )" + fitness_json + "}", "t.json",
                          "/nowhere");
}

soda::ModelDef prepared_dainty_walker(const RunConfig& config) {
  const soda::ModelDef seed = soda::read_model_file(std::string(SODAEVO_MODELS_DIR) + "/dainty_walker.xml").def;
  return walk_problem_of(config).prepare(creature_from_seed(seed, config));
}

} // namespace

TEST_CASE("config: mode, integrator, sub-steps, divergence and honesty keys", "[honesty][config]") {
  const RunConfig c = config_with(
      R"({"mode": "continuous", "integrator": "rk4", "substeps": 8, "divergence": "energy",
          "honesty": {"max_change": 0.05, "substeps_factor": 2}})");
  CHECK(c.fitness.mode == soda::PhysicsMode::Continuous);
  CHECK(c.fitness.integrator == soda::Integrator::Rk4);
  CHECK(c.fitness.substeps == 8);
  CHECK(c.fitness.divergence == DivergenceCheck::Energy);
  CHECK(c.fitness.honesty_max_change == 0.05);
  CHECK(c.fitness.honesty_substeps_factor == 2);
  const nlohmann::json j = to_json(c);
  CHECK(j["fitness"]["integrator"] == "rk4");
  CHECK(parse_run_config(j.dump(), "resolved", "/nowhere") == c);

  try {
    config_with(R"({"integrator": "leapfrog", "substeps": 0})");
    FAIL("accepted a bad integrator");
  } catch (const soda::InputError& e) {
    const std::string what = e.what();
    CHECK(what.find("/fitness/integrator") != std::string::npos);
    CHECK(what.find("leapfrog") != std::string::npos);
    CHECK(what.find("/fitness/substeps") != std::string::npos);
  }
}

TEST_CASE("fitness: continuous Euler at one step per frame scores exactly as soda", "[honesty]") {
  const RunConfig soda_config = config_with(R"({"frames": 1500, "settle_frames": 100})");
  const RunConfig cont_config =
      config_with(R"({"frames": 1500, "settle_frames": 100, "mode": "continuous", "integrator": "euler"})");
  const soda::ModelDef walker = prepared_dainty_walker(soda_config);
  const Evaluation a = walk_problem_of(soda_config).rollouts({&walker}).front();
  const Evaluation b = walk_problem_of(cont_config).rollouts({&walker}).front();
  REQUIRE(a.ok());
  REQUIRE(b.ok());
  CHECK(std::memcmp(&a.fitness, &b.fitness, sizeof(double)) == 0);
  // ... and a different setting scores differently (the setting is really used).
  const RunConfig rk4 = config_with(R"({"frames": 1500, "settle_frames": 100, "mode": "continuous",
                                        "integrator": "rk4", "substeps": 4})");
  const Evaluation c = walk_problem_of(rk4).rollouts({&walker}).front();
  REQUIRE(c.ok());
  CHECK(c.fitness != a.fitness);
}

TEST_CASE("honesty: refined stepping and relative change", "[honesty]") {
  CHECK(refined_stepping({}, 4) == soda::Stepping{soda::PhysicsMode::Continuous, soda::Integrator::Euler, 4});
  CHECK(refined_stepping({soda::PhysicsMode::Continuous, soda::Integrator::Rk4, 8}, 4) ==
        soda::Stepping{soda::PhysicsMode::Continuous, soda::Integrator::Rk4, 32});
  CHECK(refined_stepping({soda::PhysicsMode::Continuous, soda::Integrator::Verlet, 4000}, 4).substeps ==
        soda::kMaxSubsteps);
  CHECK(relative_change(100.0, 50.0) == -1.0);  // walks half as far when refined: -100 % of the refined
  CHECK(relative_change(100.0, 125.0) == 0.2);
  CHECK(relative_change(0.5, 0.0) == -0.5);     // below 1 px the denominator is 1 px
}

TEST_CASE("honesty: the GA flags a creature whose distance changes more than allowed", "[honesty]") {
  const RunConfig strict = config_with(R"({"frames": 1000, "settle_frames": 100, "honesty": {"max_change": 1e-9}})");
  const RunConfig lax = config_with(R"({"frames": 1000, "settle_frames": 100, "honesty": {"max_change": 1e6}})");
  const soda::ModelDef walker = prepared_dainty_walker(strict);
  const Evaluation flagged = walk_problem_of(strict).rollouts({&walker}).front();
  CHECK(flagged.status == EvaluationStatus::Diverged);
  CHECK(flagged.reason.find("dishonest") == 0);
  CHECK(flagged.reason.find("euler/4") != std::string::npos);
  const Evaluation ok = walk_problem_of(lax).rollouts({&walker}).front();
  REQUIRE(ok.ok());
  CHECK(ok.honesty_change != 0.0);
  CHECK(std::isfinite(ok.honesty_change));
}

TEST_CASE("cli: simulate in the continuous mode, with the honesty check", "[honesty][cli]") {
  const std::string model = std::string(SODAEVO_MODELS_DIR) + "/dainty_walker.xml";
  const auto r =
      test::run_sodaevo("simulate " + model + " --frames 500 --mode continuous --integrator verlet --substeps 4 --honesty --json");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.output);
  CHECK(j["stepping"] == "verlet/4");
  CHECK(j["honesty_stepping"] == "verlet/16");
  CHECK(j["diverged"] == false);
  CHECK(j["honesty_relative_change"].is_number());

  const auto bad = test::run_sodaevo("simulate " + model + " --substeps 4");
  CHECK(bad.exit_code != 0);
  CHECK(bad.output.find("--mode continuous") != std::string::npos);
  const auto bad_integrator = test::run_sodaevo("simulate " + model + " --mode continuous --integrator leapfrog");
  CHECK(bad_integrator.exit_code != 0);
  CHECK(bad_integrator.output.find("leapfrog") != std::string::npos);
}

TEST_CASE("cli: a diverging model stops at the last healthy frame, no NaN in output, trace or saved model",
          "[honesty][cli]") {
  // Rest length 1.7e308 on a link 1e-9 px long: NaN velocity after frame 1.
  const fs::path dir = test::fresh_temp_dir("honesty_diverging");
  const fs::path model = dir / "overflow.xml";
  {
    std::ofstream out(model);
    out << R"(<?xml version="1.0" encoding="ISO-8859-1" standalone="no"?>
<!DOCTYPE sodaconstructor>
<model>
	<container width="1000" height="1000"/>
	<environment gravity="0.0" friction="0.0" springyness="0.5"/>
	<collisions surface_friction="0.1" surface_reflection="-0.75"/>
	<wave amplitude="0.5" phase="0.0" speed="0.01"/>
	<settings gravitydirection="down" wavedirection="forward" autoreverse="off"/>
	<nodes>
		<mass id="m0" x="500.0" y="500.0" vx="0.0" vy="0.0"/>
		<mass id="m1" x="500.0" y="500.000000001" vx="0.0" vy="0.0"/>
	</nodes>
	<links>
		<spring a="m0" b="m1" restlength="1.7E308"/>
	</links>
</model>
)";
  }
  for (const std::string& extra : {std::string(), " --trace " + (dir / "t.csv").string() + " --out " + (dir / "final.xml").string()}) {
    const auto r = test::run_sodaevo("simulate " + model.string() + " --frames 50 --json" + extra);
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    const auto j = nlohmann::json::parse(r.output);
    CHECK(j["diverged"] == true);
    CHECK(j["diverged_frame"] == 1);
    CHECK(j["frames"] == 0);
    CHECK(r.output.find("nan") == std::string::npos);
    CHECK(r.output.find("inf") == std::string::npos);
  }
  const std::string trace = soda::read_whole_file(dir / "t.csv");
  CHECK(trace.find("nan") == std::string::npos);
  CHECK(trace.find("inf") == std::string::npos);
  const std::string xml = soda::read_whole_file(dir / "final.xml");
  CHECK(xml.find("NaN") == std::string::npos);
  CHECK(xml.find("inf") == std::string::npos);
  CHECK(xml.find("Inf") == std::string::npos);
  fs::remove_all(dir);
}
