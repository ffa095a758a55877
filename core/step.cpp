#include "step.hpp"

#include <cmath>
#include <limits>

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

double cross(double ax, double ay, double bx, double by) { return ax * by - ay * bx; }

/// Fixed bars (spec 5.4): the first bar (smallest t) crossed by the move from
/// (x0, y0) to the mass's new position responds. Not mapped from the original (it
/// was not studied): chains of bars, corners and bar ends, several crossings in
/// one frame. So that a mass left on a bar is not let through on the next frame,
/// it is kept strictly on the side it came from (the crossing is detected as a
/// strict change of side).
void collide_with_bars(const Model& m, State& s, int i, double x0, double y0) {
  const double mx = s.x[i] - x0;
  const double my = s.y[i] - y0;
  int best = -1;
  double best_t = std::numeric_limits<double>::infinity();
  double best_side0 = 0.0;
  for (int bar = 0; bar < m.bar_count(); ++bar) {
    const int pa = m.bar_a[bar];
    const int pb = m.bar_b[bar];
    if (pa == i || pb == i) continue; // a bar does not stop its own end
    const double px = s.x[pa], py = s.y[pa];
    const double sx = s.x[pb] - px, sy = s.y[pb] - py;
    const double side0 = cross(sx, sy, x0 - px, y0 - py);
    const double side1 = cross(sx, sy, s.x[i] - px, s.y[i] - py);
    if (!((side0 > 0.0 && side1 < 0.0) || (side0 < 0.0 && side1 > 0.0))) continue;
    const double denom = cross(mx, my, sx, sy);
    if (denom == 0.0) continue;
    const double t = cross(px - x0, py - y0, sx, sy) / denom;
    const double along = cross(px - x0, py - y0, mx, my) / denom;
    if (along < 0.0 || along > 1.0 || !(t > 0.0 && t <= 1.0)) continue;
    if (t < best_t) {
      best = bar;
      best_t = t;
      best_side0 = side0;
    }
  }
  if (best < 0) return;
  const int pa = m.bar_a[best];
  const int pb = m.bar_b[best];
  const double sx = s.x[pb] - s.x[pa], sy = s.y[pb] - s.y[pa];
  const double bar_length = std::sqrt(sx * sx + sy * sy);
  const double ux = sx / bar_length, uy = sy / bar_length;
  const rules::BarResponse r =
      rules::respond_to_bar(x0 + best_t * mx, y0 + best_t * my, best_t, s.vx[i], s.vy[i], ux, uy,
                            m.surface_friction, m.surface_reflection);
  double nx = r.x, ny = r.y;
  // Keep the mass strictly on its original side (rounding may put it on the bar).
  for (int tries = 0; tries < 64; ++tries) {
    const double side = cross(sx, sy, nx - s.x[pa], ny - s.y[pa]);
    if ((side > 0.0) == (best_side0 > 0.0) && side != 0.0) break;
    const double push = (best_side0 > 0.0 ? 1.0 : -1.0) * std::ldexp(1.0, tries - 52) *
                        (1.0 + std::fabs(nx) + std::fabs(ny));
    nx += -uy * push;
    ny += ux * push;
  }
  s.x[i] = nx;
  s.y[i] = ny;
  s.vx[i] = r.vx;
  s.vy[i] = r.vy;
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
    if (m.bar_count() > 0) collide_with_bars(m, s, i, x0, y0);
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
