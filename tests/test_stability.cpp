// The stability predictor (core/stiffness.hpp, core/stability.hpp): the stiffness
// matrix's spectrum against closed forms (one spring, fixed and free chains), the
// dense solver against Lanczos, and the predicted threshold of the soda step
// against what the engine does just below and just above it.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "bench/analytic_scenes.hpp"
#include "bench/stability_bench.hpp"
#include "formats/model_file.hpp"
#include "core/stability.hpp"
#include "core/step.hpp"
#include "core/stiffness.hpp"
#include "core/input_error.hpp"
#include "evolve/config/run_config.hpp"
#include "evolve/problems/walk_problem.hpp"
#include "test_support.hpp"

using namespace sodaevo::test;

namespace {

constexpr double kPi = 3.14159265358979323846;

soda::NodeDef stability_mass(double x, double y) { return {"m" + std::to_string(static_cast<long long>(x)), false, x, y, 0, 0}; }
soda::NodeDef fixed(double x, double y) { return {"f" + std::to_string(static_cast<long long>(x)), true, x, y, 0, 0}; }

/// Two masses `length` apart along a direction at `angle`, one spring of rest `rest`.
soda::ModelDef one_spring(double k, double length, double rest, double angle) {
  soda::ModelDef def = sodaevo::bench::open_world(0.0, 0.0, k);
  def.nodes.push_back({"a", false, 500.0, 500.0, 0, 0});
  def.nodes.push_back({"b", false, 500.0 + length * std::cos(angle), 500.0 + length * std::sin(angle), 0, 0});
  def.links.push_back({soda::LinkKind::Spring, 0, 1, rest, 0, 0});
  return def;
}

/// n masses in a row, 10 px apart, springs at rest between neighbours; with
/// fixed ends, a fixed node at each end joined by a spring too.
soda::ModelDef chain(int n, double k, bool fixed_ends) {
  soda::ModelDef def = sodaevo::bench::open_world(0.0, 0.0, k);
  for (int i = 1; i <= n; ++i) def.nodes.push_back(stability_mass(100.0 + 10.0 * i, 500.0));
  for (int i = 0; i + 1 < n; ++i) def.links.push_back({soda::LinkKind::Spring, i, i + 1, 10.0, 0, 0});
  if (fixed_ends) {
    def.nodes.push_back(fixed(100.0, 500.0));
    def.nodes.push_back(fixed(100.0 + 10.0 * (n + 1), 500.0));
    def.links.push_back({soda::LinkKind::Spring, n, 0, 10.0, 0, 0});
    def.links.push_back({soda::LinkKind::Spring, n - 1, n + 1, 10.0, 0, 0});
  }
  return def;
}

Eigen::VectorXd spectrum(const soda::Model& model) {
  const soda::State s = soda::make_state(model);
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Eigen::MatrixXd(soda::stiffness_matrix(model, s)))
      .eigenvalues();
}

/// One free mass between two fixed nodes, `parallel` springs of stiffness k on
/// each side along x, at rest, friction f, no gravity: omega^2 = 2 * parallel * k
/// along x. Started 0.1 px off centre.
soda::ModelDef hub(int parallel, double k, double friction) {
  soda::ModelDef def = sodaevo::bench::open_world(0.0, friction, k);
  def.nodes.push_back({"m", false, 500.1, 500.0, 0, 0});
  def.nodes.push_back(fixed(400.0, 500.0));
  def.nodes.push_back(fixed(600.0, 500.0));
  for (int i = 0; i < parallel; ++i) {
    def.links.push_back({soda::LinkKind::Spring, 1, 0, 100.0, 0, 0});
    def.links.push_back({soda::LinkKind::Spring, 0, 2, 100.0, 0, 0});
  }
  return def;
}

/// Largest |x - 500| over the last 100 of `frames` soda frames.
double late_amplitude(const soda::Model& model, long long frames) {
  soda::State s = soda::make_state(model);
  double worst = 0.0;
  for (long long f = 0; f < frames; ++f) {
    soda::step(model, s);
    if (f >= frames - 100) worst = std::max(worst, std::fabs(s.x[0] - 500.0));
  }
  return worst;
}

} // namespace

