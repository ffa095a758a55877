// Physics checks that do not depend on the golden data: closed forms of the
// frame recurrence (docs/physics.md) and a conservation law.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "bench/analytic_scenes.hpp"
#include "core/model.hpp"
#include "core/step.hpp"
#include "evolve/algorithms/rng.hpp"

namespace {

using sodaevo::bench::open_world;

soda::NodeDef physics_mass(double x, double y, double vx = 0, double vy = 0) {
  return {"m", false, x, y, vx, vy};
}

} // namespace

TEST_CASE("free fall follows the closed form of the frame recurrence", "[physics]") {
  // v_n = a*(v_{n-1} - g) with a = 1 - f, so v_n = v*(1 - a^n), v* = -a*g/f, and
  // y_n = y_0 + v*(n - a*(1 - a^n)/(1 - a)). Terminal speed a*g/f stays below 20.
  const double g = 0.3, f = 0.05, a = 1.0 - f, y0 = 90000.0;
  soda::ModelDef def = open_world(g, f, 0.2);
  def.nodes.push_back(physics_mass(500.0, y0));
  const soda::Model model = soda::build_model(def);
  soda::State s = soda::make_state(model);
  const double v_inf = -a * g / f;
  for (int n = 1; n <= 2000; ++n) {
    soda::step(model, s);
    const double an = std::pow(a, n);
    const double v = v_inf * (1.0 - an);
    const double y = y0 + v_inf * (n - a * (1.0 - an) / (1.0 - a));
    REQUIRE(s.vy[0] == Approx(v).epsilon(1e-12).margin(1e-12));
    REQUIRE(s.y[0] == Approx(y).epsilon(1e-12));
    REQUIRE(s.x[0] == 500.0);
    REQUIRE(s.vx[0] == 0.0);
  }
}

TEST_CASE("the syrup threshold caps the speed at 20 px/frame", "[physics]") {
  // Without air friction gravity 1 would reach 21 px/frame after 21 frames; the
  // speed limiter scales it back to 20 (docs/physics.md, part 2 step 2).
  soda::ModelDef def = open_world(1.0, 0.0, 0.2);
  def.nodes.push_back(physics_mass(500.0, 90000.0));
  const soda::Model model = soda::build_model(def);
  soda::State s = soda::make_state(model);
  for (int n = 1; n <= 200; ++n) {
    soda::step(model, s);
    if (n < 20) REQUIRE(s.vy[0] == -static_cast<double>(n));
    else REQUIRE(s.vy[0] == Approx(-20.0).epsilon(1e-15));
  }
}

TEST_CASE("a single spring oscillates with the period the recurrence predicts", "[physics]") {
  // One mass on a spring to a fixed node along x, no gravity, no friction. With
  // e = L - R the update is v' = v - k*e, e' = e + v' (symplectic Euler): the
  // matrix [[1, -k], [1, 1-k]] has det 1 and trace 2 - k, so the motion is
  // e_n = e_0*cos(n*theta) + B*sin(n*theta), cos(theta) = 1 - k/2,
  // B = -e_0*(k/2)/sin(theta) (from e_1 = (1-k)*e_0), period 2*pi/theta frames.
  const double k = 0.2, rest = 100.0, e0 = 10.0;
  soda::ModelDef def = open_world(0.0, 0.0, k);
  def.nodes.push_back({"n", true, 50000.0, 50000.0, 0, 0});
  def.nodes.push_back(physics_mass(50000.0 + rest + e0, 50000.0));
  def.links.push_back({soda::LinkKind::Spring, 0, 1, rest, 0, 0});
  const soda::Model model = soda::build_model(def);
  soda::State s = soda::make_state(model);
  const double theta = std::acos(1.0 - k / 2.0);
  const double b = -e0 * (k / 2.0) / std::sin(theta);
  const int mass_point = 0, node_point = 1;
  REQUIRE(model.is_mass(mass_point));
  int crossings = 0;
  double first_crossing = -1, last_crossing = -1, previous_e = e0;
  for (int n = 1; n <= 5000; ++n) {
    soda::step(model, s);
    const double e = (s.x[mass_point] - s.x[node_point]) - rest;
    REQUIRE(e == Approx(e0 * std::cos(n * theta) + b * std::sin(n * theta)).margin(1e-8));
    REQUIRE(s.y[mass_point] == 50000.0);
    REQUIRE(s.x[node_point] == 50000.0); // fixed nodes never move
    if ((previous_e > 0) != (e > 0)) {
      const double t = (n - 1) + previous_e / (previous_e - e); // linear interpolation
      if (crossings == 0) first_crossing = t;
      last_crossing = t;
      ++crossings;
    }
    previous_e = e;
  }
  const double measured_period = 2.0 * (last_crossing - first_crossing) / (crossings - 1);
  CHECK(measured_period == Approx(2.0 * M_PI / theta).epsilon(1e-3));
}

