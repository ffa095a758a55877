// LockstepBatch's frame kernels (lockstep_batch.hpp), written once over the SIMD
// operations of an 8-lane vector O: Avx512Ops (simd_ops.hpp) or Avx2PairOps
// (avx2_pair_ops.hpp). Each level's file (lockstep_kernels_avx512.cpp,
// lockstep_kernels_avx2.cpp) includes this under its target and exports the pair
// of entry points LockstepBatch::Data calls (LockstepEntry).
//
// Why a template: the kernels are the same operations on the same operands per
// lane at every level, so the same bits; only the instructions differ. Private to
// those two files (core/detail/); everything is in an unnamed namespace, so each
// file has its own copy for its own instruction set.
#pragma once

// The SIMD templates are instantiated with the default target and always inlined
// into the kernels: no call ever crosses the vector ABI this warns about.
#pragma GCC diagnostic ignored "-Wpsabi"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>

#include "core/detail/java_sine_simd.hpp"
#include "core/detail/lockstep_data.hpp"
#include "core/detail/simd_rules.hpp"
#include "core/physics_rules.hpp"

namespace soda {
namespace {

template <class O>
struct LockstepKernels {
  using Data = LockstepBatch::Data;
  using Group = Data::Group;
  using V = typename O::V;
  using M = typename O::M;
  using I = typename O::I;
  static constexpr int kW = lockstep_detail::kW;
  static_assert(O::W == kW);

  // The pool's arguments in rows [first_row, end_row): each column's muscle phase
  // against its group's wave phase, the operations of sine_argument lane by lane.
  // Recomputing a row leaves the other groups' columns as they were (the same
  // operands), so one group's sines may be formed again alone (sines_now).
  [[gnu::always_inline]] static void pool_arguments_rows(Data& d, std::size_t first_row, std::size_t end_row) {
    for (std::size_t r = first_row; r < end_row; ++r) {
      O::store(d.pool_arguments.data() + r * kW,
               simd_rules::sine_argument<O>(O::load(d.pool_phase.data() + r * kW), O::load(d.pool_wave.data() + r * kW)));
    }
  }

  // Group g's sine arguments for wave phase `phase`, noted in `predicted`: in the
  // pool (one per column) where the lanes share their column phases and their
  // wave phase, its rows' arguments formed now if `pool_rows_now` (else by the caller).
  [[gnu::always_inline]] static void arguments_for(Data& d, int g, V phase, bool pool_rows_now) {
    O::store(d.predicted.data() + static_cast<std::size_t>(g) * kW, phase);
    const Group& G = d.groups[static_cast<std::size_t>(g)];
    const bool share = G.uniform && O::lanes_alike(phase);
    d.packed[static_cast<std::size_t>(g)] = share ? 1 : 0;
    if (share) {
      double* wave = d.pool(d.pool_wave, g);
      const double w = O::first(phase);
      for (int q = 0; q < G.columns; ++q) wave[q] = w;
      if (pool_rows_now) pool_arguments_rows(d, G.pool_at / kW, (G.pool_at + static_cast<std::size_t>(G.columns) + kW - 1) / kW);
      return;
    }
    double* const arguments = d.arguments_row(g, 0);
    const double* const columns = d.column_row(g, 0);
    for (int q = 0; q < G.columns; ++q) {
      const std::size_t at = static_cast<std::size_t>(q) * kW;
      O::store(arguments + at, simd_rules::sine_argument<O>(O::load(columns + at), phase));
    }
  }

  // Group g's sines for the phase it has now (in the pool: its rows' sines, the
  // other columns' the same again).
  static void sines_now(Data& d, int g) {
    const Group& G = d.groups[static_cast<std::size_t>(g)];
    arguments_for(d, g, O::load(d.world_row(g, Data::kPhase)), true);
    if (d.packed[static_cast<std::size_t>(g)] != 0) {
      const std::size_t first = G.pool_at / kW, end = (G.pool_at + static_cast<std::size_t>(G.columns) + kW - 1) / kW;
      d.sine_fn(d.pool_arguments.data() + first * kW, d.pool_sines.data() + first * kW, static_cast<int>((end - first) * kW));
    } else {
      d.sine_fn(d.arguments_row(g, 0), d.sines_row(g, 0), G.columns * kW);
    }
  }