TEST_CASE("stiffness: two unit masses joined by one spring have omega^2 = 2k", "[stability]") {
  for (double k : {0.05, 0.2, 0.5}) {
    for (double angle : {0.0, 0.3, 1.0, 2.5}) {
      const soda::Model at_rest = soda::build_model(one_spring(k, 100.0, 100.0, angle));
      const Eigen::VectorXd e = spectrum(at_rest);
      CHECK(e[3] == Approx(2.0 * k).margin(1e-9));
      CHECK(std::fabs(e[2]) < 1e-12); // no transverse stiffness at rest; translations free
      // Stretched 10 %: the geometric term adds 2k (1 - D/L) across the link.
      const Eigen::VectorXd s = spectrum(soda::build_model(one_spring(k, 110.0, 100.0, angle)));
      CHECK(s[3] == Approx(2.0 * k).margin(1e-9));
      CHECK(s[2] == Approx(2.0 * k * (1.0 - 100.0 / 110.0)).margin(1e-9));
      // Compressed: that term is negative (buckling), not a faster mode.
      const Eigen::VectorXd c = spectrum(soda::build_model(one_spring(k, 90.0, 100.0, angle)));
      CHECK(c[0] == Approx(2.0 * k * (1.0 - 100.0 / 90.0)).margin(1e-9));
      CHECK(soda::predict_stability(at_rest, soda::make_state(at_rest), {}).omega_max ==
            Approx(std::sqrt(2.0 * k)).margin(1e-9));
    }
  }
}

TEST_CASE("stiffness: a chain's spectrum is the discrete Laplacian's", "[stability]") {
  const double k = 0.3;
  for (int n : {1, 2, 5, 12}) {
    // Fixed ends: 4k sin^2(j pi / (2 (n + 1))), j = 1..n; free ends: 4k sin^2(j pi / (2n)), j = 0..n-1.
    // Along the chain only; across it a chain at rest has no stiffness (n zeros).
    for (bool fixed_ends : {true, false}) {
      const Eigen::VectorXd e = spectrum(soda::build_model(chain(n, k, fixed_ends)));
      std::vector<double> expected(static_cast<std::size_t>(n), 0.0); // the transverse zeros
      for (int j = fixed_ends ? 1 : 0; j <= (fixed_ends ? n : n - 1); ++j) {
        const double s = std::sin(j * kPi / (2.0 * (fixed_ends ? n + 1 : n)));
        expected.push_back(4.0 * k * s * s);
      }
      std::sort(expected.begin(), expected.end());
      REQUIRE(e.size() == static_cast<Eigen::Index>(expected.size()));
      for (std::size_t i = 0; i < expected.size(); ++i) {
        INFO("n " << n << (fixed_ends ? " fixed" : " free") << ", eigenvalue " << i);
        CHECK(e[static_cast<Eigen::Index>(i)] == Approx(expected[i]).margin(1e-9));
      }
    }
  }
}

TEST_CASE("stability: Lanczos finds a long chain's largest eigenvalue as the closed form gives it", "[stability]") {
  const double k = 0.5;
  for (int n : {30, 250}) {
    const soda::Model model = soda::build_model(chain(n, k, true));
    const auto K = soda::stiffness_matrix(model, soda::make_state(model));
    const double s = std::sin(n * kPi / (2.0 * (n + 1)));
    const double exact = 4.0 * k * s * s;
    const soda::LargestEigenvalue lanczos = soda::largest_eigenvalue(K, 0);
    const soda::LargestEigenvalue dense = soda::largest_eigenvalue(K, 1 << 20);
    CHECK(lanczos.method == "lanczos");
    CHECK(dense.method == "dense");
    CHECK(lanczos.value == Approx(exact).epsilon(1e-10));
    CHECK(dense.value == Approx(exact).epsilon(1e-10));
  }
}

