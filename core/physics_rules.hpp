// The update rules of the SodaConstructor engine, one function per rule.
//
// This file is the one place where the physics is written down (spec section 5,
// verified against the original 2003 engine). Every stepper (the reference step,
// and any faster one) calls these functions, so a rule cannot differ between them.
// The operation order inside each function is part of the rule: the original
// computes in double, and reproducing it bit for bit needs the same order (spec
// 5.7) and no fused multiply-add (the build sets -ffp-contract=off).
#pragma once

#include <cmath>
#include <limits>

#include "constants.hpp"
#include "model.hpp"
#include "sine.hpp"
#include "sine_jitter.hpp"

namespace soda::rules {

/// A muscle's sine (docs/physics.md, Part 1: links): sin(2pi*(phi_m - phi_w)), by the engine's own sine
/// (sine.hpp), never the C library's, then moved by the replica's jitter
/// (sine_jitter.hpp; none for seed 0) as a pure function of the argument's bits.
inline double muscle_sine(double muscle_phase, double wave_phase, const SineJitter& jitter) {
  const double argument = kTwoPi * (muscle_phase - wave_phase);
  const double s = sine(argument);
  return jitter.seed == 0 ? s : jittered(s, argument, jitter);
}

/// Desired length of a muscle (docs/physics.md, Part 1: links):
/// rest * (1 + (Aw*Am) * sin(2pi*(phi_m - phi_w))).
/// Note the minus: a forward-running wave runs each muscle's own phase backward.
inline double muscle_target_length(double rest, double wave_amplitude, double muscle_amplitude,
                                   double muscle_phase, double wave_phase, const SineJitter& jitter) {
  const double power = (wave_amplitude * muscle_amplitude) * muscle_sine(muscle_phase, wave_phase, jitter);
  return rest * (1.0 + power);
}

/// Desired length of link i of a model at wave phase `wave_phase`: its rest length,
/// or for a muscle muscle_target_length.
inline double link_target_length(const Model& m, int i, double wave_phase, const SineJitter& jitter) {
  return m.link_muscle[i] ? muscle_target_length(m.link_rest[i], m.wave_amplitude, m.link_amplitude[i],
                                                 m.link_phase[i], wave_phase, jitter)
                          : m.link_rest[i];
}

/// Velocity impulse factor of a link of current length L > 0 and desired length D:
/// c = k*(L - D)/L; end A gets +c*(dx, dy), end B gets -c*(dx, dy), (dx, dy) = B - A.
inline double link_impulse_factor(double springyness, double length, double target) {
  return springyness * (length - target) / length;
}

/// Muscle power Aw*Am (docs/physics.md, Part 1: links), the product muscle_target_length forms. 0 makes a
/// muscle a spring: its target is rest*(1 + (+-0)) = rest whatever the sine.
inline double muscle_power(double wave_amplitude, double muscle_amplitude) {
  return wave_amplitude * muscle_amplitude;
}

/// Gravity's velocity step g*d (docs/physics.md, Part 2 step 1), y up, d = +1 down, -1 up, 0 off.
/// g = 0 with gravity up gives -0, which is not an identity (-0 - (-0) = +0).
inline double gravity_step(double gravity, GravityDirection direction) {
  return gravity * static_cast<double>(static_cast<int>(direction));
}

/// The share of velocity air friction leaves per frame (docs/physics.md, Part 2 step 2), 1 - f.
inline double air_keep(double friction) { return 1.0 - friction; }

/// Gravity (docs/physics.md, Part 2 step 1): vy -= g*d, with `step` = gravity_step(g, d)
/// (Model::gravity_step).
inline double apply_gravity(double vy, double step) { return vy - step; }

/// The same from g and d.
inline double apply_gravity(double vy, double gravity, GravityDirection direction) {
  return apply_gravity(vy, gravity_step(gravity, direction));
}

/// Air friction with the "syrup" speed limit (docs/physics.md, Part 2 step 2): the velocity is
/// scaled by `keep`, and additionally by 20/|v| when |v| > 20. The quotient is
/// formed first, then the product: the other order breaks bit-exactness. In the
/// original `keep` = 1 - f; the `continuous` mode passes the per-step (1 - f)^dt
/// (the syrup limit stays 20 px/frame whatever dt: it is a speed, not a rate).
inline double friction_factor_kept(double vx, double vy, double keep) {
  const double speed = std::sqrt(vx * vx + vy * vy);
  double factor = keep;
  if (speed > kSyrupThreshold) factor = factor * (kSyrupThreshold / speed);
  return factor;
}

/// The original's air friction: friction_factor_kept with keep = air_keep(f).
inline double friction_factor(double vx, double vy, double friction) {
  return friction_factor_kept(vx, vy, air_keep(friction));
}

/// Syrup limit alone (continuous mode, Verlet and RK4, where air friction is part
/// of the smooth force): the factor that brings a speed above 20 px/frame back to 20.
inline double syrup_factor(double vx, double vy) {
  const double speed = std::sqrt(vx * vx + vy * vy);
  return speed > kSyrupThreshold ? kSyrupThreshold / speed : 1.0;
}

/// Rest test (docs/physics.md, Part 2 step 3): such a mass is neither moved nor collided.
inline bool is_at_rest(double vx, double vy) {
  return std::fabs(vx) < kZeroVelocity && std::fabs(vy) < kZeroVelocity;
}

/// Container collision after the move (docs/physics.md, Part 2 step 5). Floor/ceiling clamp y and
/// respond with vy *= Rs, vx *= Fs (x keeps its full move). Side walls clamp x;
/// their response vx *= Rs, vy *= Fs happens only when the same mass did not also
/// hit the floor or ceiling this frame (corner rule). Returns the side wall that
/// responded (for autoreverse), or None.
inline SideWall collide_with_container(double& x, double& y, double& vx, double& vy, double width,
                                       double height, double surface_friction,
                                       double surface_reflection) {
  bool hit_floor_or_ceiling = false;
  if (y < 0.0) {
    y = 0.0;
    hit_floor_or_ceiling = true;
  } else if (y > height) {
    y = height;
    hit_floor_or_ceiling = true;
  }
  if (hit_floor_or_ceiling) {
    vy = vy * surface_reflection;
    vx = vx * surface_friction;
  }
  SideWall side = SideWall::None;
  if (x < 0.0) {
    x = 0.0;
    side = SideWall::Left;
  } else if (x > width) {
    x = width;
    side = SideWall::Right;
  }
  if (side == SideWall::None || hit_floor_or_ceiling) return SideWall::None;
  vx = vx * surface_reflection;
  vy = vy * surface_friction;
  return side;
}

/// The numbers the mass rules (docs/physics.md, Part 2) take for one mass: its model's for the
/// original's frame (frame_constants), or per step of dt frames in the `continuous`
/// mode's Euler (step.hpp EulerStep).
struct MassConstants {
  double gravity_step;       ///< g*d (gravity_step), per step
  double keep;               ///< share of velocity air friction leaves per step (air_keep)
  double dt;                 ///< frames per step (1 in the original)
  double width, height;      ///< container
  double surface_friction;   ///< Fs, per step
  double surface_reflection; ///< Rs
};

/// The original's frame for model `m`: its derived constants (Model::gravity_step,
/// Model::air_keep; set_constants) and dt = 1.
inline MassConstants frame_constants(const Model& m) {
  return {m.gravity_step, m.air_keep, 1.0, m.width, m.height, m.surface_friction, m.surface_reflection};
}

/// What move_mass did.
struct MassStepResult {
  bool moved = false;            ///< false: at rest (is_at_rest), neither moved nor collided
  SideWall hit = SideWall::None; ///< the side wall that responded (for autoreverse)
  MassMove move;                 ///< start, end before the container, velocity then (fixed bars)
};

/// One free mass after its link impulses (docs/physics.md, Part 2): gravity, air friction with the
/// syrup limit, the rest test, the move by v*dt and the container, in the
/// original's order; (x, y, vx, vy) are updated. The caller then does autoreverse on
/// `hit` and the fixed bars (complete_move). Every stepper's scalar mass update is
/// this function (step.cpp, the fused scenes' ordered masses);
/// simd_rules::move_mass is its twin for W masses at once.
[[gnu::always_inline]] inline MassStepResult move_mass(const MassConstants& c, double& x, double& y, double& vx,
                                                       double& vy) {
  MassStepResult r;
  vy = apply_gravity(vy, c.gravity_step);
  const double factor = friction_factor_kept(vx, vy, c.keep);
  vx = factor * vx;
  vy = factor * vy;
  if (is_at_rest(vx, vy)) return r;
  r.moved = true;
  const double x0 = x, y0 = y;
  x = x0 + vx * c.dt;
  y = y0 + vy * c.dt;
  r.move = {x0, y0, x, y, x, y, vx, vy};
  r.hit = collide_with_container(x, y, vx, vy, c.width, c.height, c.surface_friction, c.surface_reflection);
  return r;
}

/// Continuous mode, Verlet and RK4 only (not in the original): surface friction is
/// a rate, Fs per frame of contact, so it must act in every step a mass spends on a
/// surface. Under one-kick Euler a resting mass crosses the floor every step (the
/// full gravity kick beats the reflected velocity), but a split-kick integrator
/// lets it leave the floor by a hair every other step (the reflected 0.75*g*dt
/// outweighs half a kick), and the crossing test alone would then apply the
/// friction only half the time (a sliding mass would slide twice as far). So a mass
/// that starts the step on the floor or ceiling (side wall) and does not cross it
/// also keeps only `keep` = Fs^dt of its tangential velocity.
inline void friction_while_touching(bool started_on_floor_or_ceiling, bool started_on_side_wall,
                                    bool crossed_floor_or_ceiling, bool crossed_side_wall, double& vx, double& vy,
                                    double keep) {
  if (started_on_floor_or_ceiling && !crossed_floor_or_ceiling) vx = vx * keep;
  if (started_on_side_wall && !crossed_side_wall && !crossed_floor_or_ceiling) vy = vy * keep;
}

/// Autoreverse (docs/physics.md, Part 2 step 6): hitting a side wall other than the last one hit
/// records it and toggles the wave direction; repeated hits of the same wall do
/// nothing. Only when autoreverse is on and the wave is not manual.
inline void autoreverse_on_wall_hit(SideWall hit, bool autoreverse, WaveDirection& mode,
                                    SideWall& last_side_wall) {
  if (hit == SideWall::None || !autoreverse || mode == WaveDirection::Manual) return;
  if (hit == last_side_wall) return;
  last_side_wall = hit;
  mode = (mode == WaveDirection::Forward) ? WaveDirection::Reverse : WaveDirection::Forward;
}

/// The wave's wrap after a move (docs/physics.md, "The wave"): Java's `moved % 1.0` (fmod: exact, the
/// sign of the dividend), plus 1 when negative. The result lies in [0, 1] and 1.0
/// is kept: a reverse-running phase that lands on -3.1e-17 becomes 1 - 3.1e-17,
/// which rounds to 1.0, and the next sines are those of phase 1.0, not 0.0 (golden
/// wave_wrap/). Not the loader's wrap_phase, which maps 1.0 to 0. Inline, with the
/// usual one-cycle moves found by comparisons (std::fmod is a library call); the
/// same bits as fmod: moved - 1 is exact on [1, 2) (Sterbenz).
inline double wrap_moved_wave_phase(double moved) {
  if (moved >= 0.0 && moved < 1.0) return moved; // -0.0 stays -0.0, as fmod keeps it
  if (moved >= 1.0 && moved < 2.0) return moved - 1.0;
  if (moved > -1.0 && moved < 0.0) return moved + 1.0;
  const double r = std::fmod(moved, 1.0);
  return r < 0.0 ? r + 1.0 : r;
}

/// Wave advance after the physics (docs/physics.md, "The wave"): phase += speed*mode, then the wrap above.
inline double advance_wave_phase(double phase, double speed, WaveDirection mode) {
  if (mode == WaveDirection::Manual) return phase;
  const double moved = phase + speed * static_cast<double>(static_cast<int>(mode));
  return wrap_moved_wave_phase(moved);
}

/// The end of a mass's move (docs/physics.md, Part 2 steps 6-7), after the container: autoreverse
/// on the side wall `hit`, the new position and velocity stored, then the fixed bars
/// (fixed_bars.hpp) test the move `move` (its start, its end before the clamp and the
/// velocity before the container's response; (x, y) is the clamped end). A bar hit
/// replaces the container's velocity response; the autoreverse test stays.
/// The fixed bars' rules for mass `p` after its move: `move` has its start, its end
/// before the container and its velocity before the container's response; (x, y)
/// and (vx, vy) are where the container left the mass. A bar's hit replaces them
/// (collide_with_fixed_bars); returns whether one did. Every stepper's bar step is
/// this function (complete_move, the fused scenes' bar pass, the lockstep lanes').
inline bool apply_fixed_bars(const FixedBars& bars, BarMemory& memory, int p, const MassMove& move,
                             const Surface& surface, double& x, double& y, double& vx, double& vy) {
  MassMove clamped = move;
  clamped.x = x;
  clamped.y = y;
  MassEnd end;
  if (!collide_with_fixed_bars(bars, memory, p, clamped, surface, end)) return false;
  x = end.x;
  y = end.y;
  vx = end.vx;
  vy = end.vy;
  return true;
}

inline void complete_move(const Model& m, State& s, int i, SideWall hit, double surface_friction,
                          const MassMove& move, double x, double y, double vx, double vy) {
  autoreverse_on_wall_hit(hit, m.autoreverse, s.wave_mode, s.last_side_wall);
  s.x[i] = x;
  s.y[i] = y;
  s.vx[i] = vx;
  s.vy[i] = vy;
  if (m.fixed_bars.empty()) return;
  const Surface surface{surface_friction, m.surface_reflection, m.width, m.height};
  apply_fixed_bars(m.fixed_bars, s.bar_memory, i, move, surface, s.x[i], s.y[i], s.vx[i], s.vy[i]);
}

/// The move of a mass from (x0, y0) to (x, y) with velocity (vx, vy), before the container.
inline MassMove mass_move(double x0, double y0, double x, double y, double vx, double vy) {
  return {x0, y0, x, y, x, y, vx, vy};
}

} // namespace soda::rules
