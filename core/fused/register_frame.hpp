// The frame in registers: a fused scene of at most 16 points and 32 link slots
// (AVX-512; the Dainty Walker) runs whole frames with its positions, velocities,
// impulses and targets in vector registers (SceneData::frame_in_registers).
// Include only in kernels.cpp, after kernels.hpp.
#pragma once

#include "core/fused/kernels.hpp"

namespace soda::fused {

/// Frames of a scene of at most 16 points and 32 link slots (AVX-512), with every
/// point's position and velocity and every impulse in registers from frame to
/// frame: the link pass takes each end by one permute, the sums take each impulse
/// by one or two permutes and a sign, and nothing goes through memory but the
/// muscle targets and the side-wall hits. The same rules in the same order as
/// link_kernel and mass_kernel (each mass still adds its impulses in file order,
/// from its velocity; a lane without an impulse in a round is left as it is, which
/// is what adding the identity -0.0 gives). A frame with a zero-length link (both
/// ends must add -0.0, not +-0.0) runs through link_kernel and mass_kernel.
// GCC 12 takes the undefined pass-through of _mm512_unpacklo_pd (inside the
// always-inlined lambdas below) for an uninitialised variable: a false positive.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
template <bool Gravity, bool Floor, bool Ceiling, bool Sides>
void register_chunk(SceneData& s, State* const* st, long long frames) {
  using O = Avx512Ops;
  using V = O::V;
  using M = O::M;
  constexpr int W = O::W;
  const int mass_blocks = s.padded_masses / W;
  const int link_blocks = s.padded_link_slots / W;
  const bool wave = s.wave_muscles > 0;
  double* positions = s.positions.data();
  double* velocities = s.velocities.data();
  V x[2], y[2], vx[2], vy[2];
  // Loops over blocks have constant trip counts and test the block count inside,
  // so that they unroll and every array index is a constant: the arrays are then
  // registers, not stack memory.
  const auto load = [&]() __attribute__((always_inline)) {
#pragma GCC unroll 2
    for (int r = 0; r < 2; ++r) {
      O::load_pairs(positions + 2 * W * r, x[r], y[r]); // positions holds 16 points at least
      if (r < mass_blocks) O::load_pairs(velocities + 2 * W * r, vx[r], vy[r]);
    }
  };
  const auto store = [&]() __attribute__((always_inline)) {
#pragma GCC unroll 2
    for (int r = 0; r < 2; ++r) {
      if (r >= mass_blocks) break;
      O::store_pairs(positions + 2 * W * r, x[r], y[r]);
      O::store_pairs(velocities + 2 * W * r, vx[r], vy[r]);
    }
  };
  vx[1] = vy[1] = O::set1(0.0);
  load();
  const V zero = O::set1(0.0);
  // Link targets in registers too. Where the sines fit in two registers
  // (sines_in_registers) the muscle targets are formed here (muscle_targets, as
  // targets_kernel forms them), and nothing is called but fill_rows when the rows
  // run out (row_for_frame): a call spills every vector register.
  V target[4];
  const int target_blocks = s.padded_wave_muscles / W;
  const auto load_targets = [&]() __attribute__((always_inline)) {
#pragma GCC unroll 4
    for (int b = 0; b < 4; ++b) target[b] = b < link_blocks ? O::load(s.link_target.data() + W * b) : zero;
  };
  const auto store_targets = [&]() __attribute__((always_inline)) {
#pragma GCC unroll 4
    for (int b = 0; b < 4; ++b) {
      if (b < target_blocks) O::store(s.link_target.data() + W * b, target[b]);
    }
  };
  load_targets();
  for (long long f = 0; f < frames; ++f) {
    if (wave) {
      if (const double* sine = s.row_for_frame(st)) {
        if (s.sines_in_registers) {
          const V row[2] = {O::loadu(sine), O::loadu(sine + W)}; // the row is padded to kRegisterPoints
#pragma GCC unroll 4
          for (int b = 0; b < 4; ++b) {
            if (b >= target_blocks) break;
            target[b] = muscle_targets<O>(s, row, W * b);
          }
        } else {
          targets_kernel<O>(s, sine);
          load_targets();
        }
      }
    }
    // The links (link_kernel).
    V px[4], py[4];
    px[2] = py[2] = px[3] = py[3] = zero;
    M zero_length = 0;
#pragma GCC unroll 4
    for (int b = 0; b < 4; ++b) {
      if (b >= link_blocks) break;
      const __m512i ia = _mm512_load_si512(s.reg_end_a_lane.data() + W * b);
      const __m512i ib = _mm512_load_si512(s.reg_end_b_lane.data() + W * b);
      const V xa = _mm512_permutex2var_pd(x[0], ia, x[1]), xb = _mm512_permutex2var_pd(x[0], ib, x[1]);
      const V ya = _mm512_permutex2var_pd(y[0], ia, y[1]), yb = _mm512_permutex2var_pd(y[0], ib, y[1]);
      const V dx = O::sub(xb, xa);
      const V dy = O::sub(yb, ya);
      const V length = simd_rules::length<O>(dx, dy);
      const V c = simd_rules::impulse_factor<O>(O::load(s.link_springyness.data() + W * b), length, target[b]);
      // The impulse from the file's difference b - a (link_swap_sign; the impulse_slots give
      // each end its sign).
      const M swapped = O::lt(O::load(s.link_swap_sign.data() + W * b), zero);
      px[b] = O::mul(c, O::select(swapped, O::sub(xa, xb), dx));
      py[b] = O::mul(c, O::select(swapped, O::sub(ya, yb), dy));
      zero_length = O::m_or(zero_length, O::m_and(O::eq(length, zero), s.reg_real_links[b]));
    }
    M any_side = O::m_none();
    if (O::any(zero_length)) [[unlikely]] {
      store();
      store_targets();
      link_kernel<O, true>(s);
      if (mass_kernel<O, Gravity, Floor, Ceiling, Sides>(s)) any_side = 1;
      load();
    } else {
      // The masses (mass_kernel): the sums, then move_mass_block.
      const std::int64_t* index = s.reg_impulse_lane.data();
      const double* sign = s.reg_impulse_sign.data();
      const std::uint8_t* upper = s.reg_upper_blocks.data();
      const std::uint8_t* valid = s.reg_has_impulse.data();
#pragma GCC unroll 2
      for (int m = 0; m < 2; ++m) {
        if (m >= mass_blocks) break;
        V sx = vx[m], sy = vy[m];
        for (int r = s.reg_rounds[m]; r > 0; --r, index += W, sign += W, ++upper, ++valid) {
          // A lane without an impulse this round takes +0.0 (zero-masked), which
          // its sign -0.0 turns into -0.0, the identity of +: so every addition
          // is a plain one (a masked add is a cycle longer on the sums' chain).
          const __m512i idx = _mm512_load_si512(index);
          V ix = _mm512_maskz_permutex2var_pd(*valid, px[0], idx, px[1]);
          V iy = _mm512_maskz_permutex2var_pd(*valid, py[0], idx, py[1]);
          if (link_blocks == 3) {
            // A round without an impulse of the last block (order_by_need puts
            // those late) does not wait for it: the same branch every frame.
            if (*upper != 0) {
              ix = _mm512_mask_permutexvar_pd(ix, *upper, idx, px[2]);
              iy = _mm512_mask_permutexvar_pd(iy, *upper, idx, py[2]);
            }
          } else if (link_blocks == 4) {
            ix = O::select(*upper, _mm512_permutex2var_pd(px[2], idx, px[3]), ix);
            iy = O::select(*upper, _mm512_permutex2var_pd(py[2], idx, py[3]), iy);
          }
          const V sg = O::load(sign);
          // End B: v -= p is v + (-p) exactly.
          sx = O::add(sx, O::bits_xor(ix, sg));
          sy = O::add(sy, O::bits_xor(iy, sg));
        }
        vx[m] = sx;
        vy[m] = sy;
        move_mass_block<O, Gravity, Floor, Ceiling, Sides>(s, W * m, x[m], y[m], vx[m], vy[m], any_side);
      }
    }
    if (O::any(any_side)) s.replay_side_hits(st);
    s.advance_waves(st);
  }
  store();
  store_targets(); // the next chunk starts from s.link_target
}
#pragma GCC diagnostic pop

} // namespace soda::fused