TEST_CASE("without friction, gravity and walls, momentum is conserved", "[physics]") {
  // Every link adds +c*d to one end and -c*d to the other (docs/physics.md, part 1), so the sum
  // of velocities only changes by rounding. A random creature with springs and muscles.
  sodaevo::Rng rng(12345);
  auto uniform = [&rng]() { return rng.uniform(); };
  soda::ModelDef def = open_world(0.0, 0.0, 0.05);
  def.wave = {1.0, 0.3, 0.02};
  const int masses = 12;
  for (int i = 0; i < masses; ++i) {
    def.nodes.push_back(physics_mass(50000 + 100 * uniform(), 50000 + 100 * uniform(), uniform() - 0.5, uniform() - 0.5));
  }
  for (int i = 0; i < masses; ++i) {
    for (int j = i + 1; j < masses; j += 3) {
      const double dx = def.nodes[j].x - def.nodes[i].x, dy = def.nodes[j].y - def.nodes[i].y;
      const bool muscle = (i + j) % 2 == 0;
      def.links.push_back({muscle ? soda::LinkKind::Muscle : soda::LinkKind::Spring, i, j,
                           std::sqrt(dx * dx + dy * dy) * (0.95 + 0.1 * uniform()), muscle ? 0.2 : 0.0,
                           muscle ? uniform() : 0.0});
    }
  }
  const soda::Model model = soda::build_model(def);
  soda::State s = soda::make_state(model);
  auto momentum = [&] {
    double px = 0, py = 0;
    for (int i = 0; i < model.mass_count; ++i) {
      px += s.vx[i];
      py += s.vy[i];
    }
    return std::pair{px, py};
  };
  const auto [px0, py0] = momentum();
  double max_speed = 0;
  // 400 frames: the muscles pump energy in (nothing damps it), so after long
  // enough the speed limit would act.
  for (int n = 0; n < 400; ++n) {
    soda::step(model, s);
    for (int i = 0; i < model.mass_count; ++i) max_speed = std::max(max_speed, std::hypot(s.vx[i], s.vy[i]));
    INFO("frame " << n << ", max speed so far " << max_speed);
    const auto [px, py] = momentum();
    REQUIRE(std::fabs(px - px0) < 1e-9);
    REQUIRE(std::fabs(py - py0) < 1e-9);
  }
  // The test is only meaningful if the creature moved and the speed limiter (which
  // is a friction) never acted.
  CHECK(max_speed > 0.5);
  CHECK(max_speed < 20.0);
}

TEST_CASE("a mass at rest is not moved and fixed nodes ignore impulses", "[physics]") {
  soda::ModelDef def = open_world(0.0, 0.0, 0.5);
  def.nodes.push_back(physics_mass(100.0, 100.0, 5e-6, -5e-6)); // below the rest threshold 1e-5
  const soda::Model model = soda::build_model(def);
  soda::State s = soda::make_state(model);
  soda::step(model, s);
  CHECK(s.x[0] == 100.0);
  CHECK(s.y[0] == 100.0);
  CHECK(s.vx[0] == 5e-6); // the velocity is kept
}

TEST_CASE("a mass crossing a fixed bar responds as the fixed-bar rule says (docs/physics.md)", "[physics]") {
  // Horizontal bar y = 100 between two fixed nodes; the mass moves from (300, 105)
  // by (2, -10), crossing at t = 0.5. With u = (1, 0), n = (0, 1): vt = 2, vn = -10.
  // Position: crossing point (301, 100) plus (1 - t)*Fs*vt*u = (0.1, 0); velocity
  // Fs*vt*u + Rs*vn*n = (0.2, 7.5) for (Fs, Rs) = (0.1, -0.75).
  soda::ModelDef def = open_world(0.0, 0.0, 0.2);
  def.nodes.push_back({"n0", true, 100.0, 100.0, 0, 0});
  def.nodes.push_back({"n1", true, 500.0, 100.0, 0, 0});
  def.nodes.push_back(physics_mass(300.0, 105.0, 2.0, -10.0));
  def.links.push_back({soda::LinkKind::FixedBar, 0, 1, 0, 0, 0});
  const soda::Model model = soda::build_model(def);
  soda::State s = soda::make_state(model);
  soda::step(model, s);
  CHECK(s.x[0] == Approx(301.1).epsilon(1e-12));
  CHECK(s.y[0] == Approx(100.0).epsilon(1e-12));
  CHECK(s.y[0] >= 100.0); // it stays on the side it came from
  CHECK(s.vx[0] == Approx(0.2).epsilon(1e-12));
  CHECK(s.vy[0] == Approx(7.5).epsilon(1e-12));
  // Next frame it moves up, away from the bar, freely.
  soda::step(model, s);
  CHECK(s.y[0] == Approx(107.5).epsilon(1e-9));
}