  // Packed sines (and, for the jitter, their arguments) into group g's rows, one
  // column's value in each of its lanes.
  [[gnu::always_inline]] static void unpack_sines(Data& d, int g) {
    const Group& G = d.groups[static_cast<std::size_t>(g)];
    const double* argument = d.pool(d.pool_arguments, g);
    const double* sine = d.pool(d.pool_sines, g);
    double* const sines = d.sines_row(g, 0);
    double* const arguments = d.arguments_row(g, 0);
    for (int q = 0; q < G.columns; ++q) {
      O::store(sines + static_cast<std::size_t>(q) * kW, O::set1(sine[q]));
      O::store(arguments + static_cast<std::size_t>(q) * kW, O::set1(argument[q]));
    }
  }

  // Group g's (arguments, sines) rows to compute during the link passes (not
  // packed: the pool's rows are queued whole).
  [[gnu::always_inline]] static void queue_sines(Data& d, int g) {
    const Group& G = d.groups[static_cast<std::size_t>(g)];
    if (d.packed[static_cast<std::size_t>(g)] != 0) return;
    const double* const arguments = d.arguments_row(g, 0);
    double* const sines = d.sines_row(g, 0);
    for (std::size_t at = 0; at < static_cast<std::size_t>(G.columns) * kW; at += kW) d.sine_work.emplace_back(arguments + at, sines + at);
  }

  // The lanes whose jitter (seed_mix, threshold per lane) moves a sine of these
  // arguments: PreparedJitter::steps's hash, mix64 (mix64.hpp), for 8 lanes at once.
  [[gnu::always_inline]] static unsigned jitter_hits(V arguments, I seed_mix, I threshold) {
    I z = O::ixor(O::ibits(arguments), seed_mix);
    z = O::imul(O::ixor(z, O::template ishr<30>(z)), O::iset1(0xbf58476d1ce4e5b9ULL));
    z = O::imul(O::ixor(z, O::template ishr<27>(z)), O::iset1(0x94d049bb133111ebULL));
    z = O::ixor(z, O::template ishr<31>(z));
    return O::ilt_small(O::template ishr<11>(z), threshold); // both below 2^63: threshold <= 2^53
  }

  // Group g's sines moved by each lane's jitter, as rules::muscle_sine moves them:
  // the arguments row still holds the arguments these sines were computed from
  // (inline for the predicted phase, or again by sines_now). The hash of
  // PreparedJitter::steps for the 8 lanes at once; the few lanes it hits (a share
  // p of them) move one by one.
  static void jitter_sines(Data& d, int g) {
    const std::size_t first = static_cast<std::size_t>(g) * kW;
    const I seed_mix = O::iload(d.lane_seed_mix.data() + first);
    const I threshold = O::iload(d.lane_threshold.data() + first);
    const double* const arguments = d.arguments_row(g, 0);
    double* const sines = d.sines_row(g, 0);
    for (int q = 0; q < d.groups[static_cast<std::size_t>(g)].columns; ++q) {
      const double* argument = arguments + static_cast<std::size_t>(q) * kW;
      unsigned hits = jitter_hits(O::load(argument), seed_mix, threshold);
      if (hits == 0) [[likely]] continue;
      double* sine = sines + static_cast<std::size_t>(q) * kW;
      for (; hits != 0; hits &= hits - 1) {
        const int l = __builtin_ctz(hits);
        PreparedJitter jitter;
        jitter.seed_mix = d.lane_seed_mix[first + static_cast<std::size_t>(l)];
        jitter.threshold = d.lane_threshold[first + static_cast<std::size_t>(l)];
        sine[l] = jitter.apply(sine[l], argument[l]);
      }
    }
  }

  // Whether the jitter of some lane of packed group g moves one of its sines this
  // frame (the hash of jitter_sines, each column's argument in every lane).
  [[gnu::always_inline]] static bool packed_jitter_hits(Data& d, int g) {
    const std::size_t first = static_cast<std::size_t>(g) * kW;
    const I seed_mix = O::iload(d.lane_seed_mix.data() + first);
    const I threshold = O::iload(d.lane_threshold.data() + first);
    const double* argument = d.pool(d.pool_arguments, g);
    unsigned hits = 0;
    for (int q = 0; q < d.groups[static_cast<std::size_t>(g)].columns; ++q) {
      hits |= jitter_hits(O::set1(argument[q]), seed_mix, threshold);
    }
    return hits != 0;
  }