TEST_CASE("stability: the soda step's threshold 2(1+c)/c is where the engine turns unstable", "[stability]") {
  // omega^2 = 12k with six parallel springs a side; the threshold k* = 2(1+c)/c / 12.
  for (double f : {0.0, 0.05, 0.3}) {
    const double c = 1.0 - f;
    const double k_star = 2.0 * (1.0 + c) / c / 12.0;
    for (double share : {0.97, 1.03}) {
      const double k = k_star * share;
      if (k > 0.5) continue; // beyond the original's largest springyness
      const soda::Model model = soda::build_model(hub(6, k, f));
      const soda::StabilityPrediction p = soda::predict_stability(model, soda::make_state(model), {});
      INFO("f " << f << ", k " << k << ", margin " << p.margin);
      CHECK(p.omega_max * p.omega_max == Approx(12.0 * k).epsilon(1e-12));
      CHECK(p.margin == Approx(2.0 * (1.0 + c) / c / (12.0 * k)).epsilon(1e-12));
      CHECK(p.stable_dt == Approx(std::sqrt(2.0 * (1.0 + c) / c) / p.omega_max).epsilon(1e-12));
      const double amplitude = late_amplitude(model, 3000);
      // Started 0.1 px off: a stable step keeps it within 0.1 / sqrt(1 - w^2 / limit) < 1 px
      // (the discrete orbit's ellipse); an unstable one grows until the speed limit holds
      // it (an alternating mode of about 20 / 2 px).
      if (share < 1.0) CHECK(amplitude < 1.0);
      else CHECK(amplitude > 5.0);
    }
  }
}

TEST_CASE("stability: each continuous integrator's stable step", "[stability]") {
  const soda::Model model = soda::build_model(hub(1, 0.5, 0.0)); // omega = 1, no friction
  using soda::Integrator;
  using soda::PhysicsMode;
  // Without friction: Euler and Verlet w dt < 2, RK4 w dt < 2 sqrt(2) (its imaginary-axis limit).
  CHECK(soda::predict_stability(model, 1.0, {PhysicsMode::Continuous, Integrator::Euler, 1}).stable_dt ==
        Approx(2.0).epsilon(1e-12));
  CHECK(soda::predict_stability(model, 1.0, {PhysicsMode::Continuous, Integrator::Verlet, 1}).stable_dt ==
        Approx(2.0).epsilon(1e-12));
  const soda::StabilityPrediction rk4 = soda::predict_stability(model, 1.0, {PhysicsMode::Continuous, Integrator::Rk4, 4});
  CHECK(rk4.stable_dt == Approx(2.0 * std::sqrt(2.0)).epsilon(1e-9));
  CHECK(rk4.margin == Approx(8.0 * 16.0).epsilon(1e-8)); // (stable_dt / (1/4))^2
  // With friction, Verlet's limit does not move; Euler's widens as c = (1 - f)^dt shrinks.
  const soda::Model damped = soda::build_model(hub(1, 0.5, 0.3));
  CHECK(soda::predict_stability(damped, 1.0, {PhysicsMode::Continuous, Integrator::Verlet, 1}).stable_dt ==
        Approx(2.0).epsilon(1e-12));
  const double euler_dt = soda::predict_stability(damped, 1.0, {PhysicsMode::Continuous, Integrator::Euler, 1}).stable_dt;
  const double c = std::pow(0.7, euler_dt);
  CHECK(euler_dt * euler_dt == Approx(2.0 * (1.0 + c) / c).epsilon(1e-9));
  // Heavy drag alone makes RK4 unstable: lambda dt < 2.785 on the real axis, even with no spring.
  const soda::Model sticky = soda::build_model(hub(1, 0.5, 0.99));
  const double lambda = -std::log1p(-0.99);
  CHECK(soda::predict_stability(sticky, 0.0, {PhysicsMode::Continuous, Integrator::Rk4, 1}).stable_dt * lambda ==
        Approx(2.785293563).epsilon(1e-6));
  // No spring, no friction: nothing limits the explicit steps.
  CHECK(std::isinf(soda::predict_stability(model, 0.0, {}).margin));
}

TEST_CASE("simulate --stability: omega^2 = 2k for two masses and one spring, and the JSON keys", "[stability][cli]") {
  const auto dir = fresh_temp_dir("stability_cli");
  const auto file = dir / "spring.xml";
  soda::write_model_file(file, one_spring(0.2, 100.0, 100.0, 0.0));
  const ShellResult r = run_sodaevo("simulate " + file.string() + " --stability --json --frames 0");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const nlohmann::json j = nlohmann::json::parse(r.output);
  const double w = j.at("omega_max").get<double>();
  CHECK(w * w == Approx(0.4).margin(1e-9));
  // No friction: c = 1, margin 2(1 + c)/c / (2k) = 4 / 0.4, stable_dt = 2 / omega.
  CHECK(j.at("margin").get<double>() == Approx(10.0).epsilon(1e-9));
  CHECK(j.at("stable_dt").get<double>() == Approx(2.0 / w).epsilon(1e-9));
  const ShellResult walker = run_sodaevo("simulate " + (models_dir() / "dainty_walker.xml").string() +
                                         " --stability --json --frames 200 --stability-every 20");
  REQUIRE(walker.exit_code == 0);
  const nlohmann::json d = nlohmann::json::parse(walker.output);
  CHECK(d.at("samples").get<int>() == 11);
  CHECK(d.at("min_margin").get<double>() <= d.at("margin").get<double>());
}

