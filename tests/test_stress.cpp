// Stability under stress: thousands of random creatures with extreme but legal
// parameters (bench/extreme_creatures.hpp) in every physics mode; no non-finite
// value may escape the divergence detector, and divergence is flagged with the
// frame and the reason while the run goes on.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include "bench/extreme_creatures.hpp"
#include "core/divergence.hpp"
#include "core/model.hpp"
#include "core/step.hpp"
#include "evolve/problems/walk_problem.hpp"
#include "test_support.hpp"

using namespace sodaevo;

TEST_CASE("stress: thousands of extreme creatures, no non-finite value escapes", "[stress]") {
  bench::StressOptions o;
  o.seed = 20261121;
  o.creatures = 3000;
  o.frames = 150;
  o.steppings = {soda::Stepping{},
                 {soda::PhysicsMode::Continuous, soda::Integrator::Euler, 2},
                 {soda::PhysicsMode::Continuous, soda::Integrator::Verlet, 2},
                 {soda::PhysicsMode::Continuous, soda::Integrator::Rk4, 1}};
  o.threads = 2;
  const std::vector<bench::StressCounts> counts = bench::run_stress(o);
  REQUIRE(counts.size() == o.steppings.size());
  for (const bench::StressCounts& c : counts) {
    INFO(c.stepping << ": tried " << c.tried << ", non-finite " << c.diverged_non_finite << ", energy "
                    << c.diverged_energy << ", escaped " << c.escaped << " " << c.first_escape << "; example "
                    << c.example_diverged);
    CHECK(c.tried == o.creatures);
    CHECK(c.escaped == 0);
    // The generator does produce creatures that blow up (rest lengths of 1e300),
    // so the detector has something to catch; and most creatures stay healthy.
    CHECK(c.diverged_non_finite > 0);
    CHECK(c.diverged_non_finite + c.diverged_energy < c.tried / 2);
  }
}

TEST_CASE("stress: the same seed gives the same counts whatever the thread count", "[stress]") {
  bench::StressOptions o;
  o.creatures = 200;
  o.frames = 60;
  o.threads = 1;
  const auto one = bench::run_stress(o);
  o.threads = 2;
  const auto two = bench::run_stress(o);
  CHECK(one[0].diverged_non_finite == two[0].diverged_non_finite);
  CHECK(one[0].diverged_energy == two[0].diverged_energy);
  CHECK(one[0].frames_stepped == two[0].frames_stepped);
}

namespace {

soda::ModelDef two_masses(double rest) {
  soda::ModelDef def;
  def.width = 1000;
  def.height = 1000;
  def.environment = {0.0, 0.0, 0.5};
  def.nodes.push_back({"a", false, 500.0, 500.0, 0.0, 0.0});
  def.nodes.push_back({"b", false, 500.0, 500.0 + 1e-9, 0.0, 0.0}); // vertical: dx = 0, L ~ 1e-9
  def.links.push_back({soda::LinkKind::Spring, 0, 1, rest, 0.0, 0.0});
  return def;
}

} // namespace

TEST_CASE("divergence: an overflowing spring is flagged non-finite at its frame", "[stress]") {
  // Rest 1.7e308 on a link of length 1e-9: c = k (L - D)/L overflows to -inf, and
  // c*dx with dx = 0 is NaN (IEEE 754: inf * 0), so vx is NaN after frame 1.
  const soda::Model model = soda::build_model(two_masses(1.7e308));
  soda::State s = soda::make_state(model);
  soda::DivergenceMonitor monitor(model, s);
  soda::step(model, s);
  CHECK_FALSE(monitor.check(s));
  CHECK(monitor.result().diverged);
  CHECK(monitor.result().frame == 1);
  CHECK(monitor.result().reason == "non-finite x of mass 0");
  // The GA marks it diverged with the reason, and does not throw.
  FitnessConfig fc;
  fc.frames = 10;
  fc.settle_frames = 0;
  const Evaluation e = WalkProblem(fc, {}, {}).rollout_with(two_masses(1.7e308), {});
  CHECK(e.status == EvaluationStatus::Diverged);
  CHECK(e.reason.find("non-finite") != std::string::npos);
}

