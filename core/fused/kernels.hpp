// The SIMD kernels of a fused scene, written once as templates over the SIMD
// operations O (core/detail/simd_ops.hpp) and compiled per instruction set in
// kernels.cpp: the link pass, the mass pass, the muscle targets and the sine
// arguments, and the frame loop that runs them for one wall/gravity specialisation.
//
// The formulas are those of physics_rules.hpp (and of the link loop of step.cpp),
// lane by lane, in the same operation order; the comment on each says which rule
// it is (the SIMD twins of the rules are core/detail/simd_rules.hpp).
// tests/test_fast_step.cpp and tests/test_batch_step.cpp check the results bit for bit.
// Include only in kernels.cpp.
#pragma once

#include <immintrin.h>

#include <cstdint>
#include <cstring>

#include "core/detail/simd_rules.hpp"
#include "core/fused/scene_data.hpp"
#include "core/fused/sine_rows.hpp"

// move_mass_block is instantiated implicitly with the default target and always
// inlined into the kernels of each level: no call ever crosses the vector ABI that
// this warning is about.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace soda::fused {

/// The links (docs/physics.md, part 1; step.cpp apply_links): impulses of all acting links in
/// SIMD from the positions (which do not change while links act). With
/// PointRegisters (Avx512Ops, small scenes) the ends' coordinates come from
/// registers holding every point (O::load_points, O::point).
template <class O, bool PointRegisters>
void link_kernel(SceneData& s) {
  using V = typename O::V;
  const double* positions = s.positions.data();
  const double* link_target = s.link_target.data();
  double* imp_a = s.impulses.data();
  double* imp_b = s.impulses.data() + 2 * static_cast<std::size_t>(s.padded_link_slots);
  const std::uint32_t* end_a_offset = s.end_a_offset.data();
  const std::uint32_t* end_b_offset = s.end_b_offset.data();
  const std::int32_t* a_end_block = s.a_end_block.data();
  const double* link_springyness = s.link_springyness.data();
  const double* link_swap_sign = s.link_swap_sign.data();
  const V zero = O::set1(0.0);
  const V neg_zero = O::set1(-0.0);
  [[maybe_unused]] V x[2], y[2];
  if constexpr (PointRegisters) O::load_points(positions, x, y);
  const int n = (s.link_slots + O::W - 1) / O::W * O::W;
  for (int i = 0; i < n; i += O::W) {
    V xa, ya, xb, yb;
    if constexpr (PointRegisters) {
      const std::int64_t* pa = s.end_a_point.data() + i;
      const std::int64_t* pb = s.end_b_point.data() + i;
      xa = O::point(x, pa);
      ya = O::point(y, pa);
      xb = O::point(x, pb);
      yb = O::point(y, pb);
    } else {
      if (const int blk = a_end_block[i / O::W]; blk >= 0) {
        O::load_pairs(positions + 2 * O::W * blk, xa, ya);
      } else {
        O::load_pairs_at(positions, end_a_offset + i, xa, ya);
      }
      O::load_pairs_at(positions, end_b_offset + i, xb, yb);
    }
    const V dx = O::sub(xb, xa);
    const V dy = O::sub(yb, ya);
    const V length = simd_rules::length<O>(dx, dy);
    const V c = simd_rules::impulse_factor<O>(O::load(link_springyness + i), length, O::load(link_target + i));
    // The impulse from the file's difference b - a (link_swap_sign; the impulse_slots give each
    // end its sign).
    const auto swapped = O::lt(O::load(link_swap_sign + i), zero);
    const V px = O::mul(c, O::select(swapped, O::sub(xa, xb), dx));
    const V py = O::mul(c, O::select(swapped, O::sub(ya, yb), dy));
    // End B: v -= p is v + (-p) exactly. A zero-length link is skipped: both its
    // ends then add -0.0, the identity of + (rare, so tested once per block).
    const auto skip = O::eq(length, zero);
    if (!O::any(skip)) {
      O::store_pairs(imp_a + 2 * i, px, py);
      O::store_pairs(imp_b + 2 * i, O::neg(px), O::neg(py));
    } else {
      O::store_pairs(imp_a + 2 * i, O::select(skip, neg_zero, px), O::select(skip, neg_zero, py));
      O::store_pairs(imp_b + 2 * i, O::select(skip, neg_zero, O::neg(px)), O::select(skip, neg_zero, O::neg(py)));
    }
  }
}

/// move_may_touch_tile (fixed_bars.hpp) for the W masses of a block, each with the
/// tile it keeps (SceneData::mass_tile), the same comparisons lane by lane (O::min(b,
/// a) is std::min(a, b), NaN included): the lanes whose move may touch a bar's box.
template <class O>
[[gnu::always_inline]] inline unsigned may_touch_bars(const double* tile, typename O::V x0, typename O::V y0,
                                                     typename O::V x, typename O::V y) {
  using V = typename O::V;
  const V lo = O::min(x, x0), hi = O::max(x, x0);
  const unsigned inside = O::lanes(O::m_and(O::ge(lo, O::load(tile)), O::le(hi, O::load(tile + O::W))));
  const auto touch = O::m_and(O::m_and(O::ge(hi, O::load(tile + 2 * O::W)), O::le(lo, O::load(tile + 3 * O::W))),
                              O::m_and(O::ge(O::max(y, y0), O::load(tile + 4 * O::W)),
                                       O::le(O::min(y, y0), O::load(tile + 5 * O::W))));
  return (~inside & ((1u << O::W) - 1)) | O::lanes(touch);
}

