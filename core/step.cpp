#include "step.hpp"

#include <cmath>

#include "physics_rules.hpp"

namespace soda {

namespace {

/// Part 1 (spec 5.2): springs and muscles in file order, each adding its impulse to
/// the velocities at once. Links read only positions, which do not change in this
/// part, so the file order matters only as the order of the additions into each
/// mass's velocity (which is what bit-exactness needs).
void apply_links(const Model& m, State& s) {
  const int n = m.link_count();
  for (int i = 0; i < n; ++i) {
    const int a = m.link_a[i];
    const int b = m.link_b[i];
    const double dx = s.x[b] - s.x[a];
    const double dy = s.y[b] - s.y[a];
    const double length = std::sqrt(dx * dx + dy * dy);
    if (length == 0.0) continue; // coincident ends: no direction, no force
    const double target =
        m.link_muscle[i] ? rules::muscle_target_length(m.link_rest[i], m.wave_amplitude, m.link_amplitude[i],
                                                       m.link_phase[i], s.wave_phase)
                         : m.link_rest[i];
    const double c = rules::link_impulse_factor(m.springyness, length, target);
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
void move_masses(const Model& m, State& s) {
  for (int i = 0; i < m.mass_count; ++i) {
    double vx = s.vx[i];
    double vy = rules::apply_gravity(s.vy[i], m.gravity, m.gravity_direction);
    const double factor = rules::friction_factor(vx, vy, m.friction);
    vx = factor * vx;
    vy = factor * vy;
    if (rules::is_at_rest(vx, vy)) {
      s.vx[i] = vx;
      s.vy[i] = vy;
      continue;
    }
    const double x0 = s.x[i];
    const double y0 = s.y[i];
    double x = x0 + vx;
    double y = y0 + vy;
    const SideWall hit = rules::collide_with_container(x, y, vx, vy, m.width, m.height,
                                                       m.surface_friction, m.surface_reflection);
    rules::autoreverse_on_wall_hit(hit, m.autoreverse, s.wave_mode, s.last_side_wall);
    s.x[i] = x;
    s.y[i] = y;
    s.vx[i] = vx;
    s.vy[i] = vy;
    if (m.bar_count() > 0) {
      rules::collide_with_bars(s.x.data(), s.y.data(), m.bar_a.data(), m.bar_b.data(), m.bar_count(), i, x0, y0,
                               s.x[i], s.y[i], s.vx[i], s.vy[i], m.surface_friction, m.surface_reflection);
    }
  }
}

} // namespace

void step(const Model& model, State& state) {
  apply_links(model, state);
  move_masses(model, state);
  state.wave_phase = rules::advance_wave_phase(state.wave_phase, model.wave_speed, state.wave_mode);
  ++state.frame;
}

void run(const Model& model, State& state, long long frames) {
  for (long long f = 0; f < frames; ++f) step(model, state);
}

} // namespace soda
