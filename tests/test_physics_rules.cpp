// Each rule of the engine (docs/physics.md), one at a time, on scenes of one to
// three masses stepped once by the reference step. The expected numbers are
// worked out here from the rules as docs/physics.md states them, in the order
// the rule gives, not read from the engine's code: exact comparisons throughout.
#include <catch2/catch.hpp>

#include <bit>
#include <cmath>
#include <vector>

#include "core/constants.hpp"
#include "core/model.hpp"
#include "core/sine.hpp"
#include "core/step.hpp"

namespace {

using soda::GravityDirection;
using soda::LinkKind;
using soda::ModelDef;
using soda::WaveDirection;

bool same(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

/// A world with nothing acting: no gravity, no air friction, wave stopped; a big
/// container (1000 x 1000) so that nothing touches a wall unless a test says so.
ModelDef quiet_world() {
  ModelDef d;
  d.width = 1000;
  d.height = 1000;
  d.environment.gravity = 0.0;
  d.environment.friction = 0.0;
  d.environment.springyness = 0.2;
  d.wave.speed = 0.0;
  d.settings.autoreverse = false;
  return d;
}

soda::NodeDef rule_mass(double x, double y, double vx = 0.0, double vy = 0.0) {
  soda::NodeDef n;
  n.x = x;
  n.y = y;
  n.vx = vx;
  n.vy = vy;
  return n;
}

soda::NodeDef fixed_node(double x, double y) {
  soda::NodeDef n;
  n.fixed = true;
  n.x = x;
  n.y = y;
  return n;
}

soda::LinkDef rule_spring(int a, int b, double rest) {
  soda::LinkDef l;
  l.kind = LinkKind::Spring;
  l.a = a;
  l.b = b;
  l.rest_length = rest;
  return l;
}

struct Stepped {
  soda::Model model;
  soda::State state;
};

/// The scene after `frames` reference steps.
Stepped stepped(const ModelDef& d, int frames = 1) {
  Stepped s{soda::build_model(d), {}};
  s.state = soda::make_state(s.model);
  for (int f = 0; f < frames; ++f) soda::step(s.model, s.state);
  return s;
}

} // namespace

// --- 5.1: the wave advances after the physics, wrapped into [0, 1) -------------

TEST_CASE("rule: the wave advances by speed times mode and wraps below 1", "[physics_rules]") {
  ModelDef d = quiet_world();
  d.nodes = {rule_mass(100, 100)};
  d.wave.speed = 0.01;
  d.wave.phase = 0.995;
  d.settings.wave_direction = WaveDirection::Forward;
  CHECK(same(stepped(d).state.wave_phase, (0.995 + 0.01) - 1.0));
  d.wave.phase = 0.25;
  CHECK(same(stepped(d).state.wave_phase, 0.25 + 0.01));

  d.wave.phase = 0.003;
  d.settings.wave_direction = WaveDirection::Reverse;
  CHECK(same(stepped(d).state.wave_phase, (0.003 - 0.01) + 1.0));

  d.settings.wave_direction = WaveDirection::Manual;
  CHECK(same(stepped(d).state.wave_phase, 0.003));

  // Landing on 1.0 exactly wraps to 0.
  d.wave.phase = 0.75;
  d.wave.speed = 0.25;
  d.settings.wave_direction = WaveDirection::Forward;
  CHECK(same(stepped(d).state.wave_phase, 0.0));
}

// --- 5.2: links, in file order, velocities changed at once ---------------------

TEST_CASE("rule: a spring pushes its ends by c = k (L - D) / L along B - A", "[physics_rules]") {
  ModelDef d = quiet_world();
  d.nodes = {rule_mass(10, 50), rule_mass(40, 54)};
  d.links = {rule_spring(0, 1, 25.0)};
  const Stepped s = stepped(d);
  const double dx = 40.0 - 10.0, dy = 54.0 - 50.0;
  const double length = std::sqrt(dx * dx + dy * dy);
  const double c = 0.2 * (length - 25.0) / length; // stretched: c > 0 pulls the ends together
  REQUIRE(c > 0.0);
  CHECK(same(s.state.vx[0], c * dx));
  CHECK(same(s.state.vy[0], c * dy));
  CHECK(same(s.state.vx[1], 0.0 - c * dx));
  CHECK(same(s.state.vy[1], 0.0 - c * dy));
  // Then the masses move by their new velocities (no friction: factor 1 - 0 = 1).
  CHECK(same(s.state.x[0], 10.0 + c * dx));
  CHECK(same(s.state.y[1], 54.0 + (0.0 - c * dy)));
}

TEST_CASE("rule: a muscle's length is rest (1 + (Aw Am) sin(2 pi (phi_m - phi_w)))", "[physics_rules]") {
  ModelDef d = quiet_world();
  d.nodes = {rule_mass(10, 50), rule_mass(40, 50)};
  soda::LinkDef muscle = rule_spring(0, 1, 25.0);
  muscle.kind = LinkKind::Muscle;
  muscle.amplitude = 0.5;
  muscle.phase = 0.3;
  d.links = {muscle};
  d.wave.amplitude = 0.8;
  d.wave.phase = 0.1;
  d.wave.speed = 0.01; // the wave moves after the links: this frame uses 0.1
  // The sine is the engine's own (tests/test_sine.cpp checks it against glibc's).
  const double target = 25.0 * (1.0 + (0.8 * 0.5) * soda::sine(soda::kTwoPi * (0.3 - 0.1)));
  const double plus_target = 25.0 * (1.0 + (0.8 * 0.5) * soda::sine(soda::kTwoPi * (0.3 + 0.1)));
  const double c = 0.2 * (30.0 - target) / 30.0;
  const double c_plus = 0.2 * (30.0 - plus_target) / 30.0;
  REQUIRE(!same(c * 30.0, c_plus * 30.0)); // the minus is visible
  const Stepped s = stepped(d);
  CHECK(same(s.state.vx[0], c * 30.0));
  CHECK(same(s.state.vx[1], 0.0 - c * 30.0));
  CHECK(same(s.state.vy[0], 0.0 + c * 0.0));
}

TEST_CASE("rule: links act in file order, each impulse added at once", "[physics_rules]") {
  // Mass 1 between two springs: its velocity is ((0 + i0) + i1) in file order.
  ModelDef d = quiet_world();
  d.nodes = {rule_mass(0.1, 50), rule_mass(30.3, 50.7), rule_mass(71.9, 49.3)};
  d.links = {rule_spring(0, 1, 20.0), rule_spring(1, 2, 33.3)};
  const Stepped s = stepped(d);
  const double dx0 = 30.3 - 0.1, dy0 = 50.7 - 50.0;
  const double l0 = std::sqrt(dx0 * dx0 + dy0 * dy0);
  const double c0 = 0.2 * (l0 - 20.0) / l0;
  const double dx1 = 71.9 - 30.3, dy1 = 49.3 - 50.7;
  const double l1 = std::sqrt(dx1 * dx1 + dy1 * dy1);
  const double c1 = 0.2 * (l1 - 33.3) / l1;
  CHECK(same(s.state.vx[1], (0.0 - c0 * dx0) + c1 * dx1));
  CHECK(same(s.state.vy[1], (0.0 - c0 * dy0) + c1 * dy1));
}

TEST_CASE("rule: a link of length 0 is skipped", "[physics_rules]") {
  ModelDef d = quiet_world();
  d.nodes = {rule_mass(20, 50, 0.5, 0.25), rule_mass(20, 50, -1.5, 0.0)};
  d.links = {rule_spring(0, 1, 10.0)};
  const Stepped s = stepped(d);
  CHECK(same(s.state.vx[0], 0.5));
  CHECK(same(s.state.vy[0], 0.25));
  CHECK(same(s.state.vx[1], -1.5));
  CHECK(same(s.state.x[1], 20.0 - 1.5));
}

TEST_CASE("rule: a fixed node is neither pushed nor moved", "[physics_rules]") {
  ModelDef d = quiet_world();
  d.environment.gravity = 0.3;
  d.nodes = {fixed_node(10, 50), rule_mass(10, 80)};
  d.links = {rule_spring(0, 1, 20.0)};
  Stepped s = stepped(d, 3);
  const int fixed = s.model.point_of_node[0];
  CHECK(same(s.state.x[fixed], 10.0));
  CHECK(same(s.state.y[fixed], 50.0));
  CHECK(same(s.state.vx[fixed], 0.0));
  CHECK(same(s.state.vy[fixed], 0.0));
  // The mass got the whole impulse of the first frame: c * dy, dy = 30, then gravity.
  s = stepped(d, 1);
  const double c = 0.2 * (30.0 - 20.0) / 30.0;
  CHECK(same(s.state.vy[s.model.point_of_node[1]], (0.0 - c * 30.0) - 0.3));
}

// --- 5.3: each mass in order: gravity, friction, rest test, move, container ----

TEST_CASE("rule: gravity changes vy by -g d, d = +1 down, -1 up, 0 off", "[physics_rules]") {
  ModelDef d = quiet_world();
  d.environment.gravity = 0.3;
  d.nodes = {rule_mass(100, 100, 0.0, 0.7)};
  d.settings.gravity_direction = GravityDirection::Down;
  CHECK(same(stepped(d).state.vy[0], 0.7 - 0.3));
  d.settings.gravity_direction = GravityDirection::Up;
  CHECK(same(stepped(d).state.vy[0], 0.7 + 0.3));
  d.settings.gravity_direction = GravityDirection::Off;
  CHECK(same(stepped(d).state.vy[0], 0.7));
}

TEST_CASE("rule: air friction keeps 1 - f, and gravity's kick is damped too", "[physics_rules]") {
  ModelDef d = quiet_world();
  d.environment.gravity = 0.3;
  d.environment.friction = 0.05;
  d.nodes = {rule_mass(100, 100, 2.5, 1.0)};
  const Stepped s = stepped(d);
  CHECK(same(s.state.vx[0], (1.0 - 0.05) * 2.5));
  CHECK(same(s.state.vy[0], (1.0 - 0.05) * (1.0 - 0.3)));
  CHECK(same(s.state.y[0], 100.0 + (1.0 - 0.05) * (1.0 - 0.3)));
}

TEST_CASE("rule: above 20 px/frame the syrup scales by 20/v, the quotient formed first", "[physics_rules]") {
  ModelDef d = quiet_world();
  d.environment.friction = 0.05;
  d.nodes = {rule_mass(500, 500, 30.0, 41.0)};
  const double v = std::sqrt(30.0 * 30.0 + 41.0 * 41.0);
  const double factor = (1.0 - 0.05) * (20.0 / v);
  REQUIRE(!same(factor * 30.0, ((1.0 - 0.05) * 20.0) / v * 30.0)); // the order shows here
  const Stepped s = stepped(d);
  CHECK(same(s.state.vx[0], factor * 30.0));
  CHECK(same(s.state.vy[0], factor * 41.0));
  CHECK(same(s.state.x[0], 500.0 + factor * 30.0));
  // At 20 px/frame exactly there is no syrup.
  d.nodes = {rule_mass(500, 500, 12.0, 16.0)};
  CHECK(same(stepped(d).state.vx[0], (1.0 - 0.05) * 12.0));
}

TEST_CASE("rule: a mass slower than 1e-5 in both components is not moved", "[physics_rules]") {
  ModelDef d = quiet_world();
  d.nodes = {rule_mass(100, 100, 9.9e-6, -9.9e-6), rule_mass(200, 100, 1e-5, 0.0)};
  const Stepped s = stepped(d);
  CHECK(same(s.state.x[0], 100.0));
  CHECK(same(s.state.y[0], 100.0));
  CHECK(same(s.state.vx[0], 9.9e-6)); // its velocity is kept
  CHECK(same(s.state.x[1], 200.0 + 1e-5)); // 1e-5 itself moves
}

TEST_CASE("rule: the floor and the ceiling clamp y and respond with Rs and Fs", "[physics_rules]") {
  ModelDef d = quiet_world();
  d.collisions.surface_friction = 0.1;
  d.collisions.surface_reflection = -0.75;
  d.nodes = {rule_mass(100, 1, 2.0, -3.0), rule_mass(100, 998, 2.0, 3.0)};
  const Stepped s = stepped(d);
  CHECK(same(s.state.y[0], 0.0));
  CHECK(same(s.state.x[0], 102.0)); // x keeps its full move
  CHECK(same(s.state.vy[0], -3.0 * -0.75));
  CHECK(same(s.state.vx[0], 2.0 * 0.1));
  CHECK(same(s.state.y[1], 1000.0));
  CHECK(same(s.state.vy[1], 3.0 * -0.75));
  CHECK(same(s.state.vx[1], 2.0 * 0.1));
}

TEST_CASE("rule: side walls clamp x and respond with Rs and Fs, except in a corner", "[physics_rules]") {
  ModelDef d = quiet_world();
  d.collisions.surface_friction = 0.1;
  d.collisions.surface_reflection = -0.75;
  d.nodes = {rule_mass(1, 100, -3.0, 2.0), rule_mass(999, 100, 3.0, 2.0), rule_mass(1, 1, -3.0, -2.0)};
  const Stepped s = stepped(d);
  CHECK(same(s.state.x[0], 0.0));
  CHECK(same(s.state.y[0], 102.0));
  CHECK(same(s.state.vx[0], -3.0 * -0.75));
  CHECK(same(s.state.vy[0], 2.0 * 0.1));
  CHECK(same(s.state.x[1], 1000.0));
  CHECK(same(s.state.vx[1], 3.0 * -0.75));
  // The corner: floor and left wall in one frame: x is only clamped, the floor responds.
  CHECK(same(s.state.x[2], 0.0));
  CHECK(same(s.state.y[2], 0.0));
  CHECK(same(s.state.vx[2], -3.0 * 0.1));
  CHECK(same(s.state.vy[2], -2.0 * -0.75));
}

TEST_CASE("rule: autoreverse toggles the wave once per new side wall", "[physics_rules]") {
  ModelDef d = quiet_world();
  d.settings.autoreverse = true;
  d.wave.speed = 0.01;
  d.collisions.surface_reflection = 0.0; // masses stay against the wall
  // Two masses hit the right wall in the same frame: one toggle.
  d.nodes = {rule_mass(999, 100, 3.0, 0.0), rule_mass(998, 200, 5.0, 0.0)};
  Stepped s = stepped(d);
  CHECK(s.state.wave_mode == WaveDirection::Reverse);
  CHECK(s.state.last_side_wall == soda::SideWall::Right);
  CHECK(same(s.state.wave_phase, (0.0 + 0.01 * -1.0) + 1.0)); // the wave moves after the toggle
  // Hitting the same wall again: nothing.
  d.nodes = {rule_mass(999, 100, 3.0, 0.0), rule_mass(500, 200, 0.0, 0.0)};
  s = stepped(d);
  CHECK(s.state.wave_mode == WaveDirection::Reverse);
  s.state.vx[0] = 4.0;
  soda::step(s.model, s.state);
  CHECK(s.state.wave_mode == WaveDirection::Reverse);
  // The other wall: toggles back.
  s.state.x[1] = 1.0;
  s.state.vx[1] = -2.0;
  soda::step(s.model, s.state);
  CHECK(s.state.wave_mode == WaveDirection::Forward);
  CHECK(s.state.last_side_wall == soda::SideWall::Left);
  // A manual wave, or autoreverse off: no toggle.
  d.settings.wave_direction = WaveDirection::Manual;
  CHECK(stepped(d).state.wave_mode == WaveDirection::Manual);
  d.settings.wave_direction = WaveDirection::Forward;
  d.settings.autoreverse = false;
  CHECK(stepped(d).state.wave_mode == WaveDirection::Forward);
}