// wrap_phase finds floor by comparisons on [-1, 2); its definition (docs/physics.md, "The
// wave", the original's parser) is x - floor(x) with a result of 1.0 mapped to 0.
TEST_CASE("wrap_phase equals x - floor(x) bit for bit, signed zeros and edges included", "[physics]") {
  auto by_definition = [](double x) {
    const double w = x - std::floor(x);
    return w >= 1.0 ? 0.0 : w;
  };
  auto bits = [](double v) {
    std::uint64_t b = 0;
    std::memcpy(&b, &v, sizeof b);
    return b;
  };
  std::vector<double> xs = {0.0, -0.0, 1.0, -1.0, 2.0, -2.0, 0.5, -0.5, 1e-300, -1e-300, -1e-17, -0x1p-54,
                            -0x1p-53, std::nextafter(1.0, 0.0), std::nextafter(2.0, 0.0), std::nextafter(-1.0, 0.0),
                            std::nextafter(-1.0, -2.0), std::nextafter(0.0, -1.0), 3.75, -7.25, 1e20, -1e20};
  sodaevo::Rng rng(42);
  for (int k = 0; k < 100000; ++k) {
    const double u = rng.uniform();
    xs.push_back(-1.5 + 4.0 * u);                    // around the fast range [-1, 2)
    xs.push_back((k % 2 ? -1.0 : 1.0) * u * 0x1p-40); // tiny values of both signs
  }
  for (double x : xs) {
    INFO("x = " << x);
    REQUIRE(bits(soda::wrap_phase(x)) == bits(by_definition(x)));
  }
}

TEST_CASE("a model's derived constants are formed once, by hand-checked values", "[physics]") {
  // Gravity 0.3 down: step +0.3; friction 0.25: keep 0.75; a muscle of amplitude
  // 0.4 under a wave of amplitude 0.5: power 0.2 (a halving, exact); a spring: 0.
  soda::ModelDef def = open_world(0.3, 0.25, 0.2);
  def.wave.amplitude = 0.5;
  def.nodes.push_back(physics_mass(100.0, 100.0));
  def.nodes.push_back(physics_mass(150.0, 100.0));
  def.nodes.push_back(physics_mass(125.0, 140.0));
  def.links.push_back({soda::LinkKind::Muscle, 0, 1, 50.0, 0.4, 0.25});
  def.links.push_back({soda::LinkKind::Spring, 1, 2, 47.0, 0.0, 0.0});
  soda::Model model = soda::build_model(def);
  CHECK(model.gravity_step == 0.3);
  CHECK(model.air_keep == 0.75);
  REQUIRE(model.link_power.size() == 2);
  CHECK(model.link_power[0] == 0.2);
  CHECK(model.link_power[1] == 0.0);
  CHECK(soda::is_wave_muscle(model, 0));
  CHECK_FALSE(soda::is_wave_muscle(model, 1));
  CHECK(soda::constants_current(model));

  // Changed by hand: stale until set_constants. Gravity up with g = 0 is -0, not
  // +0 (vy - (-0) turns a -0 velocity into +0: not an identity).
  model.gravity = 0.0;
  model.gravity_direction = soda::GravityDirection::Up;
  model.friction = 0.5;
  model.link_amplitude[0] = 0.0;
  CHECK_FALSE(soda::constants_current(model));
  soda::set_constants(model);
  CHECK(soda::constants_current(model));
  CHECK(model.gravity_step == 0.0);
  CHECK(std::signbit(model.gravity_step));
  CHECK(model.air_keep == 0.5);
  CHECK(model.link_power[0] == 0.0);
  CHECK_FALSE(soda::is_wave_muscle(model, 0));
}
