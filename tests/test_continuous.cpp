// The continuous mode (core/continuous_step.hpp): with one Euler step per frame it
// is the original engine bit for bit; on smooth scenes each integrator converges at
// its order to the closed-form solution of the ODE (or to a converged reference).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "bench/analytic_scenes.hpp"
#include "bench/extreme_creatures.hpp"
#include "core/continuous_step.hpp"
#include "core/divergence.hpp"
#include "formats/model_file.hpp"
#include "core/step_failure.hpp"
#include "core/input_error.hpp"
#include "core/step.hpp"
#include "core/stepping.hpp"
#include "test_support.hpp"

using namespace sodaevo::test;
namespace fs = std::filesystem;

namespace {

/// Compares soda::step with continuous Euler at one sub-step for `frames` frames,
/// frame by frame. Returns the number of models compared.
int compare_directory(const fs::path& dir, long long frames) {
  int compared = 0;
  for (const fs::path& file : xml_files_under(dir)) {
    const std::optional<Scene> scene = load_scene_unless_race(file);
    if (!scene) continue;
    const soda::Model& model = scene->model;
    soda::State reference = soda::make_state(model);
    soda::State continuous = soda::make_state(model);
    soda::ContinuousStepper stepper(model, {soda::Integrator::Euler, 1});
    std::string diff;
    long long frame = 0;
    for (; frame < frames && diff.empty(); ++frame) {
      soda::step(model, reference);
      stepper.step(continuous);
      diff = compare_states(model, reference, continuous);
    }
    INFO(file.string() << ": first difference at frame " << frame << ": " << diff);
    CHECK(diff.empty());
    ++compared;
  }
  return compared;
}

/// Largest coordinate difference between the scene's state after `frames` frames
/// and `expected` (x0, y0, x1, ... of the free masses).
double position_error(const soda::Model& model, const soda::State& s, const std::vector<double>& expected) {
  double worst = 0.0;
  for (int i = 0; i < model.mass_count; ++i) {
    worst = std::max(worst, std::fabs(s.x[i] - expected[2 * i]));
    worst = std::max(worst, std::fabs(s.y[i] - expected[2 * i + 1]));
  }
  return worst;
}

std::vector<double> positions_after(const soda::Model& model, soda::Integrator integrator, int substeps,
                                    long long frames) {
  soda::State s = soda::make_state(model);
  soda::ContinuousStepper stepper(model, {integrator, substeps});
  stepper.run(s, frames);
  std::vector<double> out;
  for (int i = 0; i < model.mass_count; ++i) {
    out.push_back(s.x[i]);
    out.push_back(s.y[i]);
  }
  return out;
}

/// Least-squares slope of log(error) against log(dt).
double fitted_order(const std::vector<int>& substeps, const std::vector<double>& errors) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(substeps.size());
  for (std::size_t i = 0; i < substeps.size(); ++i) {
    const double x = std::log(1.0 / substeps[i]);
    const double y = std::log(errors[i]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

} // namespace

TEST_CASE("continuous Euler with one step per frame equals soda bit for bit on every test model", "[continuous]") {
  CHECK(compare_directory(data_dir() / "soda", 5000) > 20);
}

TEST_CASE("continuous Euler with one step per frame equals soda bit for bit on the bundled creatures",
          "[continuous]") {
  CHECK(compare_directory(models_dir(), 10000) >= 5);
}

TEST_CASE("continuous Euler with one step per frame equals soda bit for bit on the shared models", "[continuous]") {
  const fs::path shared = shared_models_dir();
  if (shared.empty()) {
    WARN("../shared/models/soda is absent: only tests/data/soda and models/ are compared");
    return;
  }
  CHECK(compare_directory(shared, 5000) > 0);
}

TEST_CASE("each integrator converges at its order on the smooth scenes", "[continuous]") {
  const long long frames = 40;
  struct Expect {
    soda::Integrator integrator;
    std::vector<int> substeps; // a range where the error is well above rounding
    double order;
  };
  const std::vector<Expect> expectations = {
      {soda::Integrator::Euler, {4, 8, 16, 32, 64}, 1.0},
      {soda::Integrator::Verlet, {4, 8, 16, 32, 64}, 2.0},
      {soda::Integrator::Rk4, {2, 4, 8, 16}, 4.0},
      // Backward Euler's damping is far from asymptotic at 4 steps per frame (the spring
      // loses 40 % of its amplitude in 40 frames): its range starts finer.
      {soda::Integrator::BackwardEuler, {32, 64, 128, 256, 512}, 1.0},
      {soda::Integrator::ImplicitMidpoint, {4, 8, 16, 32, 64}, 2.0},
  };
  for (const sodaevo::bench::AnalyticScene& scene : sodaevo::bench::analytic_scenes()) {
    // The stiff hub vibrates 3x faster than these ranges resolve; its own test below.
    if (scene.name == "stiff hub") continue;
    const soda::Model model = soda::build_model(scene.def);
    // No closed form: RK4 with 1024 steps per frame (error ~1e-13) is the truth.
    const std::vector<double> truth = scene.exact ? scene.exact(static_cast<double>(frames))
                                                  : positions_after(model, soda::Integrator::Rk4, 1024, frames);
    for (const Expect& e : expectations) {
      std::vector<double> errors;
      for (int k : e.substeps) {
        soda::State s = soda::make_state(model);
        soda::ContinuousStepper(model, {e.integrator, k}).run(s, frames);
        errors.push_back(position_error(model, s, truth));
      }
      const double order = fitted_order(e.substeps, errors);
      INFO(scene.name << ", " << soda::integrator_name(e.integrator) << ": errors " << errors.front() << " .. "
                      << errors.back() << ", fitted order " << order);
      CHECK(errors.back() < errors.front());
      CHECK(order == Approx(e.order).margin(e.order * 0.15));
    }
  }
}

TEST_CASE("the closed forms agree with the original engine's own closed form at dt = 1 only to first order",
          "[continuous]") {
  // The soda recurrence for free fall (test_physics.cpp) and the ODE's exact
  // solution differ by O(1) px after 40 frames: the original is a first-order
  // discretisation of the continuous model, not the model itself.
  const auto scene = sodaevo::bench::free_fall_with_friction();
  const soda::Model model = soda::build_model(scene.def);
  soda::State s = soda::make_state(model);
  soda::run(model, s, 40);
  const double err = position_error(model, s, scene.exact(40.0));
  CHECK(err > 0.5);
  CHECK(err < 10.0);
}

TEST_CASE("continuous stepper rejects a bad sub-step count", "[continuous]") {
  const auto scene = sodaevo::bench::single_spring();
  const soda::Model model = soda::build_model(scene.def);
  CHECK_THROWS_AS(soda::ContinuousStepper(model, {soda::Integrator::Euler, 0}), soda::InputError);
  CHECK_THROWS_AS(soda::ContinuousStepper(model, {soda::Integrator::Rk4, soda::kMaxSubsteps + 1}), soda::InputError);
  CHECK(soda::parse_integrator("verlet") == soda::Integrator::Verlet);
  CHECK(soda::parse_integrator("backward-euler") == soda::Integrator::BackwardEuler);
  CHECK(soda::parse_integrator("implicit-midpoint") == soda::Integrator::ImplicitMidpoint);
  CHECK_FALSE(soda::parse_integrator("leapfrog").has_value());
  CHECK(soda::parse_mode("continuous") == soda::PhysicsMode::Continuous);
}

TEST_CASE("a block sliding on the sticky floor stops where the continuous model's closed form says",
          "[continuous]") {
  // One mass on the floor, vx0 = 10 px/frame, gravity keeping it there. In the
  // continuous model air friction is the drag lambda_a = -ln(1 - f) and surface
  // friction on a resting mass the drag lambda_s = -ln(Fs) per frame of contact, so
  // vx decays as e^(-(lambda_a + lambda_s) t) and the block slides
  // vx0 / (lambda_a + lambda_s) px. Every integrator must approach it at first
  // order (contact is a first-order event); a split-kick integrator that felt the
  // floor only every other step would slide about twice as far.
  const double f = 0.03, fs = 0.1, vx0 = 10.0;
  soda::ModelDef def;
  def.width = 100000;
  def.height = 100000;
  def.environment = {0.38, f, 0.2};
  def.collisions = {fs, -0.75};
  def.settings.autoreverse = false;
  def.nodes.push_back({"m", false, 500.0, 0.0, vx0, 0.0});
  const soda::Model model = soda::build_model(def);
  const double exact = vx0 / (-std::log1p(-f) - std::log(fs));
  for (soda::Integrator integrator : soda::kIntegrators) {
    double errors[2] = {};
    int k = 0;
    for (int substeps : {64, 256}) {
      soda::State s = soda::make_state(model);
      soda::ContinuousStepper(model, {integrator, substeps}).run(s, 200);
      errors[k++] = std::fabs((s.x[0] - 500.0) - exact);
    }
    INFO(soda::integrator_name(integrator) << ": errors " << errors[0] << ", " << errors[1] << " px of " << exact);
    CHECK(errors[1] < 0.01 * exact);
    CHECK(errors[0] / errors[1] == Approx(4.0).margin(1.0)); // first order: 4x the steps, a quarter of the error
  }
}

TEST_CASE("implicit integrators: a singular Newton matrix is a StepFailure with the frame, the state untouched",
          "[continuous][implicit]") {
  // Two masses 50 px apart, one spring of rest 100, k 0.5, no friction: the compressed
  // spring's geometric term gives K the eigenvalue 2k (1 - D/L) = -1 across it, so
  // backward Euler at dt = 1 has J = I + K singular.
  soda::ModelDef def = sodaevo::bench::open_world(0.0, 0.0, 0.5);
  def.nodes.push_back({"a", false, 500.0, 500.0, 0.0, 1.0});
  def.nodes.push_back({"b", false, 550.0, 500.0, 0.0, 1.0});
  def.links.push_back({soda::LinkKind::Spring, 0, 1, 100.0, 0.0, 0.0});
  const soda::Model model = soda::build_model(def);
  soda::State s = soda::make_state(model);
  const soda::State before = s;
  soda::ContinuousStepper stepper(model, {soda::Integrator::BackwardEuler, 1});
  try {
    stepper.step(s);
    FAIL("no StepFailure");
  } catch (const soda::StepFailure& failure) {
    CHECK(failure.frame == 1);
    CHECK(failure.reason.find("backward-euler: singular Newton matrix") == 0);
  }
  CHECK(compare_states(model, before, s).empty());
  // The same pair at 4 steps per frame is regular: it steps, finite.
  soda::State fine = soda::make_state(model);
  soda::ContinuousStepper(model, {soda::Integrator::BackwardEuler, 4}).run(fine, 10);
  CHECK(std::isfinite(fine.x[0]));
  // simulate reports it as divergence at frame 1, not as an error and never as NaN.
  const fs::path file = fresh_temp_dir("implicit_singular") / "pair.xml";
  soda::write_model_file(file, def);
  const ShellResult r = run_sodaevo("simulate " + file.string() +
                                    " --mode continuous --integrator backward-euler --frames 5 --json");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("\"diverged\":true") != std::string::npos);
  CHECK(r.output.find("\"diverged_frame\":1") != std::string::npos);
  CHECK(r.output.find("singular Newton matrix") != std::string::npos);
  CHECK(r.output.find("nan") == std::string::npos);
}

TEST_CASE("implicit integrators on extreme creatures: finite states or a StepFailure, never a hang",
          "[continuous][implicit]") {
  int failures = 0, runs = 0;
  for (std::uint64_t i = 0; i < 12; ++i) {
    sodaevo::Rng rng = sodaevo::Rng::stream(7, i, 0, 0x1a91);
    const soda::Model model = soda::build_model(sodaevo::bench::extreme_creature(rng));
    for (soda::Integrator integrator : {soda::Integrator::BackwardEuler, soda::Integrator::ImplicitMidpoint}) {
      soda::State s = soda::make_state(model);
      soda::ContinuousStepper stepper(model, {integrator, 1});
      ++runs;
      try {
        stepper.run(s, 60);
      } catch (const soda::StepFailure& failure) {
        ++failures;
        CHECK(!failure.reason.empty());
        CHECK(failure.frame == s.frame + 1);
      }
      INFO("creature " << i << ", " << soda::integrator_name(integrator));
      CHECK(!soda::first_non_finite(model, s).has_value());
    }
  }
  CHECK(failures < runs);
}

TEST_CASE("the stiff hub: explicit steps of one frame blow up, the implicit ones stay on the closed form",
          "[continuous][implicit]") {
  const auto scene = sodaevo::bench::stiff_hub();
  const soda::Model model = soda::build_model(scene.def);
  const long long frames = 40;
  const std::vector<double> truth = scene.exact(static_cast<double>(frames));
  auto error_of = [&](soda::Integrator integrator, int substeps) {
    return position_error(model, [&] {
      soda::State s = soda::make_state(model);
      soda::ContinuousStepper(model, {integrator, substeps}).run(s, frames);
      return s;
    }(), truth);
  };
  soda::State soda_state = soda::make_state(model);
  soda::run(model, soda_state, frames);
  // Started 2 px off centre: the unstable steps grow until the speed limit holds them.
  CHECK(position_error(model, soda_state, truth) > 5.0);
  CHECK(error_of(soda::Integrator::Euler, 1) > 5.0);
  CHECK(error_of(soda::Integrator::Verlet, 1) > 5.0);
  // At one step per frame the implicit ones stay within the 2 px the mass started off,
  // the midpoint rule within a fraction of it; both converge with sub-steps.
  const double be1 = error_of(soda::Integrator::BackwardEuler, 1);
  const double mid1 = error_of(soda::Integrator::ImplicitMidpoint, 1);
  INFO("backward-euler/1 " << be1 << " px, implicit-midpoint/1 " << mid1 << " px");
  CHECK(be1 < 2.0);
  CHECK(mid1 < 2.0);
  // Order 2: 8x the steps, 64x less error (asymptotically; 40 allows for the rest).
  CHECK(error_of(soda::Integrator::ImplicitMidpoint, 128) < error_of(soda::Integrator::ImplicitMidpoint, 16) / 40.0);
}
