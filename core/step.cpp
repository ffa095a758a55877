#include "step.hpp"

#include <cmath>

#include "physics_rules.hpp"

namespace soda {

namespace {

/// Part 1 (spec 5.2): springs and muscles in file order, each adding its impulse to
/// the velocities at once. Links read only positions, which do not change in this
/// part, so the file order matters only as the order of the additions into each
/// mass's velocity (which is what bit-exactness needs).
[[gnu::always_inline]] inline void apply_links(const Model& m, State& s, double dt) {
  const int n = m.link_count();
  for (int i = 0; i < n; ++i) {
    const int a = m.link_a[i];
    const int b = m.link_b[i];
    const double dx = s.x[b] - s.x[a];
    const double dy = s.y[b] - s.y[a];
    const double length = std::sqrt(dx * dx + dy * dy);
    if (length == 0.0) continue; // coincident ends: no direction, no force
    const double target = rules::link_target_length(m, i, s.wave_phase);
    const double c = rules::link_impulse_factor(m.springyness, length, target) * dt;
    if (m.is_mass(a)) {
      s.vx[a] += c * dx;
      s.vy[a] += c * dy;
    }
    if (m.is_mass(b)) {
      s.vx[b] -= c * dx;
      s.vy[b] -= c * dy;
    }
  }
}

/// Part 2 (spec 5.3): the masses in order.
[[gnu::always_inline]] inline void move_masses(const Model& m, State& s, EulerStep e) {
  for (int i = 0; i < m.mass_count; ++i) {
    double vx = s.vx[i];
    double vy = rules::apply_gravity(s.vy[i], e.gravity, m.gravity_direction);
    const double factor = rules::friction_factor_kept(vx, vy, e.keep);
    vx = factor * vx;
    vy = factor * vy;
    if (rules::is_at_rest(vx, vy)) {
      s.vx[i] = vx;
      s.vy[i] = vy;
      continue;
    }
    const double x0 = s.x[i];
    const double y0 = s.y[i];
    double x = x0 + vx * e.dt;
    double y = y0 + vy * e.dt;
    const SideWall hit =
        rules::collide_with_container(x, y, vx, vy, m.width, m.height, e.surface_friction, m.surface_reflection);
    rules::complete_move(m, s, i, hit, e.dt, e.surface_friction, x0, y0, x, y, vx, vy);
  }
}

// Inlined into step() too, where dt = 1 is a constant and its products fold away:
// the reference step costs no more than before it served both.
[[gnu::always_inline]] inline void euler_step_inline(const Model& m, State& s, EulerStep e) {
  apply_links(m, s, e.dt);
  move_masses(m, s, e);
  s.wave_phase = rules::advance_wave_phase(s.wave_phase, e.wave_step, s.wave_mode);
}

} // namespace

void euler_step(const Model& model, State& state, const EulerStep& e) { euler_step_inline(model, state, e); }

namespace {
void step_unchecked(const Model& model, State& state) {
  euler_step_inline(model, state,
                    {1.0, model.gravity, 1.0 - model.friction, model.surface_friction, model.wave_speed});
  ++state.frame;
}
} // namespace

void step(const Model& model, State& state) {
  require_state_size(state, model.point_count, "soda::step");
  step_unchecked(model, state);
}

void run(const Model& model, State& state, long long frames) {
  require_state_size(state, model.point_count, "soda::run");
  for (long long f = 0; f < frames; ++f) step_unchecked(model, state);
}

} // namespace soda