  // Packed group g's wave links' targets: each column's one sine in every lane.
  [[gnu::always_inline]] static void targets_from_packed(Data& d, int g) {
    const Group& G = d.groups[static_cast<std::size_t>(g)];
    const double* sine = d.pool(d.pool_sines, g);
    const double* const rest = d.link_row(g, 0, 0);
    const double* const power = d.link_row(g, 1, 0);
    double* const target = d.link_row(g, 2, 0);
    const int wave_links = static_cast<int>(G.wave_links.size());
    for (int w = 0; w < wave_links; ++w) {
      const std::size_t at = static_cast<std::size_t>(G.wave_links[static_cast<std::size_t>(w)]) * kW;
      O::store(target + at, simd_rules::muscle_target<O>(O::load(rest + at), O::load(power + at),
                                                         O::set1(sine[G.column_of[static_cast<std::size_t>(w)]])));
    }
  }

  // Group g's wave links' targets from its sines: rest * (1 + power * sine).
  [[gnu::always_inline]] static void targets_from_sines(Data& d, int g) {
    const Group& G = d.groups[static_cast<std::size_t>(g)];
    const double* const rest = d.link_row(g, 0, 0);
    const double* const power = d.link_row(g, 1, 0);
    double* const target = d.link_row(g, 2, 0);
    const double* const sines = d.sines_row(g, 0);
    const int wave_links = static_cast<int>(G.wave_links.size());
    for (int w = 0; w < wave_links; ++w) {
      const std::size_t at = static_cast<std::size_t>(G.wave_links[static_cast<std::size_t>(w)]) * kW;
      const std::size_t column = static_cast<std::size_t>(G.column_of[static_cast<std::size_t>(w)]) * kW;
      O::store(target + at, simd_rules::muscle_target<O>(O::load(rest + at), O::load(power + at), O::load(sines + column)));
    }
  }

  // The lanes whose move of one mass may meet a bar: moved (not at rest) and, by the
  // tile of the cell of its start (FixedBars::cell_tile), move_may_touch_tile, lane
  // by lane the same compares (cell_of's clamps; std::min and std::max as written).
  [[gnu::always_inline]] static unsigned may_meet_bars(const FixedBars& f, V x0, V y0, V x, V y, V vx, V vy) {
    const V still = O::set1(kZeroVelocity);
    const unsigned rest = O::lanes(O::m_and(O::lt(O::abs(vx), still), O::lt(O::abs(vy), still)));
    alignas(64) double c[kW];
    O::store(c, O::mul(O::sub(x0, O::set1(f.cell_x0)), O::set1(f.cell_scale)));
    const double last = static_cast<double>(f.cell_count - 1);
    alignas(64) std::int64_t cell[kW];
    static_assert(FixedBars::kTileStride == 8);
    for (int l = 0; l < kW; ++l) { // cell_of: 0 below the first cell (and NaN), the last above it
      const double k = c[l] >= last ? last : c[l] > 0.0 ? c[l] : 0.0;
      cell[l] = 8 * static_cast<std::int64_t>(k);
    }
    const double* tile = f.cell_tile.data();
    const V t0 = O::gather64(tile + 0, cell), t1 = O::gather64(tile + 1, cell);
    const V t2 = O::gather64(tile + 2, cell), t3 = O::gather64(tile + 3, cell);
    const V t4 = O::gather64(tile + 4, cell), t5 = O::gather64(tile + 5, cell);
    const V lo = O::select(O::lt(x, x0), x, x0), hi = O::select(O::lt(x0, x), x, x0); // std::min, std::max (x0, x)
    const V ylo = O::select(O::lt(y, y0), y, y0), yhi = O::select(O::lt(y0, y), y, y0);
    const unsigned inside = O::lanes(O::m_and(O::ge(lo, t0), O::le(hi, t1)));
    const unsigned touch = O::lanes(O::m_and(O::m_and(O::ge(hi, t2), O::le(lo, t3)), O::m_and(O::ge(yhi, t4), O::le(ylo, t5))));
    return ~rest & (~inside | touch) & 0xffu;
  }

