// LockstepBatch's AVX-512 frame kernels (lockstep_batch.hpp); its construction
// and the states' load and store are in lockstep_plan.cpp.
#include "lockstep_batch.hpp"
#include "core/cancellation.hpp"

// The SIMD templates (simd_rules.hpp) are instantiated with the default target
// and always inlined into the AVX-512 kernels below: no call ever crosses the
// vector ABI that this warning is about.
#pragma GCC diagnostic ignored "-Wpsabi"

#include <immintrin.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "detail/bits.hpp"
#include "detail/lockstep_data.hpp"
#include "detail/simd_rules.hpp"
#include "physics_rules.hpp"

namespace soda {

namespace {
using O = lockstep_detail::O;
using lockstep_detail::kW;
using lockstep_detail::kSideBySide;
} // namespace

// The AVX-512 kernels.
#pragma GCC push_options
#pragma GCC target("avx512f,avx512dq")

// The pool's arguments in rows [first_row, end_row): each column's muscle phase
// against its group's wave phase, the operations of sine_argument lane by lane.
// Recomputing a row leaves the other groups' columns as they were (the same
// operands), so one group's sines may be formed again alone (sines_now).
[[gnu::always_inline]] inline void LockstepBatch::Data::pool_arguments_rows(std::size_t first_row, std::size_t end_row) {
  for (std::size_t r = first_row; r < end_row; ++r) {
    O::store(pool_arguments.data() + r * kW,
             simd_rules::sine_argument<O>(O::load(pool_phase.data() + r * kW), O::load(pool_wave.data() + r * kW)));
  }
}

// Group g's sine arguments for wave phase `phase`, noted in `predicted`: in the
// pool (one per column) where the lanes share their column phases and their
// wave phase, its rows' arguments formed now if `pool_rows_now` (else by the caller).
[[gnu::always_inline]] inline void LockstepBatch::Data::arguments_for(int g, O::V phase, bool pool_rows_now) {
  O::store(predicted.data() + static_cast<std::size_t>(g) * kW, phase);
  const Group& G = groups[static_cast<std::size_t>(g)];
  const O::V first = _mm512_broadcastsd_pd(_mm512_castpd512_pd128(phase));
  const bool share = G.uniform && _mm512_cmpneq_epi64_mask(_mm512_castpd_si512(phase), _mm512_castpd_si512(first)) == 0;
  packed[static_cast<std::size_t>(g)] = share ? 1 : 0;
  if (share) {
    double* wave = pool(pool_wave, g);
    const double w = _mm512_cvtsd_f64(phase);
    for (int q = 0; q < G.columns; ++q) wave[q] = w;
    if (pool_rows_now) pool_arguments_rows(G.pool_at / kW, (G.pool_at + static_cast<std::size_t>(G.columns) + kW - 1) / kW);
    return;
  }
  for (int q = 0; q < G.columns; ++q) O::store(arguments_row(g, q), simd_rules::sine_argument<O>(O::load(column_row(g, q)), phase));
}

// Group g's sines for the phase it has now (in the pool: its rows' sines, the
// other columns' the same again).
void LockstepBatch::Data::sines_now(int g) {
  const Group& G = groups[static_cast<std::size_t>(g)];
  arguments_for(g, O::load(world_row(g, kPhase)), true);
  if (packed[static_cast<std::size_t>(g)] != 0) {
    const std::size_t first = G.pool_at / kW, end = (G.pool_at + static_cast<std::size_t>(G.columns) + kW - 1) / kW;
    sine_fn(pool_arguments.data() + first * kW, pool_sines.data() + first * kW, static_cast<int>((end - first) * kW));
  } else {
    sine_fn(arguments_row(g, 0), sines_row(g, 0), G.columns * kW);
  }
}

// Packed sines (and, for the jitter, their arguments) into group g's rows, one
// column's value in each of its lanes.
[[gnu::always_inline]] inline void LockstepBatch::Data::unpack_sines(int g) {
  const Group& G = groups[static_cast<std::size_t>(g)];
  const double* argument = pool(pool_arguments, g);
  const double* sine = pool(pool_sines, g);
  for (int q = 0; q < G.columns; ++q) {
    O::store(sines_row(g, q), O::set1(sine[q]));
    O::store(arguments_row(g, q), O::set1(argument[q]));
  }
}

// Group g's (arguments, sines) rows to compute during the link passes (not
// packed: the pool's rows are queued whole).
[[gnu::always_inline]] inline void LockstepBatch::Data::queue_sines(int g) {
  const Group& G = groups[static_cast<std::size_t>(g)];
  if (packed[static_cast<std::size_t>(g)] != 0) return;
  for (int q = 0; q < G.columns; ++q) sine_work.emplace_back(arguments_row(g, q), sines_row(g, q));
}

// The lanes whose jitter (seed_mix, threshold per lane) moves a sine of these
// arguments: PreparedJitter::steps's hash, mix64 (mix64.hpp), for 8 lanes at once
// (64-bit multiplies: AVX-512DQ).
namespace {
[[gnu::always_inline]] inline unsigned jitter_hits(__m512d arguments, __m512i seed_mix, __m512i threshold) {
  const __m512i m1 = _mm512_set1_epi64(static_cast<long long>(0xbf58476d1ce4e5b9ULL));
  const __m512i m2 = _mm512_set1_epi64(static_cast<long long>(0x94d049bb133111ebULL));
  __m512i z = _mm512_xor_si512(_mm512_castpd_si512(arguments), seed_mix);
  z = _mm512_mullo_epi64(_mm512_xor_si512(z, _mm512_srli_epi64(z, 30)), m1);
  z = _mm512_mullo_epi64(_mm512_xor_si512(z, _mm512_srli_epi64(z, 27)), m2);
  z = _mm512_xor_si512(z, _mm512_srli_epi64(z, 31));
  return _mm512_cmplt_epu64_mask(_mm512_srli_epi64(z, 11), threshold);
}
} // namespace

// Group g's sines moved by each lane's jitter, as rules::muscle_sine moves them:
// the arguments row still holds the arguments these sines were computed from
// (inline for the predicted phase, or again by sines_now). The hash of
// PreparedJitter::steps for the 8 lanes at once (64-bit multiplies: AVX-512DQ);
// the few lanes it hits (a share p of them) move one by one.
void LockstepBatch::Data::jitter_sines(int g) {
  const std::size_t first = static_cast<std::size_t>(g) * kW;
  const __m512i seed_mix = _mm512_loadu_si512(lane_seed_mix.data() + first);
  const __m512i threshold = _mm512_loadu_si512(lane_threshold.data() + first);
  for (int q = 0; q < groups[static_cast<std::size_t>(g)].columns; ++q) {
    const double* argument = arguments_row(g, q);
    unsigned hits = jitter_hits(_mm512_loadu_pd(argument), seed_mix, threshold);
    if (hits == 0) [[likely]] continue;
    double* sine = sines_row(g, q);
    for (; hits != 0; hits &= hits - 1) {
      const int l = __builtin_ctz(hits);
      PreparedJitter jitter;
      jitter.seed_mix = lane_seed_mix[first + static_cast<std::size_t>(l)];
      jitter.threshold = lane_threshold[first + static_cast<std::size_t>(l)];
      sine[l] = jitter.apply(sine[l], argument[l]);
    }
  }
}

// Whether the jitter of some lane of packed group g moves one of its sines this
// frame (the hash of jitter_sines, each column's argument in every lane).
[[gnu::always_inline]] inline bool LockstepBatch::Data::packed_jitter_hits(int g) {
  const std::size_t first = static_cast<std::size_t>(g) * kW;
  const __m512i seed_mix = _mm512_loadu_si512(lane_seed_mix.data() + first);
  const __m512i threshold = _mm512_loadu_si512(lane_threshold.data() + first);
  const double* argument = pool(pool_arguments, g);
  unsigned hits = 0;
  for (int q = 0; q < groups[static_cast<std::size_t>(g)].columns; ++q) {
    hits |= jitter_hits(_mm512_set1_pd(argument[q]), seed_mix, threshold);
  }
  return hits != 0;
}

// Packed group g's wave links' targets: each column's one sine in every lane.
[[gnu::always_inline]] inline void LockstepBatch::Data::targets_from_packed(int g) {
  const Group& G = groups[static_cast<std::size_t>(g)];
  const double* sine = pool(pool_sines, g);
  for (std::size_t w = 0; w < G.wave_links.size(); ++w) {
    const int j = G.wave_links[w];
    O::store(link_row(g, 2, j), simd_rules::muscle_target<O>(O::load(link_row(g, 0, j)), O::load(link_row(g, 1, j)),
                                                             O::set1(sine[G.column_of[w]])));
  }
}

// Group g's wave links' targets from its sines: rest * (1 + power * sine).
[[gnu::always_inline]] inline void LockstepBatch::Data::targets_from_sines(int g) {
  const Group& G = groups[static_cast<std::size_t>(g)];
  for (std::size_t w = 0; w < G.wave_links.size(); ++w) {
    const int j = G.wave_links[w];
    O::store(link_row(g, 2, j), simd_rules::muscle_target<O>(O::load(link_row(g, 0, j)), O::load(link_row(g, 1, j)),
                                                             O::load(sines_row(g, G.column_of[w]))));
  }
}

// The lanes whose move of one mass may meet a bar: moved (not at rest) and, by the
// tile of the cell of its start (FixedBars::cell_tile), move_may_touch_tile, lane
// by lane the same compares (cell_of's clamps; std::min and std::max as written).
[[gnu::always_inline]] inline unsigned may_meet_bars(const FixedBars& f, O::V x0, O::V y0, O::V x, O::V y, O::V vx,
                                                     O::V vy) {
  const O::V still = O::set1(kZeroVelocity);
  const unsigned rest = _mm512_cmp_pd_mask(_mm512_abs_pd(vx), still, _CMP_LT_OQ) &
                        _mm512_cmp_pd_mask(_mm512_abs_pd(vy), still, _CMP_LT_OQ);
  const O::V c = O::mul(O::sub(x0, O::set1(f.cell_x0)), O::set1(f.cell_scale));
  const O::V last = O::set1(static_cast<double>(f.cell_count - 1));
  __m512i cell = _mm512_maskz_mov_epi64(_mm512_cmp_pd_mask(c, O::set1(0.0), _CMP_GT_OQ), _mm512_cvttpd_epi64(c));
  cell = _mm512_mask_mov_epi64(cell, _mm512_cmp_pd_mask(c, last, _CMP_GE_OQ), _mm512_cvttpd_epi64(last));
  cell = _mm512_slli_epi64(cell, 3);
  static_assert(FixedBars::kTileStride == 8);
  const double* tile = f.cell_tile.data();
  const O::V t0 = _mm512_i64gather_pd(cell, tile + 0, 8), t1 = _mm512_i64gather_pd(cell, tile + 1, 8);
  const O::V t2 = _mm512_i64gather_pd(cell, tile + 2, 8), t3 = _mm512_i64gather_pd(cell, tile + 3, 8);
  const O::V t4 = _mm512_i64gather_pd(cell, tile + 4, 8), t5 = _mm512_i64gather_pd(cell, tile + 5, 8);
  const O::V lo = O::select(O::lt(x, x0), x, x0), hi = O::select(O::lt(x0, x), x, x0);       // std::min, std::max (x0, x)
  const O::V ylo = O::select(O::lt(y, y0), y, y0), yhi = O::select(O::lt(y0, y), y, y0);
  const unsigned inside = _mm512_cmp_pd_mask(lo, t0, _CMP_GE_OQ) & _mm512_cmp_pd_mask(hi, t1, _CMP_LE_OQ);
  const unsigned touch = _mm512_cmp_pd_mask(hi, t2, _CMP_GE_OQ) & _mm512_cmp_pd_mask(lo, t3, _CMP_LE_OQ) &
                         _mm512_cmp_pd_mask(yhi, t4, _CMP_GE_OQ) & _mm512_cmp_pd_mask(ylo, t5, _CMP_LE_OQ);
  return ~rest & (~inside | touch) & 0xffu;
}

// The fixed-bar rules of group g's lanes after the mass pass (which left each
// mass as the reference leaves it before its bar rules, and kept its move), as
// FastStepper's bar_pass (fused/ordered.cpp) does them: per lane in file order
// against the lane's own BarMemory, for a mass that moved and that a bar
// remembers, a corner holds or whose move may touch a bar's box (every moving
// mass until each has its corner entry); a bar's response replaces the mass's
// position and velocity in the lane. The rules of one mass read and change only
// its own move and memory, so the lanes and masses left out change nothing.
void LockstepBatch::Data::bar_pass(int g) {
  const Group& G = groups[static_cast<std::size_t>(g)];
  const FixedBars& fixed = group_bars[static_cast<std::size_t>(g)];
  const std::uint8_t* due = bar_due.data() + G.due_at;
  for (int l = 0; l < G.lanes; ++l) { // padding lanes: never read
    State& s = *lane_state[static_cast<std::size_t>(g) * kW + static_cast<std::size_t>(l)];
    BarMemory& memory = s.bar_memory;
    const bool all = memory.corners.size() < static_cast<std::size_t>(G.masses);
    for (const BarContact& c : memory.contacts) { // bar_held is all 0 between lanes
      if (c.mass >= 0 && c.mass < G.masses) bar_held[static_cast<std::size_t>(c.mass)] = 1;
    }
    const Surface surface{world_row(g, kFs)[l], world_row(g, kRs)[l], world_row(g, kWidth)[l], world_row(g, kHeight)[l]};
    for (int p = 0; p < G.masses; ++p) {
      if (!all && ((due[p] >> l) & 1) == 0 && bar_held[static_cast<std::size_t>(p)] == 0 &&
          memory.corners[static_cast<std::size_t>(p)].bar < 0) {
        continue; // its rules would change nothing (may_meet_bars)
      }
      const double vx = move_row(g, 2, p)[l], vy = move_row(g, 3, p)[l];
      if (rules::is_at_rest(vx, vy)) continue; // not moved: no bar rules
      const double x0 = move_row(g, 0, p)[l], y0 = move_row(g, 1, p)[l];
      double& x = point_row(g, 0, p)[l];
      double& y = point_row(g, 1, p)[l];
      ++bar_rules_run;
      rules::apply_fixed_bars(fixed, memory, p, rules::mass_move(x0, y0, x0 + vx, y0 + vy, vx, vy), surface, x, y,
                              point_row(g, 2, p)[l], point_row(g, 3, p)[l]);
    }
    for (const BarContact& c : memory.contacts) {
      if (c.mass >= 0 && c.mass < G.masses) bar_held[static_cast<std::size_t>(c.mass)] = 0;
    }
  }
}

// One frame's physics and wave advance of groups [g0, g0 + N) (the same links),
// side by side: N independent chains for the processor to overlap.
template <int N, bool Bars>
[[gnu::always_inline]] inline void LockstepBatch::Data::step_groups(int g0) {
  using V = O::V;
  using M = O::M;
  V *x[N], *y[N], *vx[N], *vy[N];
  const double* target[N];
  V springyness[N];
  for (int n = 0; n < N; ++n) {
    x[n] = reinterpret_cast<V*>(point_row(g0 + n, 0, 0));
    y[n] = reinterpret_cast<V*>(point_row(g0 + n, 1, 0));
    vx[n] = reinterpret_cast<V*>(point_row(g0 + n, 2, 0));
    vy[n] = reinterpret_cast<V*>(point_row(g0 + n, 3, 0));
    target[n] = link_row(g0 + n, 2, 0);
    springyness[n] = O::load(world_row(g0 + n, kSpringyness));
  }
  const V zero = O::set1(0.0);
  // The groups' links and masses side by side, each group's in its own order.
  const int* la[N];
  const int* lb[N];
  int group_links[N], group_masses[N];
  int links = 0, masses = 0;
  for (int n = 0; n < N; ++n) {
    const Group& G = groups[static_cast<std::size_t>(g0 + n)];
    la[n] = G.link_a.data();
    lb[n] = G.link_b.data();
    group_links[n] = G.links;
    group_masses[n] = G.masses;
    links = std::max(links, G.links);
    masses = std::max(masses, G.masses);
  }
  // Links in file order (step.cpp apply_links): each impulse goes into both
  // ends' velocities at once; a zero-length link adds nothing (masked).
  for (int j = 0; j < links; ++j) {
    // The next frame's sines, spread over the link passes: sine_rows / total_links of them a link.
    for (sine_credit += sine_rows; sine_credit >= total_links; sine_credit -= total_links, ++sines_done) {
      unsigned far = 0;
      const auto& [in, out] = sine_work[static_cast<std::size_t>(sines_done)];
      java_sine::java_sin<O, 1>(in, out, &far);
      far_lanes |= far;
    }
#pragma GCC unroll 4
    for (int n = 0; n < N; ++n) {
      if (j >= group_links[n]) continue;
      const int a = la[n][j], b = lb[n][j];
      const V dx = O::sub(x[n][b], x[n][a]);
      const V dy = O::sub(y[n][b], y[n][a]);
      const V length = simd_rules::length<O>(dx, dy);
      const M acts = O::ne(length, zero);
      const V c = simd_rules::impulse_factor<O>(springyness[n], length, O::load(target[n] + static_cast<std::size_t>(j) * kW));
      const V px = O::mul(c, dx), py = O::mul(c, dy);
      if (a < group_masses[n]) {
        vx[n][a] = O::add_where(acts, vx[n][a], px);
        vy[n][a] = O::add_where(acts, vy[n][a], py);
      }
      if (b < group_masses[n]) {
        vx[n][b] = O::sub_where(acts, vx[n][b], px);
        vy[n][b] = O::sub_where(acts, vy[n][b], py);
      }
    }
  }
  // Masses in order (step.cpp move_masses); autoreverse lane by lane in mass order.
  simd_rules::MassParams<O> params[N];
  bool hit_wall[N] = {};
  for (int n = 0; n < N; ++n) {
    const int g = g0 + n;
    params[n] = {O::load(world_row(g, kGravityStep)), O::load(world_row(g, kKeep)), O::load(world_row(g, kWidth)),
                 O::load(world_row(g, kHeight)),      O::load(world_row(g, kFs)),   O::load(world_row(g, kRs))};
  }
  // Where this frame's walls were out of reach, the ceiling and side tests
  // would change nothing (the same bits without them); whether they are next
  // frame, from the new positions.
  bool far[N];
  M inside[N];
  V left[N], right[N], top[N];
  for (int n = 0; n < N; ++n) {
    const int g = g0 + n;
    far[n] = walls_far[static_cast<std::size_t>(g)] != 0;
    inside[n] = static_cast<M>(0xff);
    left[n] = O::load(world_row(g, kLeft));
    right[n] = O::load(world_row(g, kRight));
    top[n] = O::load(world_row(g, kTop));
  }
  // With bars: each mass's move kept (its start and the velocity it takes) for bar_pass.
  [[maybe_unused]] bool bars[N] = {};
  if constexpr (Bars) {
    for (int n = 0; n < N; ++n) bars[n] = groups[static_cast<std::size_t>(g0 + n)].bars;
  }
  for (int i = 0; i < masses; ++i) {
#pragma GCC unroll 4
    for (int n = 0; n < N; ++n) {
      if (i >= group_masses[n]) continue;
      [[maybe_unused]] V move_v[2];
      [[maybe_unused]] const V x0 = x[n][i], y0 = y[n][i];
      if (far[n]) {
        simd_rules::move_mass<O, true, true, false, false>(params[n], x[n][i], y[n][i], vx[n][i], vy[n][i], Bars ? move_v : nullptr);
      }
      const simd_rules::SideHits<O> hits =
          far[n] ? simd_rules::SideHits<O>{O::m_none(), O::m_none()}
                 : simd_rules::move_mass<O, true, true, true, true>(params[n], x[n][i], y[n][i], vx[n][i], vy[n][i],
                                                                     Bars ? move_v : nullptr);
      if constexpr (Bars) {
        if (bars[n]) {
          O::store(move_row(g0 + n, 0, i), x0);
          O::store(move_row(g0 + n, 1, i), y0);
          O::store(move_row(g0 + n, 2, i), move_v[0]);
          O::store(move_row(g0 + n, 3, i), move_v[1]);
          bar_due[groups[static_cast<std::size_t>(g0 + n)].due_at + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(
              may_meet_bars(group_bars[static_cast<std::size_t>(g0 + n)], x0, y0, x[n][i], y[n][i], move_v[0], move_v[1]));
        }
      }
      if (!Bars || !bars[n]) { // a group with bars tests every wall next frame anyway (below)
        inside[n] = O::m_and(inside[n], O::m_and(O::gt(x[n][i], left[n]), O::m_and(O::lt(x[n][i], right[n]), O::lt(y[n][i], top[n]))));
      }
      if (O::any(hits.hit)) [[unlikely]] {
        hit_wall[n] = true;
        const int g = g0 + n;
        double* mode = world_row(g, kMode);
        for (int l = 0; l < kW; ++l) {
          if (!((hits.hit >> l) & 1)) continue;
          State& s = *lane_state[static_cast<std::size_t>(g) * kW + l];
          WaveDirection m = static_cast<WaveDirection>(static_cast<int>(mode[l]));
          rules::autoreverse_on_wall_hit((hits.left >> l) & 1 ? SideWall::Left : SideWall::Right,
                                         autoreverse[static_cast<std::size_t>(g) * kW + l] != 0, m, s.last_side_wall);
          mode[l] = static_cast<double>(static_cast<int>(m));
        }
      }
    }
  }
  // Fixed bars after every mass moved (autoreverse done: a bar hit leaves it), as
  // FastStepper's bar_pass; every wall tested next frame (a bar's push-off is not
  // bounded by the speed limit).
  if constexpr (Bars) {
    for (int n = 0; n < N; ++n) {
      if (!bars[n]) continue;
      bar_pass(g0 + n);
      inside[n] = O::m_none();
    }
  }
  for (int n = 0; n < N; ++n) walls_far[static_cast<std::size_t>(g0 + n)] = inside[n] == static_cast<M>(0xff) ? 1 : 0;
  // The wave advance after the physics (docs/physics.md, "The wave"): the
  // predicted phase where no lane hit a side wall (the same operations on the
  // same operands). Where a direction turned, the next frame's sines again once
  // the frame is done (step_frame).
  for (int n = 0; n < N; ++n) {
    const int g = g0 + n;
    const double* expected = predicted.data() + static_cast<std::size_t>(g) * kW;
    if (groups[static_cast<std::size_t>(g)].columns > 0 && !hit_wall[n]) {
      O::store(world_row(g, kPhase), O::load(expected));
      continue;
    }
    const V phase = simd_rules::advance_wave_phase<O>(O::load(world_row(g, kPhase)), O::load(world_row(g, kSpeed)),
                                                      O::load(world_row(g, kMode)));
    O::store(world_row(g, kPhase), phase);
    if (groups[static_cast<std::size_t>(g)].columns == 0) continue;
    redo[static_cast<std::size_t>(g)] = _mm512_cmpneq_epi64_mask(_mm512_castpd_si512(phase), _mm512_load_si512(expected)) != 0;
  }
}

// One frame of every group: this frame's targets from the sines computed for it
// and the arguments of the next frame's at the phase each wave will have if no
// direction turns; the link and mass passes, two groups at a time, with those
// sines spread over them; the sines again of a group whose wave turned (or all,
// where they were not computed in the passes).
void LockstepBatch::Data::step_frame() {
  sine_work.clear();
  for (int g = 0; g < static_cast<int>(groups.size()); ++g) {
    const Group& G = groups[static_cast<std::size_t>(g)];
    if (G.columns == 0) continue;
    if (packed[static_cast<std::size_t>(g)] != 0 && !(G.jittered && packed_jitter_hits(g))) {
      targets_from_packed(g); // the lanes' sines as computed: each column's in every lane
    } else {
      if (packed[static_cast<std::size_t>(g)] != 0) unpack_sines(g);
      if (G.jittered) [[unlikely]] jitter_sines(g);
      targets_from_sines(g);
    }
    arguments_for(g, simd_rules::advance_wave_phase<O>(O::load(world_row(g, kPhase)), O::load(world_row(g, kSpeed)),
                                                       O::load(world_row(g, kMode))),
                  false);
    if (inline_sines) queue_sines(g);
  }
  pool_arguments_rows(0, static_cast<std::size_t>(pool_rows));
  if (inline_sines) {
    for (int r = 0; r < pool_rows; ++r) {
      sine_work.emplace_back(pool_arguments.data() + static_cast<std::size_t>(r) * kW, pool_sines.data() + static_cast<std::size_t>(r) * kW);
    }
  }
  sine_rows = static_cast<int>(sine_work.size());
  sines_done = 0;
  sine_credit = 0;
  far_lanes = 0;
  for (std::size_t k = 0; k < schedule.size(); ++k) {
    static_assert(kSideBySide == 2);
    const auto [g, n] = schedule[k];
    if (schedule_bars[k] != 0) [[unlikely]] {
      if (n == 2) {
        step_groups<2, true>(g);
      } else {
        step_groups<1, true>(g);
      }
    } else if (n == 2) {
      step_groups<2, false>(g);
    } else {
      step_groups<1, false>(g);
    }
  }
  assert(sines_done == sine_rows);
  const bool all_again = !inline_sines || far_lanes != 0;
  for (int g = 0; g < static_cast<int>(groups.size()); ++g) {
    if (groups[static_cast<std::size_t>(g)].columns > 0 && (all_again || redo[static_cast<std::size_t>(g)] != 0)) sines_now(g);
    redo[static_cast<std::size_t>(g)] = 0;
  }
}

void LockstepBatch::run(State* const* states, long long frames) {
  Data& d = *d_;
  require_batch_states(states, d.count, [&](int c) { return d.state_points[static_cast<std::size_t>(c)]; }, "LockstepBatch::run");
  for (int c = 0; c < d.count; ++c) require_valid_jitter_of(states[c]->jitter, "LockstepBatch::run", c);
  step(states, frames);
}

void LockstepBatch::step(State* const* states, long long frames) { step_until(states, frames, nullptr, nullptr); }

long long LockstepBatch::run_until(State* const* states, long long frames, const StopFn& stop, std::vector<long long>& done) {
  Data& d = *d_;
  require_batch_states(states, d.count, [&](int c) { return d.state_points[static_cast<std::size_t>(c)]; }, "LockstepBatch::run_until");
  for (int c = 0; c < d.count; ++c) require_valid_jitter_of(states[c]->jitter, "LockstepBatch::run_until", c);
  done.assign(static_cast<std::size_t>(d.count), 0);
  return step_until(states, frames, &stop, done.data());
}

long long LockstepBatch::step_until(State* const* states, long long frames, const StopFn* stop, long long* done) {
  Data& d = *d_;
  if (frames <= 0) return 0;
  d.load(states);
  std::fill(d.walls_far.begin(), d.walls_far.end(), 0); // tested in the first frame, known after it
  const std::size_t lanes = d.groups.size() * kW;
  // Padding lanes autoreverse into a scratch copy of their group's last state, not
  // into it; so do stopped lanes (and their bar memory), which step on unread.
  std::vector<State> scratch;
  scratch.reserve(lanes);
  d.lane_state.resize(lanes);
  d.lane_seed_mix.assign(lanes, 0); // padding lanes: exact, unread
  d.lane_threshold.assign(lanes, 0);
  for (std::size_t g = 0; g < d.groups.size(); ++g) {
    Data::Group& G = d.groups[g];
    G.jittered = false;
    for (int l = 0; l < kW; ++l) {
      const std::size_t lane = g * kW + static_cast<std::size_t>(l);
      if (l < G.lanes) {
        State* s = states[G.first + l];
        d.lane_state[lane] = s;
        const PreparedJitter jitter(s->jitter);
        d.lane_seed_mix[lane] = jitter.seed_mix;
        d.lane_threshold[lane] = jitter.threshold;
        if (jitter.threshold != 0) G.jittered = true;
      } else {
        scratch.push_back(*states[G.first + G.lanes - 1]);
        d.lane_state[lane] = &scratch.back();
      }
    }
  }
  for (int g = 0; g < static_cast<int>(d.groups.size()); ++g) {
    if (d.groups[static_cast<std::size_t>(g)].columns > 0) d.sines_now(g);
  }
  std::vector<std::uint8_t> running(static_cast<std::size_t>(d.count), 1);
  int left = d.count;
  long long ran = 0;
  while (ran < frames && left > 0) {
    if (ran % kCancellationFrames == kCancellationFrames - 1) check_cancellation();
    d.step_frame();
    ++ran;
    if (stop == nullptr) continue;
    // Each running lane's free masses' least and greatest x, in mass order as
    // FastStepper::run_until takes them (std::min, std::max one after the other).
    for (int g = 0; g < static_cast<int>(d.groups.size()); ++g) {
      const Data::Group& G = d.groups[static_cast<std::size_t>(g)];
      for (int l = 0; l < G.lanes; ++l) {
        const int c = G.first + l;
        if (running[static_cast<std::size_t>(c)] == 0) continue;
        double lo = G.masses > 0 ? d.point_row(g, 0, 0)[l] : 0.0, hi = lo;
        for (int p = 1; p < G.masses; ++p) {
          const double x = d.point_row(g, 0, p)[l];
          lo = std::min(lo, x);
          hi = std::max(hi, x);
        }
        if (!(*stop)(c, lo, hi)) continue;
        State& s = *states[c];
        d.store_lane(g, l, s);
        s.frame += ran;
        done[c] = ran;
        running[static_cast<std::size_t>(c)] = 0;
        --left;
        scratch.push_back(s);
        d.lane_state[static_cast<std::size_t>(g) * kW + static_cast<std::size_t>(l)] = &scratch.back();
      }
    }
  }
  for (int g = 0; g < static_cast<int>(d.groups.size()); ++g) {
    const Data::Group& G = d.groups[static_cast<std::size_t>(g)];
    for (int l = 0; l < G.lanes; ++l) {
      const int c = G.first + l;
      if (running[static_cast<std::size_t>(c)] == 0) continue;
      d.store_lane(g, l, *states[c]);
      states[c]->frame += ran;
      if (done != nullptr) done[c] = ran;
    }
  }
  return ran;
}

#pragma GCC pop_options

} // namespace soda
