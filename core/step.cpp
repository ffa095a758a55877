#include "step.hpp"
#include "core/cancellation.hpp"

#include <cassert>
#include <cmath>

#include "physics_rules.hpp"

namespace soda {

namespace {

/// Part 1 (docs/physics.md, part 1): springs and muscles in file order, each adding its impulse
/// to the velocities at once. Links read only positions, which do not change in this part, so
/// the file order matters only as the order of the additions into each mass's velocity (which
/// is what bit-exactness needs).
[[gnu::always_inline]] inline void apply_links(const Model& m, State& s, double dt) {
  const int n = m.link_count();
  for (int i = 0; i < n; ++i) {
    const int a = m.link_a[i];
    const int b = m.link_b[i];
    const double dx = s.x[b] - s.x[a];
    const double dy = s.y[b] - s.y[a];
    const double length = std::sqrt(dx * dx + dy * dy);
    if (length == 0.0) continue; // coincident ends: no direction, no force
    const double target = rules::link_target_length(m, i, s.wave_phase, s.jitter);
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

/// Part 2 (docs/physics.md, part 2): the masses in order, each by rules::move_mass, then
/// autoreverse and the fixed bars (rules::complete_move).
[[gnu::always_inline]] inline void move_masses(const Model& m, State& s, const rules::MassConstants& k) {
  for (int i = 0; i < m.mass_count; ++i) {
    double x = s.x[i], y = s.y[i], vx = s.vx[i], vy = s.vy[i];
    const rules::MassStepResult r = rules::move_mass(k, x, y, vx, vy);
    if (!r.moved) {
      s.vx[i] = vx;
      s.vy[i] = vy;
      continue;
    }
    rules::complete_move(m, s, i, r.hit, k.surface_friction, r.move, x, y, vx, vy);
  }
}

// Inlined into step() too, where dt = 1 is a constant and its products fold away:
// the reference step costs no more than before it served both.
[[gnu::always_inline]] inline void euler_step_inline(const Model& m, State& s, const rules::MassConstants& k,
                                                     double wave_step) {
  apply_links(m, s, k.dt);
  move_masses(m, s, k);
  s.wave_phase = rules::advance_wave_phase(s.wave_phase, wave_step, s.wave_mode);
}

} // namespace

void euler_step(const Model& model, State& state, const EulerStep& e) {
  const rules::MassConstants k{rules::gravity_step(e.gravity, model.gravity_direction),
                               e.keep,
                               e.dt,
                               model.width,
                               model.height,
                               e.surface_friction,
                               model.surface_reflection};
  euler_step_inline(model, state, k, e.wave_step);
}

namespace {
void step_unchecked(const Model& model, State& state) {
  euler_step_inline(model, state, rules::frame_constants(model), model.wave_speed);
  ++state.frame;
}
} // namespace

void step(const Model& model, State& state) {
  require_state_size(state, model.point_count, "soda::step");
  step_unchecked(model, state);
}

void run(const Model& model, State& state, long long frames) {
  require_state_size(state, model.point_count, "soda::run");
  assert(constants_current(model));
  for (long long f = 0; f < frames; ++f) {
    if (f % kCancellationFrames == kCancellationFrames - 1) check_cancellation();
    step_unchecked(model, state);
  }
}

} // namespace soda