TEST_CASE("divergence: the finite-state check names the first mass in mass order", "[stress]") {
  const soda::Model model = sodaevo::test::load_scene(sodaevo::test::models_dir() / "dainty_walker.xml").model;
  REQUIRE(model.mass_count >= 4);
  soda::State s = soda::make_state(model);
  CHECK(soda::first_non_finite_mass(model, s) == -1);
  CHECK_FALSE(soda::first_non_finite(model, s).has_value());
  s.x[3] = std::numeric_limits<double>::infinity();
  s.vy[2] = std::numeric_limits<double>::quiet_NaN();
  CHECK(soda::first_non_finite_mass(model, s) == 2);
  CHECK(soda::first_non_finite(model, s) == std::optional<std::string>("vy of mass 2"));
  s.vy[2] = 1.0;
  CHECK(soda::first_non_finite_mass(model, s) == 3);
  CHECK(soda::first_non_finite(model, s) == std::optional<std::string>("x of mass 3"));
}

TEST_CASE("divergence: a stiff hub unstable under one step per frame is flagged as energy runaway", "[stress]") {
  // A mass held by 12 horizontal springs (k 0.5) to fixed nodes left and right:
  // the stiffness along x is 12k = 6 per frame^2, above 4, the stability limit of
  // semi-implicit Euler (omega^2 dt^2 < 4), so with one step per frame the energy
  // grows without any muscle (until the speed limit caps it). With 4 steps per
  // frame (omega^2 dt^2 = 0.375) the same scene oscillates with bounded energy.
  soda::ModelDef def;
  def.width = 100000;
  def.height = 100000;
  def.environment = {0.0, 0.0, 0.5};
  def.nodes.push_back({"hub", false, 5000.0, 5000.0, 0.0, 0.0});
  for (int i = 0; i < 12; ++i) {
    const double side = i % 2 == 0 ? -1.0 : 1.0;
    const double rest = 40.0 + 5.0 * i;
    def.nodes.push_back({"n" + std::to_string(i), true, 5000.0 + side * rest, 5000.0, 0, 0});
    def.links.push_back({soda::LinkKind::Spring, 0, i + 1, rest, 0.0, 0.0});
  }
  def.nodes[0].x += 1.0; // a small push
  const soda::Model model = soda::build_model(def);
  for (int substeps : {1, 4}) {
    soda::State s = soda::make_state(model);
    soda::FrameStepper stepper(model, {soda::PhysicsMode::Continuous, soda::Integrator::Euler, substeps});
    soda::DivergenceMonitor monitor(model, s);
    bool healthy = true;
    for (int f = 0; f < 200 && healthy; ++f) {
      stepper.step(s);
      healthy = monitor.check(s);
    }
    INFO("substeps " << substeps << ": " << monitor.result().reason);
    if (substeps == 1) {
      CHECK_FALSE(healthy);
      CHECK(monitor.result().reason.find("energy runaway") == 0);
    } else {
      CHECK(healthy);
    }
  }
}

TEST_CASE("divergence: the bundled walkers are never flagged", "[stress]") {
  // No false alarms: classic creatures run 5,000 frames in soda mode with the
  // energy check on.
  for (const char* name : {"dainty_walker", "carefulslug", "monster_truck", "treader", "wheel", "wodka_m1", "turbine"}) {
    const std::string path = std::string(SODAEVO_MODELS_DIR) + "/" + name + ".xml";
    const soda::Model model = sodaevo::test::load_scene(path).model;
    soda::State s = soda::make_state(model);
    soda::DivergenceMonitor monitor(model, s);
    bool healthy = true;
    for (int f = 0; f < 5000 && healthy; ++f) {
      soda::step(model, s);
      healthy = monitor.check(s);
    }
    INFO(name << ": " << monitor.result().reason);
    CHECK(healthy);
  }
}