TEST_CASE("bench stability: confusion matrix, ROC curve and its area on hand-counted samples", "[stability]") {
  using sodaevo::bench::confusion;
  // margins and outcomes: diverged at 0.5, 0.9, 3; healthy at 0.8, 2, 5, inf.
  const std::vector<double> margins = {0.5, 0.8, 0.9, 2.0, 3.0, 5.0, INFINITY};
  const std::vector<bool> diverged = {true, false, true, false, true, false, false};
  const sodaevo::bench::Confusion c = confusion(margins, diverged, 1.0);
  CHECK(c.true_positive == 2);
  CHECK(c.false_positive == 1);
  CHECK(c.false_negative == 1);
  CHECK(c.true_negative == 3);
  // Pairs (diverged, healthy) with the diverged margin smaller: 0.5 beats all 4,
  // 0.9 beats 3 (not 0.8), 3 beats 2 (5, inf): 9 of 12.
  CHECK(sodaevo::bench::roc_area(margins, diverged) == Approx(9.0 / 12.0));
  const auto roc = sodaevo::bench::roc_curve(margins, diverged);
  REQUIRE(roc.size() == 8);
  CHECK(roc.front().true_positive_rate == 0.0);
  CHECK(roc[1].true_positive_rate == Approx(1.0 / 3.0)); // below 0.8: only 0.5
  CHECK(roc[1].false_positive_rate == 0.0);
  CHECK(roc.back().true_positive_rate == 1.0);
  CHECK(roc.back().false_positive_rate == 1.0);
  // Ties count half.
  CHECK(sodaevo::bench::roc_area({1.0, 1.0}, {true, false}) == Approx(0.5));
}

TEST_CASE("bench stability: a small run flags unstable extreme creatures better than chance", "[stability]") {
  sodaevo::bench::StabilityBenchOptions o;
  o.creatures = 150;
  o.frames = 60;
  const sodaevo::bench::StabilityBenchReport r = sodaevo::bench::run_stability_bench(o);
  REQUIRE(r.cases.size() == 150);
  const long long diverged = r.first.true_positive + r.first.false_negative;
  INFO("diverged " << diverged << ", AUC frame 0 " << r.auc_first << ", lowest " << r.auc_lowest);
  CHECK(diverged > 0);
  CHECK(diverged < 150);
  CHECK(r.auc_first > 0.6);
  CHECK(r.auc_lowest >= r.auc_first - 0.05);
}

TEST_CASE("/fitness/stability_margin_min refuses a creature below the margin, with the reason", "[stability][evolve]") {
  // The Dainty Walker's margin at its start in its own world is 1.27 (w_max^2 3.20
  // against 4.06); Sodarace scaling and placement keep it (K scales with k only).
  const soda::ModelDef walker = soda::read_model_file(models_dir() / "dainty_walker.xml").def;
  sodaevo::RunConfig config;
  config.fitness.stability_margin_min = 1.2;
  const sodaevo::WalkProblem lenient(config.fitness, config.world, config.limits);
  CHECK_NOTHROW(lenient.prepare(walker));
  config.fitness.stability_margin_min = 1.3;
  const sodaevo::WalkProblem strict(config.fitness, config.world, config.limits);
  try {
    (void)strict.prepare(walker);
    FAIL("not refused");
  } catch (const soda::InputError& e) {
    const std::string why = e.what();
    CHECK(why.find("stability margin 1.26") == 0);
    CHECK(why.find("below /fitness/stability_margin_min 1.3") != std::string::npos);
  }
  // With more sub-steps the same creature passes: euler/2 has four times the margin, about.
  config.fitness.mode = soda::PhysicsMode::Continuous;
  config.fitness.substeps = 2;
  CHECK_NOTHROW(sodaevo::WalkProblem(config.fitness, config.world, config.limits).prepare(walker));
}