/// The mass step of one block of W masses starting at working index i (docs/physics.md,
/// part 2), after their impulses: gravity, friction with the syrup limit, rest test, move,
/// container walls, each mass with its own creature's parameters. (x, y) are the positions
/// before the move and (vx, vy) the velocities after the impulses; all four are replaced by the
/// stored results. Side-wall hits go to s.side_hit and any_side.
/// With Bars, the block's moves are kept for the bar rules (SceneData::bar_pass): the
/// start positions and the velocities the moves take.
template <class O, bool Gravity, bool Floor, bool Ceiling, bool Sides, bool Bars = false>
[[gnu::always_inline]] inline void move_mass_block(SceneData& s, int i, typename O::V& x, typename O::V& y, typename O::V& vx,
                            typename O::V& vy, typename O::M& any_side) {
  using V = typename O::V;
  const simd_rules::MassParams<O> params{O::load(s.mass_gravity_step.data() + i),    O::load(s.mass_air_keep.data() + i),
                                         O::load(s.mass_width.data() + i), O::load(s.mass_height.data() + i),
                                         O::load(s.mass_surface_friction.data() + i),    O::load(s.mass_surface_reflection.data() + i)};
  [[maybe_unused]] V move_v[2];
  [[maybe_unused]] const V x0 = x, y0 = y;
  const simd_rules::SideHits<O> sides =
      simd_rules::move_mass<O, Gravity, Floor, Ceiling, Sides>(params, x, y, vx, vy, Bars ? move_v : nullptr);
  if constexpr (Bars) {
    O::store_pairs(s.move_start.data() + 2 * i, x0, y0);
    O::store_pairs(s.move_velocity.data() + 2 * i, move_v[0], move_v[1]);
    s.bar_touch[static_cast<std::size_t>(i / O::W)] =
        may_touch_bars<O>(s.mass_tile.data() + SceneData::kTileValues * static_cast<std::size_t>(i), x0, y0, x, y);
  }
  // s.side_hit is all zero between frames (replay_side_hits clears what it reads):
  // only a block with a hit writes it.
  if (O::any(sides.hit)) [[unlikely]] {
    const V h = O::select(O::m_and(sides.hit, sides.left), O::set1(-1.0), O::select(sides.hit, O::set1(1.0), O::set1(0.0)));
    O::store_pairs(s.side_hit.data() + 2 * i, h, h);
    any_side = O::m_or(any_side, sides.hit);
  }
}

/// The masses (docs/physics.md, part 2) in SIMD over masses: first each mass's impulses added
/// to its velocity in file order of the links (the order of the additions into one velocity is
/// the reference's), then move_mass_block. Returns whether some mass responded to a side wall
/// (autoreverse is then replayed in mass order).
///
/// The sums go by groups of kGatherGroup consecutive masses (numbered by degree at
/// build), one round per impulse; impulse_slots hold double offsets (2 * pair index), so
/// each addition is one load and one add, and the sums stay in registers for the
/// rest of the step. (Pairs of masses in 256-bit additions were slower: the inserts
/// cost more than the additions saved; bench/README.md, "Design figures".)
template <class O, bool Gravity, bool Floor, bool Ceiling, bool Sides, bool Bars = false>
bool mass_kernel(SceneData& s) {
  using V = typename O::V;
  using M = typename O::M;
  double* positions = s.positions.data();
  double* velocities = s.velocities.data();
  M any_side = O::m_none();
  const double* impulses = s.impulses.data();
  const std::uint32_t* sl = s.impulse_slots.data();
  const int groups = s.padded_masses / kGatherGroup;
  for (int g = 0; g < groups; ++g) {
    __m128d acc[kGatherGroup];
    for (int l = 0; l < kGatherGroup; ++l) acc[l] = _mm_load_pd(velocities + 2 * (g * kGatherGroup + l));
    for (int r = s.group_rounds[g]; r > 0; --r, sl += kGatherGroup) {
      // Two offsets per 64-bit load: the loads, not the additions, limit this loop.
      for (int l = 0; l < kGatherGroup; l += 2) {
        std::uint64_t two;
        std::memcpy(&two, sl + l, sizeof two);
        acc[l] = _mm_add_pd(acc[l], _mm_load_pd(impulses + static_cast<std::uint32_t>(two)));
        acc[l + 1] = _mm_add_pd(acc[l + 1], _mm_load_pd(impulses + (two >> 32)));
      }
    }
#pragma GCC unroll 4
    for (int j = 0; j < kGatherGroup; j += O::W) {
      const int i = g * kGatherGroup + j;
      V vx, vy, x, y;
      O::pairs_to_xy(acc + j, vx, vy);
      O::load_pairs(positions + 2 * i, x, y);
      move_mass_block<O, Gravity, Floor, Ceiling, Sides, Bars>(s, i, x, y, vx, vy, any_side);
      O::store_pairs(positions + 2 * i, x, y);
      O::store_pairs(velocities + 2 * i, vx, vy);
    }
  }
  return O::any(any_side);
}