  // One frame's physics and wave advance of groups [g0, g0 + N) (the same links),
  // side by side: N independent chains for the processor to overlap.
  template <int N, bool Bars>
  [[gnu::always_inline]] static void step_groups(Data& d, int g0) {
    // Each group's points from one pointer: point p's rows x, y, vx, vy at
    // p * kPointBytes + 0, 64, 128, 192 (point_row), so an end's four rows are
    // constant displacements from one address.
    char* P[N];
    const double* target[N];
    V springyness[N];
    for (int n = 0; n < N; ++n) {
      P[n] = reinterpret_cast<char*>(d.point_row(g0 + n, 0, 0));
      target[n] = d.link_row(g0 + n, 2, 0);
      springyness[n] = O::load(d.world_row(g0 + n, Data::kSpringyness));
    }
    const auto row = [](char* point, int k) __attribute__((always_inline)) {
      return reinterpret_cast<double*>(point + k * static_cast<int>(kW * sizeof(double)));
    };
    const V zero = O::set1(0.0);
    // The groups' links and masses side by side, each group's in its own order.
    const std::uint32_t* ends[N];
    std::uint32_t mass_bytes[N]; // an end below this is a mass (fixed nodes come after)
    int group_links[N], group_masses[N];
    int links = 0, masses = 0;
    for (int n = 0; n < N; ++n) {
      const Group& G = d.groups[static_cast<std::size_t>(g0 + n)];
      ends[n] = G.link_ends.data();
      group_links[n] = G.links;
      group_masses[n] = G.masses;
      mass_bytes[n] = static_cast<std::uint32_t>(G.masses) * Data::kPointBytes;
      links = std::max(links, G.links);
      masses = std::max(masses, G.masses);
    }
    // The sine schedule in locals: the vector stores below may alias Data's fields
    // (__m256d is may_alias), which would otherwise be reloaded and stored per link.
    int sine_credit = d.sine_credit, sines_done = d.sines_done;
    const int sine_rows = d.sine_rows, total_links = d.total_links;
    const std::pair<const double*, double*>* sine_work = d.sine_work.data();
    unsigned far_lanes = 0;
    // Links in file order (step.cpp apply_links): each impulse goes into both
    // ends' velocities at once; a zero-length link adds nothing (masked).
    for (int j = 0; j < links; ++j) {
      // The next frame's sines, spread over the link passes: sine_rows / total_links of them a link.
      for (sine_credit += sine_rows; sine_credit >= total_links; sine_credit -= total_links, ++sines_done) {
        unsigned far = 0;
        const auto& [in, out] = sine_work[sines_done];
        java_sine::java_sin<O, 1>(in, out, &far);
        far_lanes |= far;
      }
#pragma GCC unroll 4
      for (int n = 0; n < N; ++n) {
        if (j >= group_links[n]) continue;
        const std::uint32_t ea = ends[n][2 * j], eb = ends[n][2 * j + 1];
        char* const pa = P[n] + ea;
        char* const pb = P[n] + eb;
        const V dx = O::sub(O::load(row(pb, 0)), O::load(row(pa, 0)));
        const V dy = O::sub(O::load(row(pb, 1)), O::load(row(pa, 1)));
        const V length = simd_rules::length<O>(dx, dy);
        const V c = simd_rules::impulse_factor<O>(springyness[n], length, O::load(target[n] + static_cast<std::size_t>(j) * kW));
        const V px = O::mul(c, dx), py = O::mul(c, dy);
        // Without masked arithmetic (AVX2) a masked add is an add and a blend: where
        // every lane's link has a length (all but always) the plain add and subtract
        // give the same bits.
        const M zero_length = O::eq(length, zero);
        if (!O::kMaskedArithmetic && !O::any(zero_length)) [[likely]] {
          if (ea < mass_bytes[n]) {
            O::store(row(pa, 2), O::add(O::load(row(pa, 2)), px));
            O::store(row(pa, 3), O::add(O::load(row(pa, 3)), py));
          }
          if (eb < mass_bytes[n]) {
            O::store(row(pb, 2), O::sub(O::load(row(pb, 2)), px));
            O::store(row(pb, 3), O::sub(O::load(row(pb, 3)), py));
          }
          continue;
        }
        const M acts = O::ne(length, zero);
        if (ea < mass_bytes[n]) {
          O::store(row(pa, 2), O::add_where(acts, O::load(row(pa, 2)), px));
          O::store(row(pa, 3), O::add_where(acts, O::load(row(pa, 3)), py));
        }
        if (eb < mass_bytes[n]) {
          O::store(row(pb, 2), O::sub_where(acts, O::load(row(pb, 2)), px));
          O::store(row(pb, 3), O::sub_where(acts, O::load(row(pb, 3)), py));
        }
      }
    }
    d.sine_credit = sine_credit;
    d.sines_done = sines_done;
    d.far_lanes |= far_lanes;
    // Masses in order (step.cpp move_masses); autoreverse lane by lane in mass order.
    simd_rules::MassParams<O> params[N];
    bool hit_wall[N] = {};
    for (int n = 0; n < N; ++n) {
      const int g = g0 + n;
      const double* const world = d.world_row(g, 0);
      const auto at = [world](int k) __attribute__((always_inline)) { return O::load(world + static_cast<std::size_t>(k) * kW); };
      params[n] = {at(Data::kGravityStep), at(Data::kKeep), at(Data::kWidth), at(Data::kHeight), at(Data::kFs), at(Data::kRs)};
    }
    // Where this frame's walls were out of reach, the ceiling and side tests
    // would change nothing (the same bits without them); whether they are next
    // frame, from the new positions.
    bool far[N];
    M inside[N];
    V left[N], right[N], top[N];
    for (int n = 0; n < N; ++n) {
      const int g = g0 + n;
      far[n] = d.walls_far[static_cast<std::size_t>(g)] != 0;
      inside[n] = O::m_all();
      const double* const world = d.world_row(g, 0);
      left[n] = O::load(world + static_cast<std::size_t>(Data::kLeft) * kW);
      right[n] = O::load(world + static_cast<std::size_t>(Data::kRight) * kW);
      top[n] = O::load(world + static_cast<std::size_t>(Data::kTop) * kW);
    }
    // With bars: each mass's move kept (its start and the velocity it takes) for bar_pass.
    [[maybe_unused]] bool bars[N] = {};
    if constexpr (Bars) {
      for (int n = 0; n < N; ++n) bars[n] = d.groups[static_cast<std::size_t>(g0 + n)].bars;
    }
    for (int i = 0; i < masses; ++i) {
#pragma GCC unroll 4
      for (int n = 0; n < N; ++n) {
        if (i >= group_masses[n]) continue;
        [[maybe_unused]] V move_v[2];
        V* const point = reinterpret_cast<V*>(P[n] + static_cast<std::size_t>(i) * Data::kPointBytes);
        V &x = point[0], &y = point[1], &vx = point[2], &vy = point[3];
        [[maybe_unused]] const V x0 = x, y0 = y;
        if (far[n]) {
          simd_rules::move_mass<O, true, true, false, false>(params[n], x, y, vx, vy, Bars ? move_v : nullptr);
        }
        const simd_rules::SideHits<O> hits =
            far[n] ? simd_rules::SideHits<O>{O::m_none(), O::m_none()}
                   : simd_rules::move_mass<O, true, true, true, true>(params[n], x, y, vx, vy, Bars ? move_v : nullptr);
        if constexpr (Bars) {
          if (bars[n]) {
            O::store(d.move_row(g0 + n, 0, i), x0);
            O::store(d.move_row(g0 + n, 1, i), y0);
            O::store(d.move_row(g0 + n, 2, i), move_v[0]);
            O::store(d.move_row(g0 + n, 3, i), move_v[1]);
            d.bar_due[d.groups[static_cast<std::size_t>(g0 + n)].due_at + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(
                may_meet_bars(d.group_bars[static_cast<std::size_t>(g0 + n)], x0, y0, x, y, move_v[0], move_v[1]));
          }
        }
        if (!Bars || !bars[n]) { // a group with bars tests every wall next frame anyway (below)
          inside[n] = O::m_and(inside[n], O::m_and(O::gt(x, left[n]), O::m_and(O::lt(x, right[n]), O::lt(y, top[n]))));
        }
        if (O::any(hits.hit)) [[unlikely]] {
          hit_wall[n] = true;
          const int g = g0 + n;
          double* mode = d.world_row(g, Data::kMode);
          const unsigned hit = O::lanes(hits.hit), left_hit = O::lanes(hits.left);
          for (int l = 0; l < kW; ++l) {
            if (!((hit >> l) & 1)) continue;
            State& s = *d.lane_state[static_cast<std::size_t>(g) * kW + l];
            WaveDirection m = static_cast<WaveDirection>(static_cast<int>(mode[l]));
            rules::autoreverse_on_wall_hit((left_hit >> l) & 1 ? SideWall::Left : SideWall::Right,
                                           d.autoreverse[static_cast<std::size_t>(g) * kW + l] != 0, m, s.last_side_wall);
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
        d.bar_pass(g0 + n);
        inside[n] = O::m_none();
      }
    }
    for (int n = 0; n < N; ++n) d.walls_far[static_cast<std::size_t>(g0 + n)] = O::lanes(inside[n]) == 0xffu ? 1 : 0;
    // The wave advance after the physics (docs/physics.md, "The wave"): the
    // predicted phase where no lane hit a side wall (the same operations on the
    // same operands). Where a direction turned, the next frame's sines again once
    // the frame is done (step_frame).
    for (int n = 0; n < N; ++n) {
      const int g = g0 + n;
      const double* expected = d.predicted.data() + static_cast<std::size_t>(g) * kW;
      if (d.groups[static_cast<std::size_t>(g)].columns > 0 && !hit_wall[n]) {
        O::store(d.world_row(g, Data::kPhase), O::load(expected));
        continue;
      }
      const V phase = simd_rules::advance_wave_phase<O>(O::load(d.world_row(g, Data::kPhase)), O::load(d.world_row(g, Data::kSpeed)),
                                                        O::load(d.world_row(g, Data::kMode)));
      O::store(d.world_row(g, Data::kPhase), phase);
      if (d.groups[static_cast<std::size_t>(g)].columns == 0) continue;
      d.redo[static_cast<std::size_t>(g)] = O::bits_differ(phase, O::load(expected)) ? 1 : 0;
    }
  }

  // One frame of every group: this frame's targets from the sines computed for it
  // and the arguments of the next frame's at the phase each wave will have if no
  // direction turns; the link and mass passes, two groups at a time, with those
  // sines spread over them; the sines again of a group whose wave turned (or all,
  // where they were not computed in the passes).
  static void step_frame(Data& d) {
    d.sine_work.clear();
    for (int g = 0; g < static_cast<int>(d.groups.size()); ++g) {
      const Group& G = d.groups[static_cast<std::size_t>(g)];
      if (G.columns == 0) continue;
      if (d.packed[static_cast<std::size_t>(g)] != 0 && !(G.jittered && packed_jitter_hits(d, g))) {
        targets_from_packed(d, g); // the lanes' sines as computed: each column's in every lane
      } else {
        if (d.packed[static_cast<std::size_t>(g)] != 0) unpack_sines(d, g);
        if (G.jittered) [[unlikely]] jitter_sines(d, g);
        targets_from_sines(d, g);
      }
      arguments_for(d, g,
                    simd_rules::advance_wave_phase<O>(O::load(d.world_row(g, Data::kPhase)), O::load(d.world_row(g, Data::kSpeed)),
                                                      O::load(d.world_row(g, Data::kMode))),
                    false);
      if (d.inline_sines) queue_sines(d, g);
    }
    pool_arguments_rows(d, 0, static_cast<std::size_t>(d.pool_rows));
    if (d.inline_sines) {
      for (int r = 0; r < d.pool_rows; ++r) {
        d.sine_work.emplace_back(d.pool_arguments.data() + static_cast<std::size_t>(r) * kW,
                                 d.pool_sines.data() + static_cast<std::size_t>(r) * kW);
      }
    }
    d.sine_rows = static_cast<int>(d.sine_work.size());
    d.sines_done = 0;
    d.sine_credit = 0;
    d.far_lanes = 0;
    for (std::size_t k = 0; k < d.schedule.size(); ++k) {
      static_assert(lockstep_detail::kSideBySide == 2);
      const auto [g, n] = d.schedule[k];
      if (d.schedule_bars[k] != 0) [[unlikely]] {
        if (n == 2) {
          step_groups<2, true>(d, g);
        } else {
          step_groups<1, true>(d, g);
        }
      } else if (n == 2) {
        step_groups<2, false>(d, g);
      } else {
        step_groups<1, false>(d, g);
      }
    }
    assert(d.sines_done == d.sine_rows);
    const bool all_again = !d.inline_sines || d.far_lanes != 0;
    for (int g = 0; g < static_cast<int>(d.groups.size()); ++g) {
      if (d.groups[static_cast<std::size_t>(g)].columns > 0 && (all_again || d.redo[static_cast<std::size_t>(g)] != 0)) sines_now(d, g);
      d.redo[static_cast<std::size_t>(g)] = 0;
    }
  }

  static LockstepEntry entry() { return {&step_frame, &sines_now}; }
};

} // namespace
} // namespace soda
