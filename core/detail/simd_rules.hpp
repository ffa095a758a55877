// The update rules of physics_rules.hpp for W lanes at once (SIMD).
//
// The SIMD steppers (core/fused/kernels.hpp, lockstep_batch.cpp) run the rules on W masses,
// links or creatures at a time. Each function here is one rule of physics_rules.hpp
// with the same operations in the same order per lane, so every lane gets the bits
// the scalar rule gives; the comment on each names the rule. Branches of the scalar
// rules become masks and selects; where a select would sit on the position's chain
// from frame to frame, a min or max gives the same bits at less latency.
//
// Include only where the instruction set of O is enabled (#pragma GCC target), as
// simd_ops.hpp's users do.
#pragma once

#include "core/constants.hpp"
#include "simd_ops.hpp"

namespace soda::simd_rules {

// Templates returning vectors outside a target region: always inlined into code
// compiled for their instruction set, so no call passes a vector (no ABI change).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

/// Length of (dx, dy) as apply_links forms it: sqrt(dx*dx + dy*dy).
template <class O>
[[gnu::always_inline]] inline typename O::V length(typename O::V dx, typename O::V dy) {
  return O::sqrt(O::add(O::mul(dx, dx), O::mul(dy, dy)));
}

/// rules::link_impulse_factor: springyness * (length - target) / length.
template <class O>
[[gnu::always_inline]] inline typename O::V impulse_factor(typename O::V springyness, typename O::V length,
                                                           typename O::V target) {
  return O::div(O::mul(springyness, O::sub(length, target)), length);
}

/// The sine's argument in rules::muscle_target_length: 2pi * (muscle phase - wave
/// phase).
template <class O>
[[gnu::always_inline]] inline typename O::V sine_argument(typename O::V muscle_phase, typename O::V wave_phase) {
  return O::mul(O::set1(kTwoPi), O::sub(muscle_phase, wave_phase));
}

/// The second half of rules::muscle_target_length: rest * (1 + power * sine), with
/// power = Aw*Am formed beforehand (the same product every frame). A spring in a
/// muscle's lane has power 0: rest * (1 + (+-0)) = rest exactly.
template <class O>
[[gnu::always_inline]] inline typename O::V muscle_target(typename O::V rest, typename O::V power,
                                                          typename O::V sine) {
  return O::mul(rest, O::add(O::set1(1.0), O::mul(power, sine)));
}

/// The per-lane constants of the mass rules (each lane's own creature's).
template <class O>
struct MassParams {
  typename O::V gravity_step; ///< gravity * direction, as rules::apply_gravity forms it
  typename O::V keep;         ///< 1 - friction, as rules::friction_factor forms it
  typename O::V width, height, surface_friction, surface_reflection;
};

/// Where side walls responded this frame (rules::collide_with_container's result),
/// for autoreverse.
template <class O>
struct SideHits {
  typename O::M hit;  ///< lanes whose side wall responded (moving, not in a corner)
  typename O::M left; ///< of those and others: the left wall was crossed
};

/// One mass per lane after its impulses (docs/physics.md, part 2; step.cpp move_masses):
/// rules::apply_gravity, rules::friction_factor, rules::is_at_rest, the move, and
/// rules::collide_with_container, without the walls the caller knows no lane can
/// reach (Floor, Ceiling, Sides false) and without gravity when every lane's is +0
/// (Gravity false: vy - (+0) = vy). Autoreverse is left to the caller (lanes
/// `hit`, in mass order). `move_v`, if given, gets the velocity the move takes (after
/// friction, before the container's response: what the fixed bars need).
template <class O, bool Gravity, bool Floor, bool Ceiling, bool Sides>
[[gnu::always_inline]] inline SideHits<O> move_mass(const MassParams<O>& p, typename O::V& x, typename O::V& y,
                                                    typename O::V& vx, typename O::V& vy,
                                                    typename O::V* move_v = nullptr) {
  using V = typename O::V;
  using M = typename O::M;
  const V syrup = O::set1(kSyrupThreshold);
  const V syrup2 = O::set1(kSyrupThreshold * kSyrupThreshold); // 400, exact
  const V rest_limit = O::set1(kZeroVelocity);
  const V zero = O::set1(0.0);
  const V x0 = x, y0 = y;
  if constexpr (Gravity) vy = O::sub(vy, p.gravity_step); // rules::apply_gravity
  // rules::friction_factor: (1 - f), times (20 / speed) when speed > 20.
  // The square-root/divide unit is the bottleneck of the whole step, so both are
  // skipped when no lane can be above the limit: sqrt is correctly rounded and
  // monotonic with sqrt(400) = 20, so vx^2 + vy^2 <= 400 gives speed <= 20
  // exactly. The other lanes keep 1 - f either way.
  const V speed2 = O::add(O::mul(vx, vx), O::mul(vy, vy));
  V factor = p.keep;
  if (O::any(O::gt(speed2, syrup2))) {
    const V speed = O::sqrt(speed2);
    factor = O::select(O::gt(speed, syrup), O::mul(p.keep, O::div(syrup, speed)), p.keep);
  }
  vx = O::mul(factor, vx);
  vy = O::mul(factor, vy);
  if (move_v != nullptr) {
    move_v[0] = vx;
    move_v[1] = vy;
  }
  // rules::is_at_rest
  const M rest = O::m_and(O::lt(O::abs(vx), rest_limit), O::lt(O::abs(vy), rest_limit));
  V nx = O::add(x0, vx), ny = O::add(y0, vy);
  V cvx = vx, cvy = vy;
  // rules::collide_with_container. The clamps are max and min, not a compare and
  // a blend: the same bits (max(0, y) is y < 0 ? 0 : y, NaN and -0.0 included) on
  // the position's chain from frame to frame at a quarter of the latency; the
  // masks only steer the velocities.
  M fc = O::m_none();
  if constexpr (Floor) {
    fc = O::lt(ny, zero);
    ny = O::max(zero, ny);
  }
  if constexpr (Ceiling) {
    fc = O::m_or(fc, O::gt(ny, p.height)); // after the floor clamp: the "else if"
    ny = O::min(p.height, ny);
  }
  if constexpr (Floor || Ceiling) {
    cvy = O::select(fc, O::mul(cvy, p.surface_reflection), cvy);
    cvx = O::select(fc, O::mul(cvx, p.surface_friction), cvx);
  }
  SideHits<O> hits{O::m_none(), O::m_none()};
  if constexpr (Sides) {
    hits.left = O::lt(nx, zero);
    nx = O::max(zero, nx);
    const M rw = O::gt(nx, p.width);
    nx = O::min(p.width, nx);
    const M respond = O::m_andnot(O::m_or(hits.left, rw), fc); // the corner rule
    cvx = O::select(respond, O::mul(cvx, p.surface_reflection), cvx);
    cvy = O::select(respond, O::mul(cvy, p.surface_friction), cvy);
    hits.hit = O::m_andnot(respond, rest);
  }
  // A mass at rest keeps its position and its damped velocity (no collision).
  x = O::select(rest, x0, nx);
  y = O::select(rest, y0, ny);
  vx = O::select(rest, vx, cvx);
  vy = O::select(rest, vy, cvy);
  return hits;
}

/// rules::advance_wave_phase per lane, mode as a double (-1, 0 manual, +1):
/// phase + speed * mode, then Java's fmod(moved, 1) (moved - trunc(moved), exact,
/// with moved's sign) plus 1 when negative, 1.0 kept (wrap_moved_wave_phase); a
/// manual lane keeps its phase.
template <class O>
[[gnu::always_inline]] inline typename O::V advance_wave_phase(typename O::V phase, typename O::V speed,
                                                               typename O::V mode) {
  using V = typename O::V;
  const V zero = O::set1(0.0);
  const V moved = O::add(phase, O::mul(speed, mode));
  V wrapped = O::sub(moved, O::trunc(moved));
  wrapped = O::bits_or(O::abs(wrapped), O::bits_and(moved, O::set1(-0.0)));
  wrapped = O::select(O::lt(wrapped, zero), O::add(wrapped, O::set1(1.0)), wrapped);
  return O::select(O::eq(mode, zero), phase, wrapped);
}

#pragma GCC diagnostic pop

} // namespace soda::simd_rules