/// Muscle targets of the W target slots from q from their sines: rest * (1 +
/// (Aw*Am) * sine), the second half of rules::muscle_target_length.
template <class O>
[[gnu::always_inline]] inline typename O::V muscle_target(const SceneData& s, int q, typename O::V sine) {
  return simd_rules::muscle_target<O>(O::loadu(s.muscle_rest.data() + q), O::loadu(s.muscle_power.data() + q), sine);
}

/// The same from the row of sines held in two registers (sines_in_registers: one
/// permute per muscle, not a gather).
template <class O>
[[gnu::always_inline]] inline typename O::V muscle_targets(const SceneData& s, const typename O::V (&row)[2], int q) {
  return muscle_target<O>(s, q, O::point(row, s.muscle_group_lane.data() + q));
}

/// The targets of impulse_slots [0, padded_wave_muscles) from this frame's row of sines.
template <class O>
void targets_kernel(SceneData& s, const double* sine) {
  using V = typename O::V;
  if constexpr (O::kPointRegisters) {
    // A row of up to 96 sines in registers: each muscle's by permutes (O::pick; a
    // row of sines_in_registers takes one).
    // Rows are padded so that the loads may run 15 values past the row's end.
    if (s.sine_stride <= O::W * O::kPickRegisters) {
      const int pairs = (s.sine_stride + 2 * O::W - 1) / (2 * O::W);
      V row[O::kPickRegisters];
#pragma GCC unroll 12
      for (int j = 0; j < O::kPickRegisters; ++j) row[j] = j < 2 * pairs ? O::loadu(sine + O::W * j) : O::set1(0.0);
      for (int q = 0; q < s.padded_wave_muscles; q += O::W) {
        O::store(s.link_target.data() + q, muscle_target<O>(s, q, O::pick(row, pairs, s.sine_lane + q)));
      }
      return;
    }
  }
  for (int q = 0; q < s.padded_wave_muscles; q += O::W) {
    O::store(s.link_target.data() + q, muscle_target<O>(s, q, O::gather(sine, s.sine_index + q)));
  }
}

/// The sine arguments of rows [0, filled) (fill_rows): argument d of row r is
/// 2pi * (muscle phase - the row's phase of its wave state), as
/// rules::muscle_target_length forms it, W arguments of one wave state at a time
/// (they are consecutive: number_arguments). The last vector of a state runs into
/// the next state's arguments or row, which are written after it (arguments and
/// argument_muscle_phase are padded for the last row's).
template <class O>
void args_kernel(SceneData& s, int filled) {
  using V = typename O::V;
  const std::size_t stride = s.creatures.size();
  // Locals: the stores through arg could alias s's members, which would then be
  // reloaded after each of them.
  const int wave_states = s.wave_states, distinct_arguments = s.distinct_arguments;
  const int* first = s.first_argument_of_state.data();
  const double* muscle_phase = s.argument_muscle_phase.data();
  for (int r = 0; r < filled; ++r) {
    const double* phase = s.row_phase.data() + static_cast<std::size_t>(r) * stride;
    double* arg = s.arguments.data() + static_cast<std::size_t>(r) * distinct_arguments;
    for (int k = 0; k < wave_states; ++k) {
      const V wave = O::set1(phase[k]);
      for (int d = first[k]; d < first[k + 1]; d += O::W) {
        O::storeu(arg + d, simd_rules::sine_argument<O>(O::loadu(muscle_phase + d), wave));
      }
    }
  }
}

/// Frames with the SIMD kernels for one wall/gravity specialisation: the frame
/// loop is inside the specialised function, so nothing is looked up per frame.
/// With Bars (some creature has fixed bars), the bar rules follow the mass pass
/// for the masses that may meet a bar (SceneData::bar_pass).
template <class O, bool Gravity, bool Floor, bool Ceiling, bool Sides, bool Bars = false>
void run_chunk(SceneData& s, State* const* st, long long frames) {
  const bool wave = s.wave_muscles > 0;
  for (long long f = 0; f < frames; ++f) {
    if (wave) s.update_targets(st);
    if (s.link_slots > 0) {
      // points_in_registers is only ever set where O::kPointRegisters holds.
      if (s.points_in_registers) {
        link_kernel<O, O::kPointRegisters>(s);
      } else {
        link_kernel<O, false>(s);
      }
    }
    if (mass_kernel<O, Gravity, Floor, Ceiling, Sides, Bars>(s)) s.replay_side_hits(st);
    if constexpr (Bars) s.bar_pass(st);
    s.advance_waves(st);
  }
}

} // namespace soda::fused
