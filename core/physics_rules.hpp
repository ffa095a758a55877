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

#include "constants.hpp"
#include "model.hpp"

namespace soda::rules {

/// Desired length of a muscle (spec 5.2): rest * (1 + (Aw*Am) * sin(2pi*(phi_m - phi_w))).
/// Note the minus: a forward-running wave runs each muscle's own phase backward.
inline double muscle_target_length(double rest, double wave_amplitude, double muscle_amplitude,
                                   double muscle_phase, double wave_phase) {
  const double power = (wave_amplitude * muscle_amplitude) * std::sin(kTwoPi * (muscle_phase - wave_phase));
  return rest * (1.0 + power);
}

/// Velocity impulse factor of a link of current length L > 0 and desired length D:
/// c = k*(L - D)/L; end A gets +c*(dx, dy), end B gets -c*(dx, dy), (dx, dy) = B - A.
inline double link_impulse_factor(double springyness, double length, double target) {
  return springyness * (length - target) / length;
}

/// Gravity (spec 5.3 step 1): vy -= g*d, y up, d = +1 down, -1 up, 0 off.
inline double apply_gravity(double vy, double gravity, GravityDirection direction) {
  return vy - gravity * static_cast<double>(static_cast<int>(direction));
}

/// Air friction with the "syrup" speed limit (spec 5.3 step 2): the velocity is
/// scaled by (1 - f), and additionally by 20/|v| when |v| > 20. The quotient is
/// formed first, then the product: the other order breaks bit-exactness.
inline double friction_factor(double vx, double vy, double friction) {
  const double speed = std::sqrt(vx * vx + vy * vy);
  double factor = 1.0 - friction;
  if (speed > kSyrupThreshold) factor = factor * (kSyrupThreshold / speed);
  return factor;
}

/// Rest test (spec 5.3 step 3): such a mass is neither moved nor collided.
inline bool is_at_rest(double vx, double vy) {
  return std::fabs(vx) < kZeroVelocity && std::fabs(vy) < kZeroVelocity;
}

/// Container collision after the move (spec 5.3 step 5). Floor/ceiling clamp y and
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

/// Autoreverse (spec 5.3 step 5): hitting a side wall other than the last one hit
/// records it and toggles the wave direction; repeated hits of the same wall do
/// nothing. Only when autoreverse is on and the wave is not manual.
inline void autoreverse_on_wall_hit(SideWall hit, bool autoreverse, WaveDirection& mode,
                                    SideWall& last_side_wall) {
  if (hit == SideWall::None || !autoreverse || mode == WaveDirection::Manual) return;
  if (hit == last_side_wall) return;
  last_side_wall = hit;
  mode = (mode == WaveDirection::Forward) ? WaveDirection::Reverse : WaveDirection::Forward;
}

/// Wave advance after the physics (spec 5.1): phase += speed*mode, wrapped into [0, 1).
inline double advance_wave_phase(double phase, double speed, WaveDirection mode) {
  if (mode == WaveDirection::Manual) return phase;
  const double moved = phase + speed * static_cast<double>(static_cast<int>(mode));
  return wrap_phase(moved);
}

/// Fixed-bar response (spec 5.4, verified for a single bar crossing): the move from
/// p0 crosses the bar at fraction t of the move; u is the unit vector along the bar
/// and n its unit normal. The mass is placed at the crossing point plus
/// (1 - t)*Fs*vt*u (it slides along the bar for the rest of the frame) and its new
/// velocity is Fs*vt*u + Rs*vn*n, with vt = v.u and vn = v.n.
struct BarResponse {
  double x, y, vx, vy;
};
inline BarResponse respond_to_bar(double cross_x, double cross_y, double t, double vx, double vy,
                                  double ux, double uy, double surface_friction,
                                  double surface_reflection) {
  const double nx = -uy;
  const double ny = ux;
  const double vt = vx * ux + vy * uy;
  const double vn = vx * nx + vy * ny;
  const double slide = (1.0 - t) * surface_friction * vt;
  return {cross_x + slide * ux, cross_y + slide * uy,
          surface_friction * vt * ux + surface_reflection * vn * nx,
          surface_friction * vt * uy + surface_reflection * vn * ny};
}

} // namespace soda::rules
