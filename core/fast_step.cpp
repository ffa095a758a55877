#include "fast_step.hpp"

#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <map>
#include <new>
#include <stdexcept>
#include <vector>

#include "aligned_vector.hpp"
#include "bits.hpp"
#include "exact_sines.hpp"
#include "fused_scene.hpp"
#include "physics_rules.hpp"
#include "simd_ops.hpp"
#include "simd_rules.hpp"

namespace soda {

namespace {

// move_mass_block is instantiated implicitly with the default target and always
// inlined into the kernels of each level: no call ever crosses the vector ABI that
// this warning is about.
#pragma GCC diagnostic ignored "-Wpsabi"

using simd::Avx2Ops;
using simd::Avx512Ops;
using simd::kMaxWidth;
using simd::Sse2Ops;

// Loading W pairs and unpacking them puts item kLaneLink(W, l) of the W items in
// lane l (W = 8: 0 4 1 5 2 6 3 7); store_pairs undoes it. Per-lane constants
// (link targets) are stored in this lane order.
constexpr int kLaneLink(int w, int lane) { return lane % 2 == 0 ? lane / 2 : w / 2 + lane / 2; }

// Masses whose impulses are summed side by side (interleaved scalar pair adds).
constexpr int kGatherGroup = 8;

int width_of(SimdLevel level) {
  switch (level) {
    case SimdLevel::Avx512: return 8;
    case SimdLevel::Avx2: return 4;
    default: return 2;
  }
}

} // namespace

// ---------------------------------------------------------------------------
// The scene's data.
// ---------------------------------------------------------------------------

struct FusedScene::Data {
  FastStepOptions options;
  SimdLevel simd = SimdLevel::Sse2;
  int W = 2;

  // One entry per model of the scene, in the order given.
  struct Creature {
    const Model* model = nullptr;
    SceneNeeds needs;
    int mass_base = 0;              ///< working index of its first mass
    std::vector<int> work_of_point; ///< [point_count] model point -> working index
    int group_base = 0, groups = 0; ///< its distinct muscle phases in group_phase
    WaveDirection rows_mode = WaveDirection::Forward; ///< the direction its rows assume
    std::uint64_t targets_phase_bits = 0;             ///< the phase its targets are for
  };
  std::vector<Creature> creatures;
  bool any_wave = false, any_gravity = false;
  BarKind bars = BarKind::None; ///< only with a single model

  // Working points, as (x, y) pairs: masses [0, nm) (the creatures' masses one
  // creature after the other), padding masses [nm, nm_pad) (at rest at (0, 0);
  // their results are never read), fixed nodes [nm_pad, nm_pad + nf), and one
  // spare pair.
  int nm = 0, nm_pad = 0, nf = 0, sink = 0;
  AVec<double> pos, vel;  ///< [2*(sink+1)] x, y / vx, vy pairs
  AVec<double> old_pos;   ///< [2*nm_pad] positions before the move (bars)
  AVec<double> side;      ///< [2*nm_pad] side wall hit this frame (-1, 0, +1), twice per mass
  // Per-mass parameters, per block of W masses in kLaneLink order (as load_pairs
  // puts the masses in lanes): each mass's own creature's values.
  AVec<double> mass_gd;        ///< gravity * direction, as rules::apply_gravity forms it
  AVec<double> mass_keep;      ///< 1 - friction, as rules::friction_factor forms it
  AVec<double> mass_width, mass_height, mass_fs, mass_rs;

  // Links that can act (a free end) in the order the link pass computes them
  // (arrange_links), with dummy links from a point to itself (length 0: no
  // impulse) where a block needs one, padded to a multiple of kMaxWidth likewise.
  struct Acting {
    int creature = -1;    ///< -1: a dummy link from point `dummy` to itself
    int link = 0;         ///< index in its model
    bool swapped = false; ///< end A is the file's end b (arrange_links: exact)
    bool wave = false;    ///< a wave muscle (its target changes per frame)
    int dummy = 0;        ///< working index of a dummy's point
  };
  int nl = 0, nl_pad = 0; ///< link slots in use (links and dummies), padded
  std::vector<std::uint32_t> la, lb; ///< [nl_pad] 2 * working index of the ends (offset in pos)
  // Per block of W link slots: -1, or b when the A ends of the block are the W
  // masses [W*b, W*b + W) in slot order, loaded as two whole vectors.
  std::vector<std::int32_t> a_block;
  bool points_in_registers = false;  ///< the link pass keeps the points in registers (Avx512Ops)
  AVec<std::int64_t> la_point, lb_point; ///< [nl_pad] working index of the ends, lane order (registers only)
  // Impulses as (x, y) pairs: pair k = end A of acting link k (+c*d), pair
  // nl_pad + k = end B (-c*d), pair 2*nl_pad = (-0, -0), the identity of +.
  AVec<double> imp; ///< [4*nl_pad + 2]
  std::int32_t identity_pair = 0;
  // Impulse pairs per mass in file order of its model's links, by groups of
  // kGatherGroup consecutive masses (masses are numbered by degree): group b,
  // round r, lane l at the next slots; lists shorter than the group's longest
  // are padded with identity_pair (fixed trip counts: no branch mispredictions).
  std::vector<std::uint32_t> slots;      ///< double offsets into imp (2 * pair)
  std::vector<std::int32_t> block_rounds; ///< per gather group
  std::vector<std::int32_t> slot_of_mass; ///< [nm] first slot of mass i; its rounds stride kGatherGroup
  std::vector<std::int32_t> rounds_of_mass;
  // The whole frame in registers (AVX-512; at most 16 points and 32 link slots,
  // no bars): register_chunk. Points sit as load_pairs puts them (lane l of block
  // r: working point 8r + kLaneLink(8, l)), impulses as the link pass computes them.
  bool frame_in_registers = false;
  AVec<std::int64_t> rf_end_a, rf_end_b; ///< [nl_pad] lane order: register lane of each end
  // Per mass block and round of its sums: which impulse each lane adds (a lane of
  // the link blocks 0-1 by a two-register permute, of block 2-3 where the bit of
  // rf_upper is set), with which sign (-0.0: an end B), or nothing (rf_valid clear:
  // the lane adds -0.0, sign -0.0).
  AVec<std::int64_t> rf_index; ///< [8 per round]
  AVec<double> rf_sign;        ///< [8 per round]
  std::vector<std::uint8_t> rf_upper, rf_valid;
  std::vector<int> rf_rounds; ///< [mass blocks]
  std::vector<std::uint8_t> rf_real; ///< [link blocks] lanes of real links (not dummies, not padding)
  AVec<double> target;    ///< [nl_pad] desired length D, per block in kLaneLink order
  AVec<double> link_k;    ///< [nl_pad] springyness of the link's model, same order
  // -1 where the link is computed from its end b (Acting::swapped), else +1, same
  // order. Its impulse must come from the file's difference b - a, which for such
  // a link is the pass's a - b: the pass's b - a negated, except where both are +0
  // (equal coordinates), and that +0's sign reaches a velocity of -0. Each end
  // then takes its pair by the file's ends (the slots).
  AVec<double> link_swap;

  // Wave muscles (muscles whose power Aw*Am is not 0), first in the link order,
  // so target slots [0, nwm_pad) are the ones that change per frame:
  // target = rest * (1 + power * sine[group]) (springs sharing those blocks have
  // power 0: rest * (1 + +-0) = rest exactly).
  int nwm = 0, nwm_pad = 0;
  std::vector<double> tm_rest, tm_power; ///< [nwm_pad] rest length, Aw*Am
  std::vector<std::int32_t> tm_group;    ///< [nwm_pad] index into a row of sines
  // Rows of at most kRegisterPoints sines (Avx512Ops) sit in two registers while
  // the targets are formed: a muscle's sine is then one permute, not a gather.
  bool sines_in_registers = false;
  AVec<std::int64_t> tm_group_lane;      ///< [nwm_pad] tm_group as permute indices
  std::vector<double> group_phase;       ///< distinct muscle phases, per creature
  int groups = 0;                        ///< all creatures'
  // Sines for this frame and the next rows - 1, computed for the phases each
  // creature's wave will have if its direction does not change (fill_rows). A row
  // is used only while every creature's phase is the row's, bit for bit; else all
  // rows are refilled.
  int rows = 1, row_count = 0, row_next = 0;
  int current_row = -1;                       ///< the row the targets were computed from
  bool targets_valid = false;
  bool rows_standing = false; ///< no wave moves in these rows: every row is row 0
  // While rows_synced, every wave creature's phase is its rows' phase at row_next
  // and its direction the rows' (so it was when the row was checked or filled, and
  // each frame's advance is the next row's phase): a frame takes the next row and
  // the advance from it without comparing every creature's phase. leave_rows ends
  // it wherever a direction may change, another state may come in, or the rows run
  // out, and notes the phases the targets are for (what the check compares with).
  bool rows_synced = false;
  std::vector<int> wave_creatures;  ///< creatures with a wave muscle
  std::vector<int> still_creatures; ///< the others (their phases still advance)
  long long sines = 0;
  SinFn sine_fn = nullptr; ///< exact_sin_fn of the level (soda::sine alone without vector_sines), chosen at build
  // Wave states (fill_rows): creatures whose waves are in the same state (phase
  // bits, direction, speed bits) have the same rows of phases, and a muscle phase
  // they share then gives bit-identical sine arguments: each distinct (state,
  // muscle phase) pair is one argument per row (number_arguments).
  int uphases = 0;                   ///< distinct muscle phases of the whole scene
  std::vector<int> group_u;          ///< [groups] index of the group's phase among them
  int states = 0;                    ///< wave states of this numbering
  std::vector<int> fill_slot;        ///< [creatures] wave state of each wave creature
  std::vector<int> slot_leader;      ///< [creatures] first creature of each wave state
  bool numbering_valid = false;      ///< the arguments below are numbered for fill_slot
  int distinct = 0;                  ///< distinct arguments per row
  std::vector<int> su_index;         ///< [creatures * uphases] distinct argument of (state, phase), -1: none
  std::vector<int> dist_key;         ///< [groups] (state, phase) key of each distinct argument
  std::vector<int> state_first;      ///< [states + 1] first argument of each wave state
  std::vector<double> dist_phase;    ///< [groups, padded] the muscle phase of each distinct argument
  std::vector<int> group_arg;        ///< [groups] distinct argument of each group
  /// [(rows + 1) * creatures] wave state k's phase in row r at r * creatures + k;
  /// row r + 1 holds rules::advance_wave_phase of row r (the last one too)
  std::vector<double> row_phase;
  AVec<double> dist_arg, dist_sin;   ///< [rows * distinct, padded] the arguments of each row, their sines
  AVec<double> row_sin;              ///< [rows * groups, padded] sines by group (remapped, in registers)
  // Where the targets read their sines: the row of a frame starts at sine_rows +
  // row * sine_stride and muscle slot q's sine is at sine_index[q] in it. Either
  // the sines by group (dist_sin when every argument is distinct, else row_sin;
  // sine_index = tm_group), or, after a numbering that shared arguments between
  // creatures, the distinct sines themselves (sine_index = tm_dist, group_arg of
  // tm_group[q]): copying them out per group and row cost more than the targets (a
  // GA scene: 13 rows of 74 groups from 56 distinct sines). Scenes with their sines
  // in registers read by group (muscle_targets permutes by group).
  double* sine_rows = nullptr;
  int sine_stride = 0;
  const std::int32_t* sine_index = nullptr;
  std::vector<std::int32_t> tm_dist; ///< [nwm_pad]
  AVec<std::int64_t> tm_dist_lane;   ///< [nwm_pad] tm_dist as permute indices
  const std::int64_t* sine_lane = nullptr; ///< sine_index as permute indices (tm_group_lane or tm_dist_lane)

  std::vector<int> bar_a, bar_b; ///< 2 * working index (offset of x in pos), file order

  std::vector<KernelChoice> used;
  KernelChoice last;

  [[nodiscard]] double& px(int w) { return pos[2 * static_cast<std::size_t>(w)]; }
  [[nodiscard]] double& py(int w) { return pos[2 * static_cast<std::size_t>(w) + 1]; }
  [[nodiscard]] double& pvx(int w) { return vel[2 * static_cast<std::size_t>(w)]; }
  [[nodiscard]] double& pvy(int w) { return vel[2 * static_cast<std::size_t>(w) + 1]; }

  void build(const std::vector<const Model*>& models, long long budget, FastStepOptions opt);
  void arrange_links(std::vector<Acting>& acting);
  void order_by_need(std::vector<Acting>& acting);
  /// Working index of end a (or b) of acting link l of a creature: below nm for a
  /// mass, from nm_pad on for a fixed node.
  [[nodiscard]] int working_end(const Acting& l, bool b_end) const {
    const Creature& cr = creatures[l.creature];
    const Model& m = *cr.model;
    return cr.work_of_point[b_end ? m.link_b[l.link] : m.link_a[l.link]];
  }
  /// Whether whole frames of this scene with `links` link slots run in registers
  /// (register_chunk): AVX-512, at most 16 points and 32 link slots, no bars.
  [[nodiscard]] bool frames_fit_registers(int links) const {
    return options.register_frames && simd == SimdLevel::Avx512 && nm_pad + nf <= Avx512Ops::kRegisterPoints &&
           links <= 4 * kMaxWidth && bars == BarKind::None && !options.force_ordered;
  }
  void load_state(State* const* st);
  void store_state(State* const* st);
  // Muscle targets: rules::muscle_target_length split in two so that the sine is
  // shared, sine = sin(2pi*(phi_m - phi_w)) once per distinct phase per creature,
  // then per muscle rest * (1 + (Aw*Am) * sine) with the same operations in the same
  // order (targets_kernel). row_for_frame returns this frame's row of sines, filling
  // the rows when the waves left them, or nullptr when no wave moved (the targets
  // stand). Always inlined, so that the frame in registers (register_chunk) calls nothing
  // but fill_rows: a call spills every vector register.
  [[gnu::always_inline]] const double* row_for_frame(State* const* st) {
    if (rows_synced && row_next < row_count) {
      if (rows_standing && targets_valid) return nullptr;
      current_row = row_next++;
      targets_valid = true;
      return sine_rows + static_cast<std::size_t>(current_row) * sine_stride;
    }
    leave_rows(); // the rows ran out: targets_phase_bits must say what the targets are for
    bool changed = !targets_valid;
    for (std::size_t k = 0; k < wave_creatures.size() && !changed; ++k) {
      const int c = wave_creatures[k];
      changed = bits_of(st[c]->wave_phase) != creatures[c].targets_phase_bits;
    }
    if (!changed) return nullptr;
    bool row_usable = row_next < row_count;
    for (std::size_t k = 0; k < wave_creatures.size() && row_usable; ++k) {
      const int c = wave_creatures[k];
      row_usable = bits_of(st[c]->wave_phase) == bits_of(row_phase[row_at(c, row_next)]) &&
                   st[c]->wave_mode == creatures[c].rows_mode;
    }
    if (!row_usable) fill_rows(st);
    current_row = row_next++;
    targets_valid = true;
    rows_synced = true;
    return sine_rows + static_cast<std::size_t>(current_row) * sine_stride;
  }
  /// Index of wave creature c's phase in row r of row_phase (its advance: row r + 1).
  [[nodiscard]] std::size_t row_at(int c, int r) const {
    return static_cast<std::size_t>(r) * creatures.size() + static_cast<std::size_t>(fill_slot[c]);
  }
  /// Whether creatures a and b have their waves in the same state (phase and speed
  /// bit for bit, same direction): the same rows of phases.
  [[nodiscard]] bool same_wave(State* const* st, int a, int b) const {
    return bits_of(st[a]->wave_phase) == bits_of(st[b]->wave_phase) && st[a]->wave_mode == st[b]->wave_mode &&
           bits_of(creatures[a].model->wave_speed) == bits_of(creatures[b].model->wave_speed);
  }
  /// Ends rows_synced (see there), noting the phases the targets are for.
  void leave_rows() {
    if (!rows_synced) return;
    rows_synced = false;
    for (int c : wave_creatures) creatures[c].targets_phase_bits = bits_of(row_phase[row_at(c, current_row)]);
  }
  void update_targets(State* const* st);
  void fill_rows(State* const* st);
  void number_arguments(State* const* st);
  // The wave advance of this frame: already computed for the current row (same
  // rule, same inputs) when the phase and direction are still the row's.
  [[nodiscard]] [[gnu::always_inline]] double advance_phase(int c, const State& st) const {
    const Creature& cr = creatures[c];
    if (current_row >= 0 && cr.groups > 0) {
      const std::size_t at = row_at(c, current_row);
      if (bits_of(st.wave_phase) == bits_of(row_phase[at]) && st.wave_mode == cr.rows_mode) {
        return row_phase[row_at(c, current_row + 1)];
      }
    }
    return rules::advance_wave_phase(st.wave_phase, cr.model->wave_speed, st.wave_mode);
  }
  [[gnu::always_inline]] void advance_waves(State* const* st) {
    if (rows_synced) {
      for (int c : wave_creatures) st[c]->wave_phase = row_phase[row_at(c, current_row + 1)];
      for (int c : still_creatures) {
        st[c]->wave_phase = rules::advance_wave_phase(st[c]->wave_phase, creatures[c].model->wave_speed, st[c]->wave_mode);
      }
      return;
    }
    for (std::size_t c = 0; c < creatures.size(); ++c) st[c]->wave_phase = advance_phase(static_cast<int>(c), *st[c]);
  }
  void ordered_frame(State& s);
  void replay_side_hits(State* const* st);
  void bars_pass();
  void ordered_masses(State& s);
  void collide_with_bars(int i, double x0, double y0);
  void record(const KernelChoice& k);
};

// ---------------------------------------------------------------------------
// Kernels. The formulas are those of physics_rules.hpp (and of the link loop of
// step.cpp), lane by lane, in the same operation order; the comment on each says
// which rule it is. tests/test_fast_step.cpp and tests/test_batch_step.cpp check
// the results bit for bit.
// ---------------------------------------------------------------------------
namespace {

using Impl = FusedScene::Data;

/// The links (spec 5.2; step.cpp apply_links): impulses of all acting links in
/// SIMD from the positions (which do not change while links act). With
/// PointRegisters (Avx512Ops, small scenes) the ends' coordinates come from
/// registers holding every point (O::load_points, O::point).
template <class O, bool PointRegisters>
void link_kernel(Impl& s) {
  using V = typename O::V;
  const double* pos = s.pos.data();
  const double* target = s.target.data();
  double* imp_a = s.imp.data();
  double* imp_b = s.imp.data() + 2 * static_cast<std::size_t>(s.nl_pad);
  const std::uint32_t* la = s.la.data();
  const std::uint32_t* lb = s.lb.data();
  const std::int32_t* a_block = s.a_block.data();
  const double* link_k = s.link_k.data();
  const double* link_swap = s.link_swap.data();
  const V zero = O::set1(0.0);
  const V neg_zero = O::set1(-0.0);
  [[maybe_unused]] V x[2], y[2];
  if constexpr (PointRegisters) O::load_points(pos, x, y);
  const int n = (s.nl + O::W - 1) / O::W * O::W;
  for (int i = 0; i < n; i += O::W) {
    V xa, ya, xb, yb;
    if constexpr (PointRegisters) {
      const std::int64_t* pa = s.la_point.data() + i;
      const std::int64_t* pb = s.lb_point.data() + i;
      xa = O::point(x, pa);
      ya = O::point(y, pa);
      xb = O::point(x, pb);
      yb = O::point(y, pb);
    } else {
      if (const int blk = a_block[i / O::W]; blk >= 0) {
        O::load_pairs(pos + 2 * O::W * blk, xa, ya);
      } else {
        O::load_pairs_at(pos, la + i, xa, ya);
      }
      O::load_pairs_at(pos, lb + i, xb, yb);
    }
    const V dx = O::sub(xb, xa);
    const V dy = O::sub(yb, ya);
    const V length = simd_rules::length<O>(dx, dy);
    const V c = simd_rules::impulse_factor<O>(O::load(link_k + i), length, O::load(target + i));
    // The impulse from the file's difference b - a (link_swap; the slots give each
    // end its sign).
    const auto swapped = O::lt(O::load(link_swap + i), zero);
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

/// The mass step of one block of W masses starting at working index i (spec 5.3),
/// after their impulses: gravity, friction with the syrup limit, rest test, move,
/// container walls, each mass with its own creature's parameters. (x, y) are the
/// positions before the move and (vx, vy) the velocities after the impulses; all
/// four are replaced by the stored results. Side-wall hits go to s.side and
/// any_side.
template <class O, bool Gravity, bool Floor, bool Ceiling, bool Sides>
[[gnu::always_inline]] inline void move_mass_block(Impl& s, int i, typename O::V& x, typename O::V& y, typename O::V& vx,
                            typename O::V& vy, typename O::M& any_side) {
  using V = typename O::V;
  const simd_rules::MassParams<O> params{O::load(s.mass_gd.data() + i),    O::load(s.mass_keep.data() + i),
                                         O::load(s.mass_width.data() + i), O::load(s.mass_height.data() + i),
                                         O::load(s.mass_fs.data() + i),    O::load(s.mass_rs.data() + i)};
  const simd_rules::SideHits<O> sides = simd_rules::move_mass<O, Gravity, Floor, Ceiling, Sides>(params, x, y, vx, vy);
  // s.side is all zero between frames (replay_side_hits clears what it reads):
  // only a block with a hit writes it.
  if (O::any(sides.hit)) [[unlikely]] {
    const V h = O::select(O::m_and(sides.hit, sides.left), O::set1(-1.0), O::select(sides.hit, O::set1(1.0), O::set1(0.0)));
    O::store_pairs(s.side.data() + 2 * i, h, h);
    any_side = O::m_or(any_side, sides.hit);
  }
}

/// The masses (spec 5.3) in SIMD over masses: first each mass's impulses added to
/// its velocity in file order of the links (the order of the additions into one
/// velocity is the reference's), then move_mass_block. Returns whether some mass
/// responded to a side wall (autoreverse is then replayed in mass order).
///
/// The sums go by groups of kGatherGroup consecutive masses (numbered by degree at
/// build), one round per impulse; slots hold double offsets (2 * pair index), so
/// each addition is one load and one add, and the sums stay in registers for the
/// rest of the step. (Pairs of masses in 256-bit additions measured 30 % slower:
/// the inserts cost more than the additions saved.)
template <class O, bool Gravity, bool Floor, bool Ceiling, bool Sides>
bool mass_kernel(Impl& s) {
  using V = typename O::V;
  using M = typename O::M;
  double* pos = s.pos.data();
  double* vel = s.vel.data();
  M any_side = O::m_none();
  const double* imp = s.imp.data();
  const std::uint32_t* sl = s.slots.data();
  const int groups = s.nm_pad / kGatherGroup;
  for (int g = 0; g < groups; ++g) {
    __m128d acc[kGatherGroup];
    for (int l = 0; l < kGatherGroup; ++l) acc[l] = _mm_load_pd(vel + 2 * (g * kGatherGroup + l));
    for (int r = s.block_rounds[g]; r > 0; --r, sl += kGatherGroup) {
      // Two offsets per 64-bit load: the loads, not the additions, limit this loop.
      for (int l = 0; l < kGatherGroup; l += 2) {
        std::uint64_t two;
        std::memcpy(&two, sl + l, sizeof two);
        acc[l] = _mm_add_pd(acc[l], _mm_load_pd(imp + static_cast<std::uint32_t>(two)));
        acc[l + 1] = _mm_add_pd(acc[l + 1], _mm_load_pd(imp + (two >> 32)));
      }
    }
#pragma GCC unroll 4
    for (int j = 0; j < kGatherGroup; j += O::W) {
      const int i = g * kGatherGroup + j;
      V vx, vy, x, y;
      O::pairs_to_xy(acc + j, vx, vy);
      O::load_pairs(pos + 2 * i, x, y);
      if (!s.bar_a.empty()) O::store_pairs(s.old_pos.data() + 2 * i, x, y);
      move_mass_block<O, Gravity, Floor, Ceiling, Sides>(s, i, x, y, vx, vy, any_side);
      O::store_pairs(pos + 2 * i, x, y);
      O::store_pairs(vel + 2 * i, vx, vy);
    }
  }
  return O::any(any_side);
}

/// Muscle targets of the W target slots from q from their sines: rest * (1 +
/// (Aw*Am) * sine), the second half of rules::muscle_target_length.
template <class O>
[[gnu::always_inline]] inline typename O::V muscle_target(const Impl& s, int q, typename O::V sine) {
  return simd_rules::muscle_target<O>(O::loadu(s.tm_rest.data() + q), O::loadu(s.tm_power.data() + q), sine);
}

/// The same from the row of sines held in two registers (sines_in_registers: one
/// permute per muscle, not a gather).
template <class O>
[[gnu::always_inline]] inline typename O::V muscle_targets(const Impl& s, const typename O::V (&row)[2], int q) {
  return muscle_target<O>(s, q, O::point(row, s.tm_group_lane.data() + q));
}

/// The targets of slots [0, nwm_pad) from this frame's row of sines.
template <class O>
void targets_kernel(Impl& s, const double* sine) {
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
      for (int q = 0; q < s.nwm_pad; q += O::W) {
        O::store(s.target.data() + q, muscle_target<O>(s, q, O::pick(row, pairs, s.sine_lane + q)));
      }
      return;
    }
  }
  for (int q = 0; q < s.nwm_pad; q += O::W) {
    O::store(s.target.data() + q, muscle_target<O>(s, q, O::gather(sine, s.sine_index + q)));
  }
}

/// The sine arguments of rows [0, filled) (fill_rows): argument d of row r is
/// 2pi * (muscle phase - the row's phase of its wave state), as
/// rules::muscle_target_length forms it, W arguments of one wave state at a time
/// (they are consecutive: number_arguments). The last vector of a state runs into
/// the next state's arguments or row, which are written after it (dist_arg and
/// dist_phase are padded for the last row's).
template <class O>
void args_kernel(Impl& s, int filled) {
  using V = typename O::V;
  const std::size_t stride = s.creatures.size();
  // Locals: the stores through arg could alias s's members, which would then be
  // reloaded after each of them.
  const int states = s.states, distinct = s.distinct;
  const int* first = s.state_first.data();
  const double* muscle_phase = s.dist_phase.data();
  for (int r = 0; r < filled; ++r) {
    const double* phase = s.row_phase.data() + static_cast<std::size_t>(r) * stride;
    double* arg = s.dist_arg.data() + static_cast<std::size_t>(r) * distinct;
    for (int k = 0; k < states; ++k) {
      const V wave = O::set1(phase[k]);
      for (int d = first[k]; d < first[k + 1]; d += O::W) {
        O::storeu(arg + d, simd_rules::sine_argument<O>(O::loadu(muscle_phase + d), wave));
      }
    }
  }
}

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
void register_chunk(Impl& s, State* const* st, long long frames) {
  using O = Avx512Ops;
  using V = O::V;
  using M = O::M;
  constexpr int W = O::W;
  const int mass_blocks = s.nm_pad / W;
  const int link_blocks = s.nl_pad / W;
  const bool wave = s.nwm > 0;
  double* pos = s.pos.data();
  double* vel = s.vel.data();
  V x[2], y[2], vx[2], vy[2];
  // Loops over blocks have constant trip counts and test the block count inside,
  // so that they unroll and every array index is a constant: the arrays are then
  // registers, not stack memory.
  const auto load = [&]() __attribute__((always_inline)) {
#pragma GCC unroll 2
    for (int r = 0; r < 2; ++r) {
      O::load_pairs(pos + 2 * W * r, x[r], y[r]); // pos holds 16 points at least
      if (r < mass_blocks) O::load_pairs(vel + 2 * W * r, vx[r], vy[r]);
    }
  };
  const auto store = [&]() __attribute__((always_inline)) {
#pragma GCC unroll 2
    for (int r = 0; r < 2; ++r) {
      if (r >= mass_blocks) break;
      O::store_pairs(pos + 2 * W * r, x[r], y[r]);
      O::store_pairs(vel + 2 * W * r, vx[r], vy[r]);
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
  const int target_blocks = s.nwm_pad / W;
  const auto load_targets = [&]() __attribute__((always_inline)) {
#pragma GCC unroll 4
    for (int b = 0; b < 4; ++b) target[b] = b < link_blocks ? O::load(s.target.data() + W * b) : zero;
  };
  const auto store_targets = [&]() __attribute__((always_inline)) {
#pragma GCC unroll 4
    for (int b = 0; b < 4; ++b) {
      if (b < target_blocks) O::store(s.target.data() + W * b, target[b]);
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
      const __m512i ia = _mm512_load_si512(s.rf_end_a.data() + W * b);
      const __m512i ib = _mm512_load_si512(s.rf_end_b.data() + W * b);
      const V xa = _mm512_permutex2var_pd(x[0], ia, x[1]), xb = _mm512_permutex2var_pd(x[0], ib, x[1]);
      const V ya = _mm512_permutex2var_pd(y[0], ia, y[1]), yb = _mm512_permutex2var_pd(y[0], ib, y[1]);
      const V dx = O::sub(xb, xa);
      const V dy = O::sub(yb, ya);
      const V length = simd_rules::length<O>(dx, dy);
      const V c = simd_rules::impulse_factor<O>(O::load(s.link_k.data() + W * b), length, target[b]);
      // The impulse from the file's difference b - a (link_swap; the slots give
      // each end its sign).
      const M swapped = O::lt(O::load(s.link_swap.data() + W * b), zero);
      px[b] = O::mul(c, O::select(swapped, O::sub(xa, xb), dx));
      py[b] = O::mul(c, O::select(swapped, O::sub(ya, yb), dy));
      zero_length = O::m_or(zero_length, O::m_and(O::eq(length, zero), s.rf_real[b]));
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
      const std::int64_t* index = s.rf_index.data();
      const double* sign = s.rf_sign.data();
      const std::uint8_t* upper = s.rf_upper.data();
      const std::uint8_t* valid = s.rf_valid.data();
#pragma GCC unroll 2
      for (int m = 0; m < 2; ++m) {
        if (m >= mass_blocks) break;
        V sx = vx[m], sy = vy[m];
        for (int r = s.rf_rounds[m]; r > 0; --r, index += W, sign += W, ++upper, ++valid) {
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
  store_targets(); // the next chunk starts from s.target
}
#pragma GCC diagnostic pop

/// Frames with the SIMD kernels for one wall/gravity specialisation: the frame
/// loop is inside the specialised function, so nothing is looked up per frame.
template <class O, bool Gravity, bool Floor, bool Ceiling, bool Sides>
void run_chunk(Impl& s, State* const* st, long long frames) {
  const bool wave = s.nwm > 0;
  for (long long f = 0; f < frames; ++f) {
    if (wave) s.update_targets(st);
    if (s.nl > 0) {
      // points_in_registers is only ever set where O::kPointRegisters holds.
      if (s.points_in_registers) {
        link_kernel<O, O::kPointRegisters>(s);
      } else {
        link_kernel<O, false>(s);
      }
    }
    if (mass_kernel<O, Gravity, Floor, Ceiling, Sides>(s)) s.replay_side_hits(st);
    if (!s.bar_a.empty()) s.bars_pass();
    s.advance_waves(st);
  }
}

using LinkFn = void (*)(Impl&);
using TargetFn = void (*)(Impl&, const double*);
using ArgsFn = void (*)(Impl&, int);
using ChunkFn = void (*)(Impl&, State* const*, long long);

template <class O>
struct KernelTable {
  static LinkFn link();
  static ChunkFn chunk(bool g, bool f, bool c, bool sides);
  static TargetFn targets();
  static ArgsFn args();
};

// The 16 specialisations of a frame kernel (gravity, floor, ceiling, side walls),
// in the order of specialisation_index: X(args..., G, F, C, S) for each.
#define SODA_EACH_SPECIALISATION(X, ...)                                                                     \
  X(__VA_ARGS__, false, false, false, false) X(__VA_ARGS__, false, false, false, true)                     \
  X(__VA_ARGS__, false, false, true, false) X(__VA_ARGS__, false, false, true, true)                       \
  X(__VA_ARGS__, false, true, false, false) X(__VA_ARGS__, false, true, false, true)                       \
  X(__VA_ARGS__, false, true, true, false) X(__VA_ARGS__, false, true, true, true)                         \
  X(__VA_ARGS__, true, false, false, false) X(__VA_ARGS__, true, false, false, true)                       \
  X(__VA_ARGS__, true, false, true, false) X(__VA_ARGS__, true, false, true, true)                         \
  X(__VA_ARGS__, true, true, false, false) X(__VA_ARGS__, true, true, false, true)                         \
  X(__VA_ARGS__, true, true, true, false) X(__VA_ARGS__, true, true, true, true)

constexpr int specialisation_index(bool g, bool f, bool c, bool sides) {
  return (g ? 8 : 0) + (f ? 4 : 0) + (c ? 2 : 0) + (sides ? 1 : 0);
}

#define SODA_MASS_KERNEL(O, G, F, C, S) template bool mass_kernel<O, G, F, C, S>(Impl&);
#define SODA_RUN_CHUNK(O, G, F, C, S) template void run_chunk<O, G, F, C, S>(Impl&, State* const*, long long);
#define SODA_RUN_CHUNK_ADDRESS(O, G, F, C, S) &run_chunk<O, G, F, C, S>,
#define SODA_KERNELS(O)                                                                                    \
  SODA_EACH_SPECIALISATION(SODA_MASS_KERNEL, O)                                                            \
  template void link_kernel<O, false>(Impl&);                                                              \
  SODA_EACH_SPECIALISATION(SODA_RUN_CHUNK, O)                                                              \
  template void targets_kernel<O>(Impl&, const double*);                                                   \
  template void args_kernel<O>(Impl&, int);                                                                \
  template <>                                                                                              \
  TargetFn KernelTable<O>::targets() {                                                                     \
    return &targets_kernel<O>;                                                                             \
  }                                                                                                        \
  template <>                                                                                              \
  ArgsFn KernelTable<O>::args() {                                                                          \
    return &args_kernel<O>;                                                                                \
  }                                                                                                        \
  template <>                                                                                              \
  LinkFn KernelTable<O>::link() {                                                                          \
    return &link_kernel<O, false>;                                                                         \
  }                                                                                                        \
  template <>                                                                                              \
  ChunkFn KernelTable<O>::chunk(bool g, bool f, bool c, bool sides) {                                      \
    constexpr ChunkFn table[16] = {SODA_EACH_SPECIALISATION(SODA_RUN_CHUNK_ADDRESS, O)};                   \
    return table[specialisation_index(g, f, c, sides)];                                                    \
  }

SODA_KERNELS(Sse2Ops)

// Instantiated under the target pragma so that they are compiled for that
// instruction set (they are only called when the CPU has it).
#pragma GCC push_options
#pragma GCC target("avx2,fma")
SODA_KERNELS(Avx2Ops)
#pragma GCC pop_options

#pragma GCC push_options
#pragma GCC target("avx512f")
SODA_KERNELS(Avx512Ops)
template void link_kernel<Avx512Ops, true>(Impl&);
#define SODA_REGISTER_CHUNK(_, G, F, C, S) template void register_chunk<G, F, C, S>(Impl&, State* const*, long long);
#define SODA_REGISTER_CHUNK_ADDRESS(_, G, F, C, S) &register_chunk<G, F, C, S>,
SODA_EACH_SPECIALISATION(SODA_REGISTER_CHUNK, 0)

ChunkFn register_chunk_fn(bool g, const WallNeeds& w) {
  constexpr ChunkFn table[16] = {SODA_EACH_SPECIALISATION(SODA_REGISTER_CHUNK_ADDRESS, 0)};
  return table[specialisation_index(g, w.floor, w.ceiling, w.sides)];
}
#pragma GCC pop_options

#undef SODA_REGISTER_CHUNK_ADDRESS
#undef SODA_REGISTER_CHUNK
#undef SODA_RUN_CHUNK_ADDRESS
#undef SODA_RUN_CHUNK
#undef SODA_MASS_KERNEL
#undef SODA_EACH_SPECIALISATION
#undef SODA_KERNELS

LinkFn link_fn(SimdLevel level) {
  switch (level) {
    case SimdLevel::Avx512: return KernelTable<Avx512Ops>::link();
    case SimdLevel::Avx2: return KernelTable<Avx2Ops>::link();
    default: return KernelTable<Sse2Ops>::link();
  }
}

TargetFn targets_fn(SimdLevel level) {
  switch (level) {
    case SimdLevel::Avx512: return KernelTable<Avx512Ops>::targets();
    case SimdLevel::Avx2: return KernelTable<Avx2Ops>::targets();
    default: return KernelTable<Sse2Ops>::targets();
  }
}

ArgsFn args_fn(SimdLevel level) {
  switch (level) {
    case SimdLevel::Avx512: return KernelTable<Avx512Ops>::args();
    case SimdLevel::Avx2: return KernelTable<Avx2Ops>::args();
    default: return KernelTable<Sse2Ops>::args();
  }
}

ChunkFn chunk_fn(SimdLevel level, bool g, const WallNeeds& w) {
  switch (level) {
    case SimdLevel::Avx512: return KernelTable<Avx512Ops>::chunk(g, w.floor, w.ceiling, w.sides);
    case SimdLevel::Avx2: return KernelTable<Avx2Ops>::chunk(g, w.floor, w.ceiling, w.sides);
    default: return KernelTable<Sse2Ops>::chunk(g, w.floor, w.ceiling, w.sides);
  }
}


} // namespace

// ---------------------------------------------------------------------------
// CPU levels.
// ---------------------------------------------------------------------------

std::string KernelChoice::describe() const {
  std::string s = simd_level_name(simd);
  s += ordered ? " ordered" : " simd-masses";
  s += wave ? " wave" : " no-wave";
  s += gravity ? " gravity" : " no-gravity";
  s += " walls:";
  s += walls.floor ? "F" : "-";
  s += walls.ceiling ? "C" : "-";
  s += walls.sides ? "S" : "-";
  s += bars == BarKind::None ? " bars:none" : bars == BarKind::FixedSegments ? " bars:fixed" : " bars:moving";
  return s;
}

// ---------------------------------------------------------------------------
// Building the plan.
// ---------------------------------------------------------------------------

namespace {

/// `values` (one per natural index) rearranged so that block b of W holds item
/// b + kLaneLink(W, l) in lane l; padded with `fill` to `padded` entries.
AVec<double> in_lane_order(const std::vector<double>& values, int w, std::size_t padded, double fill) {
  AVec<double> out(padded, fill);
  for (std::size_t b = 0; b < padded; b += static_cast<std::size_t>(w)) {
    for (int l = 0; l < w; ++l) {
      const std::size_t item = b + static_cast<std::size_t>(kLaneLink(w, l));
      if (item < values.size()) out[b + static_cast<std::size_t>(l)] = values[item];
    }
  }
  return out;
}

} // namespace

void FusedScene::Data::build(const std::vector<const Model*>& models, long long budget, FastStepOptions opt) {
  options = opt;
  simd = opt.simd == SimdLevel::Auto ? best_simd_level() : opt.simd;
  if (!simd_level_supported(simd)) simd = best_simd_level();
  W = width_of(simd);
  sine_fn = exact_sin_fn(opt.vector_sines ? simd : SimdLevel::Sse2);

  creatures.assign(models.size(), {});
  nm = 0;
  nf = 0;
  for (std::size_t c = 0; c < models.size(); ++c) {
    Creature& cr = creatures[c];
    cr.model = models[c];
    cr.needs = analyse_scene(*models[c], budget);
    cr.mass_base = nm;
    nm += models[c]->mass_count;
    any_wave = any_wave || cr.needs.wave;
    any_gravity = any_gravity || cr.needs.gravity;
    bars = cr.needs.bars;
  }
  nm_pad = (nm + kMaxWidth - 1) / kMaxWidth * kMaxWidth;
  // A creature's masses get working indices [mass_base, mass_base + mass_count)
  // in order of decreasing degree (acting links), so that the impulse sums go
  // over consecutive masses of similar degree (mass_kernel: few padding
  // rounds, sums kept in registers for the mass step). The file order stays in
  // work_of_point for what runs in mass order.
  for (Creature& cr : creatures) {
    const Model& m = *cr.model;
    std::vector<int> degree(static_cast<std::size_t>(m.mass_count), 0);
    for (int i = 0; i < m.link_count(); ++i) {
      if (m.is_mass(m.link_a[i])) ++degree[m.link_a[i]];
      if (m.is_mass(m.link_b[i])) ++degree[m.link_b[i]];
    }
    std::vector<int> order(static_cast<std::size_t>(m.mass_count));
    for (int p = 0; p < m.mass_count; ++p) order[p] = p;
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return degree[a] > degree[b]; });
    cr.work_of_point.resize(static_cast<std::size_t>(m.point_count));
    for (int r = 0; r < m.mass_count; ++r) cr.work_of_point[order[r]] = cr.mass_base + r;
    for (int p = m.mass_count; p < m.point_count; ++p) cr.work_of_point[p] = nm_pad + nf + (p - m.mass_count);
    nf += m.point_count - m.mass_count;
  }
  sink = nm_pad + nf;
  // (Avx512Ops::load_points reads kRegisterPoints points whatever the scene's size.)
  pos.assign(2 * static_cast<std::size_t>(std::max(sink + 1, Avx512Ops::kRegisterPoints)), 0.0);
  vel.assign(2 * static_cast<std::size_t>(sink + 1), 0.0);
  old_pos.assign(2 * static_cast<std::size_t>(nm_pad), 0.0);
  side.assign(2 * static_cast<std::size_t>(nm_pad), 0.0);

  // Per-mass parameters (padding masses: gravity +0, so they stay at rest).
  std::vector<double> gd, keep, width, height, fs, rs;
  for (const Creature& cr : creatures) {
    const Model& m = *cr.model;
    for (int i = 0; i < m.mass_count; ++i) {
      gd.push_back(m.gravity * static_cast<double>(static_cast<int>(m.gravity_direction))); // rules::apply_gravity
      keep.push_back(1.0 - m.friction); // rules::friction_factor
      width.push_back(m.width);
      height.push_back(m.height);
      fs.push_back(m.surface_friction);
      rs.push_back(m.surface_reflection);
    }
  }
  const auto np = static_cast<std::size_t>(nm_pad);
  mass_gd = in_lane_order(gd, W, np, 0.0);
  mass_keep = in_lane_order(keep, W, np, 1.0);
  mass_width = in_lane_order(width, W, np, 1.0);
  mass_height = in_lane_order(height, W, np, 1.0);
  mass_fs = in_lane_order(fs, W, np, 1.0);
  mass_rs = in_lane_order(rs, W, np, 1.0);

  // Acting links (a free end), the wave muscles of every creature first, then the
  // other links, each creature's in file order. The order links are computed in
  // is free: only the order of the additions into each velocity matters, and the
  // slots below keep each model's file order for that.
  auto wave_muscle = [](const Model& m, int i) {
    return m.link_muscle[i] && (m.wave_amplitude * m.link_amplitude[i]) != 0.0;
  };
  std::vector<Acting> acting;
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t c = 0; c < creatures.size(); ++c) {
      const Model& m = *creatures[c].model;
      for (int i = 0; i < m.link_count(); ++i) {
        if (!m.is_mass(m.link_a[i]) && !m.is_mass(m.link_b[i])) continue; // no effect at all
        if (wave_muscle(m, i) == (pass == 0)) acting.push_back({static_cast<int>(c), i, false, pass == 0, 0});
      }
    }
    if (pass == 0) nwm = static_cast<int>(acting.size());
  }
  arrange_links(acting); // sets nwm_pad
  if (frames_fit_registers(static_cast<int>(acting.size()))) order_by_need(acting);
  nl = static_cast<int>(acting.size());
  nl_pad = (nl + kMaxWidth - 1) / kMaxWidth * kMaxWidth;
  la.assign(static_cast<std::size_t>(nl_pad), 0);
  lb.assign(static_cast<std::size_t>(nl_pad), 0);
  target.assign(static_cast<std::size_t>(nl_pad), 0.0);
  link_k.assign(static_cast<std::size_t>(nl_pad), 0.0);
  link_swap.assign(static_cast<std::size_t>(nl_pad), 1.0);
  imp.assign(4 * static_cast<std::size_t>(nl_pad) + 2, -0.0);
  // Per mass, its impulse pairs in file order of its model's links.
  std::vector<std::vector<std::pair<int, std::int32_t>>> per_mass_file(static_cast<std::size_t>(nm_pad));
  for (int k = 0; k < nl; ++k) {
    if (acting[k].creature < 0) {
      la[k] = lb[k] = 2 * static_cast<std::uint32_t>(acting[k].dummy);
      continue;
    }
    const Creature& cr = creatures[acting[k].creature];
    const Model& m = *cr.model;
    const int i = acting[k].link;
    const int a = acting[k].swapped ? m.link_b[i] : m.link_a[i];
    const int b = acting[k].swapped ? m.link_a[i] : m.link_b[i];
    la[k] = 2 * static_cast<std::uint32_t>(cr.work_of_point[a]);
    lb[k] = 2 * static_cast<std::uint32_t>(cr.work_of_point[b]);
    // The pass's end A gets +c*d and end B -c*d, d the file's difference b - a
    // (link_swap): with the ends swapped, the file's end a (the pass's B) takes
    // the +c*d pair and b the -c*d one.
    const bool swapped = acting[k].swapped;
    if (m.is_mass(a)) per_mass_file[cr.work_of_point[a]].emplace_back(i, swapped ? nl_pad + k : k);
    if (m.is_mass(b)) per_mass_file[cr.work_of_point[b]].emplace_back(i, swapped ? k : nl_pad + k);
  }
  std::vector<std::vector<std::int32_t>> per_mass(static_cast<std::size_t>(nm_pad));
  for (int w = 0; w < nm_pad; ++w) {
    auto& list = per_mass_file[w];
    std::stable_sort(list.begin(), list.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& e : list) per_mass[w].push_back(e.second);
  }
  identity_pair = 2 * nl_pad;
  block_rounds.clear();
  slots.clear();
  slot_of_mass.assign(static_cast<std::size_t>(nm_pad), 0);
  rounds_of_mass.assign(static_cast<std::size_t>(nm_pad), 0);
  for (int g = 0; g < nm_pad; g += kGatherGroup) {
    std::size_t rounds = 0;
    for (int l = 0; l < kGatherGroup; ++l) rounds = std::max(rounds, per_mass[g + l].size());
    block_rounds.push_back(static_cast<std::int32_t>(rounds));
    for (int l = 0; l < kGatherGroup; ++l) {
      slot_of_mass[g + l] = static_cast<std::int32_t>(slots.size()) + l;
      rounds_of_mass[g + l] = static_cast<std::int32_t>(rounds);
    }
    for (std::size_t r = 0; r < rounds; ++r) {
      for (int l = 0; l < kGatherGroup; ++l) {
        const auto& list = per_mass[g + l];
        slots.push_back(2 * static_cast<std::uint32_t>(r < list.size() ? list[r] : identity_pair));
      }
    }
  }
  // Targets and springyness in lane order: lane l of block b holds link b*W + kLaneLink(W, l).
  std::vector<int> slot_of_link(static_cast<std::size_t>(nl_pad));
  for (int b = 0; b < nl_pad; b += W) {
    for (int l = 0; l < W; ++l) slot_of_link[b + kLaneLink(W, l)] = b + l;
  }
  points_in_registers = simd == SimdLevel::Avx512 && nm_pad + nf <= Avx512Ops::kRegisterPoints;
  la_point.clear();
  lb_point.clear();
  if (points_in_registers) {
    la_point.assign(static_cast<std::size_t>(nl_pad), 0);
    lb_point.assign(static_cast<std::size_t>(nl_pad), 0);
    for (int k = 0; k < nl_pad; ++k) {
      la_point[slot_of_link[k]] = la[k] / 2;
      lb_point[slot_of_link[k]] = lb[k] / 2;
    }
  }
  tm_rest.assign(static_cast<std::size_t>(nwm_pad), 0.0);
  tm_power.assign(static_cast<std::size_t>(nwm_pad), 0.0);
  tm_group.assign(static_cast<std::size_t>(nwm_pad), 0);
  // Distinct phases per creature (its sines depend on its own wave phase).
  std::vector<std::map<std::uint64_t, int>> group_of_phase(creatures.size());
  for (int k = 0; k < nwm_pad; ++k) {
    if (!acting[k].wave) continue;
    Creature& cr = creatures[acting[k].creature];
    const double phase = cr.model->link_phase[acting[k].link];
    if (group_of_phase[acting[k].creature].try_emplace(bits_of(phase), 0).second) ++cr.groups;
  }
  groups = 0;
  for (std::size_t c = 0; c < creatures.size(); ++c) {
    creatures[c].group_base = groups; // its groups numbered in order of first use below
    groups += creatures[c].groups;
    group_of_phase[c].clear();
  }
  group_phase.assign(static_cast<std::size_t>(groups), 0.0);
  std::vector<int> next_group(creatures.size(), 0);
  for (int k = 0; k < nl; ++k) {
    if (acting[k].creature < 0) continue; // dummy: target 0, springyness 0
    const Creature& cr = creatures[acting[k].creature];
    const Model& m = *cr.model;
    const int i = acting[k].link;
    const int q = slot_of_link[k];
    target[q] = m.link_rest[i]; // springs, and muscles of power 0: rest*(1 +- 0) = rest
    link_k[q] = m.springyness;
    link_swap[q] = acting[k].swapped ? -1.0 : 1.0;
    if (q < nwm_pad) tm_rest[q] = m.link_rest[i];
    if (!acting[k].wave) continue;
    tm_power[q] = m.wave_amplitude * m.link_amplitude[i]; // the product muscle_target_length forms
    auto [it, inserted] = group_of_phase[acting[k].creature].try_emplace(bits_of(m.link_phase[i]), 0);
    if (inserted) {
      it->second = cr.group_base + next_group[acting[k].creature]++;
      group_phase[it->second] = m.link_phase[i];
    }
    tm_group[q] = it->second;
  }
  // Rows of sines per batch: enough frames that the batch overhead is shared.
  constexpr int kSinesPerBatch = 1024;
  rows = std::clamp(kSinesPerBatch / std::max(groups, 1), 1, 16);
  const std::size_t row_values = static_cast<std::size_t>((rows * groups + kMaxWidth - 1) / kMaxWidth * kMaxWidth);
  wave_creatures.clear();
  still_creatures.clear();
  for (std::size_t c = 0; c < creatures.size(); ++c) {
    (creatures[c].groups > 0 ? wave_creatures : still_creatures).push_back(static_cast<int>(c));
  }
  row_phase.assign(creatures.size() * static_cast<std::size_t>(rows + 1), 0.0);
  sines_in_registers = simd == SimdLevel::Avx512 && groups <= Avx512Ops::kRegisterPoints;
  tm_group_lane.assign(static_cast<std::size_t>(nwm_pad), 0);
  for (int q = 0; q < nwm_pad; ++q) tm_group_lane[q] = tm_group[q];
  dist_arg.assign(row_values + kMaxWidth, 1.0); // padding lanes: an argument the tables take (args_kernel)
  // Any row of sines by group loads as two registers (sines_in_registers).
  dist_sin.assign(row_values + Avx512Ops::kRegisterPoints, 0.0);
  row_sin.assign(row_values + Avx512Ops::kRegisterPoints, 0.0);
  tm_dist.assign(static_cast<std::size_t>(nwm_pad), 0);
  tm_dist_lane.assign(static_cast<std::size_t>(nwm_pad), 0);
  sine_rows = dist_sin.data();
  sine_stride = groups;
  sine_index = tm_group.data();
  sine_lane = tm_group_lane.data();
  std::map<std::uint64_t, int> u_of_phase;
  group_u.assign(static_cast<std::size_t>(groups), 0);
  for (int g = 0; g < groups; ++g) {
    group_u[g] = u_of_phase.try_emplace(bits_of(group_phase[g]), static_cast<int>(u_of_phase.size())).first->second;
  }
  uphases = static_cast<int>(u_of_phase.size());
  states = 0;
  numbering_valid = false;
  rows_synced = false;
  fill_slot.assign(creatures.size(), 0);
  slot_leader.assign(creatures.size(), 0);
  su_index.assign(creatures.size() * static_cast<std::size_t>(uphases), -1);
  dist_key.assign(static_cast<std::size_t>(groups), 0);
  state_first.assign(creatures.size() + 1, 0);
  dist_phase.assign(static_cast<std::size_t>(groups + kMaxWidth), 0.0); // padded for args_kernel
  group_arg.assign(static_cast<std::size_t>(groups), 0);

  if (creatures.size() == 1) {
    const Model& m = *creatures[0].model;
    for (int b = 0; b < m.bar_count(); ++b) {
      bar_a.push_back(2 * creatures[0].work_of_point[m.bar_a[b]]);
      bar_b.push_back(2 * creatures[0].work_of_point[m.bar_b[b]]);
    }
  }

  // The frame in registers: the register lane of working point (or link slot) p.
  frame_in_registers = frames_fit_registers(nl_pad);
  rf_end_a.clear();
  rf_end_b.clear();
  rf_index.clear();
  rf_sign.clear();
  rf_upper.clear();
  rf_valid.clear();
  rf_rounds.clear();
  rf_real.clear();
  if (frame_in_registers) {
    const auto lane_of = [](int p) {
      const int j = p % kMaxWidth;
      return p - j + (j < kMaxWidth / 2 ? 2 * j : 2 * (j - kMaxWidth / 2) + 1); // kLaneLink inverted
    };
    rf_real.assign(static_cast<std::size_t>(nl_pad / kMaxWidth), 0);
    for (int k = 0; k < nl; ++k) {
      if (acting[k].creature >= 0) rf_real[k / kMaxWidth] |= static_cast<std::uint8_t>(1u << (slot_of_link[k] % kMaxWidth));
    }
    rf_end_a.assign(static_cast<std::size_t>(nl_pad), 0);
    rf_end_b.assign(static_cast<std::size_t>(nl_pad), 0);
    for (int k = 0; k < nl_pad; ++k) {
      rf_end_a[slot_of_link[k]] = lane_of(static_cast<int>(la[k] / 2));
      rf_end_b[slot_of_link[k]] = lane_of(static_cast<int>(lb[k] / 2));
    }
    for (int blk = 0; blk < nm_pad / kMaxWidth; ++blk) {
      std::size_t rounds = 0;
      for (int l = 0; l < kMaxWidth; ++l) rounds = std::max(rounds, per_mass[blk * kMaxWidth + kLaneLink(kMaxWidth, l)].size());
      rf_rounds.push_back(static_cast<int>(rounds));
      for (std::size_t r = 0; r < rounds; ++r) {
        std::uint8_t upper = 0, valid = 0;
        for (int l = 0; l < kMaxWidth; ++l) {
          const auto& list = per_mass[blk * kMaxWidth + kLaneLink(kMaxWidth, l)];
          const bool b_end = r < list.size() && list[r] >= nl_pad;
          const int lane = r < list.size() ? lane_of(b_end ? list[r] - nl_pad : list[r]) : 0;
          rf_index.push_back(lane % (2 * kMaxWidth));
          rf_sign.push_back(b_end || r >= list.size() ? -0.0 : 0.0); // no impulse: +0.0 ^ sign = -0.0
          if (lane >= 2 * kMaxWidth) upper = static_cast<std::uint8_t>(upper | (1u << l));
          if (r < list.size()) valid = static_cast<std::uint8_t>(valid | (1u << l));
        }
        rf_upper.push_back(upper);
        rf_valid.push_back(valid);
      }
    }
  }
}

// The order the link pass computes links in is free (only the order of the
// additions into each velocity matters, and the slots keep each model's file
// order for that), and so is which end is A: with the ends swapped the pass
// still forms the file's difference d = b - a (link_swap: not the pass's b - a
// negated, which is -0 where the file's is +0), so the length, the factor c and
// c*d are the same bits, and the slots give the file's end a +c*d and b -c*d.
// So blocks of W links are formed whose A ends are the W masses of one block of
// masses, in slot order: the link pass then loads those ends as two whole
// vectors instead of W pair loads with their offsets (about 10 % of the pass).
// A block may take one dummy lane (W = 8) where a mass has no link left.
// Layout: the wave muscles first, formed blocks then the others, filled up to a
// multiple of kMaxWidth with other links (target slots [0, nwm_pad) are the ones
// that change per frame); then the other links, formed blocks first.
// The frame in registers (register_chunk) computes its link blocks in order, one
// square root per block a few cycles after the other, and a mass adds its
// impulses in rounds, one round per link in file order. A link whose impulse is
// added early in a long list holds up more additions after it than one added last,
// so the links are ordered by how many rounds still follow their first use (the
// most first) within the wave slots and within the others; a round that takes no
// impulse of the last block then does not wait for it (register_chunk).
void FusedScene::Data::order_by_need(std::vector<Acting>& acting) {
  std::vector<std::vector<std::pair<int, int>>> incident(static_cast<std::size_t>(nm_pad)); // (file link, acting)
  for (std::size_t k = 0; k < acting.size(); ++k) {
    if (acting[k].creature < 0) continue;
    for (bool b_end : {false, true}) {
      const int w = working_end(acting[k], b_end);
      if (w < nm) incident[w].emplace_back(acting[k].link, static_cast<int>(k)); // a mass
    }
  }
  std::vector<int> after(acting.size(), -1); // rounds that follow the link's first use
  for (int blk = 0; blk < nm_pad; blk += kMaxWidth) {
    std::size_t rounds = 0;
    for (int w = blk; w < blk + kMaxWidth; ++w) rounds = std::max(rounds, incident[w].size());
    for (int w = blk; w < blk + kMaxWidth; ++w) {
      auto& list = incident[w];
      std::sort(list.begin(), list.end());
      for (std::size_t r = 0; r < list.size(); ++r) {
        int& a = after[static_cast<std::size_t>(list[r].second)];
        a = std::max(a, static_cast<int>(rounds - r));
      }
    }
  }
  std::vector<int> index(acting.size());
  for (std::size_t k = 0; k < acting.size(); ++k) index[k] = static_cast<int>(k);
  const auto by_need = [&](int x, int y) { return after[x] > after[y]; };
  std::stable_sort(index.begin(), index.begin() + nwm_pad, by_need);
  std::stable_sort(index.begin() + nwm_pad, index.end(), by_need);
  std::vector<Acting> ordered;
  for (int k : index) ordered.push_back(acting[k]);
  acting = ordered;
  std::fill(a_block.begin(), a_block.end(), -1); // the blocks no longer follow the masses
}

void FusedScene::Data::arrange_links(std::vector<Acting>& acting) {
  struct Arranged {
    std::vector<Acting> formed; ///< W per block
    std::vector<std::int32_t> blocks;
    std::vector<Acting> rest; ///< in the order given
  };
  const auto arrange = [&](const std::vector<Acting>& pool) {
    Arranged out;
    std::vector<std::vector<int>> incident(static_cast<std::size_t>(nm_pad));
    std::vector<int> left(static_cast<std::size_t>(nm_pad), 0); // unplaced links at each mass
    for (std::size_t g = 0; g < pool.size(); ++g) {
      const int a = working_end(pool[g], false), b = working_end(pool[g], true);
      if (a < nm) incident[a].push_back(static_cast<int>(g));
      if (b < nm && b != a) incident[b].push_back(static_cast<int>(g));
    }
    for (int m = 0; m < nm; ++m) left[m] = static_cast<int>(incident[m].size());
    std::vector<char> placed(pool.size(), 0);
    std::vector<std::size_t> first(static_cast<std::size_t>(nm_pad), 0); // before it: all placed
    const int dummies_allowed = W == 8 ? 1 : 0;
    for (bool progress = true; progress;) {
      progress = false;
      for (int blk = 0; blk < nm_pad / W; ++blk) {
        int ready = 0;
        for (int t = 0; t < W; ++t) ready += left[W * blk + t] > 0 ? 1 : 0;
        if (ready < W - dummies_allowed) continue;
        for (int t = 0; t < W; ++t) {
          const int m = W * blk + t;
          // Of the mass's next links (a bounded look, so that a mass of huge
          // degree costs linear time), the one whose other end has the most links
          // left (an end that is not a mass cannot be an A end: taken first).
          constexpr std::size_t kLook = 32;
          const auto& list = incident[m];
          std::size_t& from = first[m];
          while (from < list.size() && placed[list[from]]) ++from;
          int best = -1, best_left = -1;
          for (std::size_t q = from; q < list.size() && q < from + kLook; ++q) {
            const int g = list[q];
            if (placed[g]) continue;
            const int a = working_end(pool[g], false), b = working_end(pool[g], true);
            const int other = a == m ? b : a;
            const int other_left = other < nm ? left[other] : std::numeric_limits<int>::max();
            if (other_left > best_left) best = g, best_left = other_left;
          }
          Acting slot;
          if (best < 0) {
            slot.dummy = m;
          } else {
            slot = pool[best];
            const int a = working_end(slot, false), b = working_end(slot, true);
            slot.swapped = a != m;
            placed[best] = 1;
            --left[m];
            const int other = a == m ? b : a;
            if (other < nm && other != m) --left[other];
          }
          out.formed.push_back(slot);
        }
        out.blocks.push_back(blk);
        progress = true;
      }
    }
    for (std::size_t g = 0; g < pool.size(); ++g) {
      if (!placed[g]) out.rest.push_back(pool[g]);
    }
    return out;
  };
  const Arranged wave = arrange(std::vector<Acting>(acting.begin(), acting.begin() + nwm));
  const Arranged other = arrange(std::vector<Acting>(acting.begin() + nwm, acting.end()));
  acting = wave.formed;
  a_block = wave.blocks;
  acting.insert(acting.end(), wave.rest.begin(), wave.rest.end());
  std::size_t next = 0; // of other.rest
  while (acting.size() % kMaxWidth != 0) acting.push_back(next < other.rest.size() ? other.rest[next++] : Acting{});
  nwm_pad = static_cast<int>(acting.size());
  a_block.resize(acting.size() / static_cast<std::size_t>(W), -1);
  acting.insert(acting.end(), other.formed.begin(), other.formed.end());
  a_block.insert(a_block.end(), other.blocks.begin(), other.blocks.end());
  acting.insert(acting.end(), other.rest.begin() + static_cast<std::ptrdiff_t>(next), other.rest.end());
  const std::size_t padded = (acting.size() + kMaxWidth - 1) / kMaxWidth * kMaxWidth;
  a_block.resize(padded / static_cast<std::size_t>(W), -1);
}

void FusedScene::Data::load_state(State* const* st) {
  for (std::size_t c = 0; c < creatures.size(); ++c) {
    const Creature& cr = creatures[c];
    const State& s = *st[c];
    for (int p = 0; p < cr.model->point_count; ++p) {
      const int w = cr.work_of_point[p];
      px(w) = s.x[p];
      py(w) = s.y[p];
      pvx(w) = s.vx[p];
      pvy(w) = s.vy[p];
    }
  }
  for (int w = nm; w < nm_pad; ++w) px(w) = py(w) = pvx(w) = pvy(w) = 0.0;
}

void FusedScene::Data::store_state(State* const* st) {
  for (std::size_t c = 0; c < creatures.size(); ++c) {
    const Creature& cr = creatures[c];
    State& s = *st[c];
    for (int p = 0; p < cr.model->mass_count; ++p) {
      const int w = cr.work_of_point[p];
      s.x[p] = px(w);
      s.y[p] = py(w);
      s.vx[p] = pvx(w);
      s.vy[p] = pvy(w);
    }
  }
}

// The wave states of the wave creatures (fill_slot, slot_leader) and the distinct
// sine arguments of a row under them (state_first, dist_phase, group_arg; tm_dist),
// numbered state by state, in creature and group order within a state: where
// every creature has its own state, or all share one, and no argument is shared,
// argument g is group g and the targets read the sines by group.
void FusedScene::Data::number_arguments(State* const* st) {
  states = 0;
  for (int c : wave_creatures) {
    int k = 0;
    while (k < states && !same_wave(st, c, slot_leader[k])) ++k;
    fill_slot[c] = k;
    if (k == states) slot_leader[states++] = c;
  }
  // State by state, so that the arguments of a state are consecutive (args_kernel).
  distinct = 0;
  for (int k = 0; k < states; ++k) {
    state_first[k] = distinct;
    for (int c : wave_creatures) {
      if (fill_slot[c] != k) continue;
      const Creature& cr = creatures[c];
      for (int g = cr.group_base; g < cr.group_base + cr.groups; ++g) {
        const int key = k * uphases + group_u[g];
        if (su_index[key] < 0) {
          su_index[key] = distinct;
          dist_key[distinct] = key;
          dist_phase[distinct++] = group_phase[g];
        }
        group_arg[g] = su_index[key];
      }
    }
  }
  state_first[states] = distinct;
  for (int d = 0; d < distinct; ++d) su_index[dist_key[d]] = -1;
  // Where the targets read (see sine_rows): by group where argument g is group g.
  bool remap = false;
  for (int g = 0; g < groups; ++g) remap = remap || group_arg[g] != g;
  // Remapped sines in registers are copied out by group per fill (row_sin).
  const bool read_distinct = remap && !sines_in_registers;
  if (read_distinct) {
    for (int q = 0; q < nwm_pad; ++q) tm_dist_lane[q] = tm_dist[q] = group_arg[tm_group[q]];
  }
  sine_rows = remap && sines_in_registers ? row_sin.data() : dist_sin.data();
  sine_stride = read_distinct ? distinct : groups;
  sine_index = read_distinct ? tm_dist.data() : tm_group.data();
  sine_lane = read_distinct ? tm_dist_lane.data() : tm_group_lane.data();
  numbering_valid = true;
}

// Sines for this frame and the next rows - 1 (while each wave's direction holds),
// for every creature, in one batch. Row 0 is the current phase.
//
// Creatures whose waves are in the same state (a GA population shares most genes)
// get the same rows of phases, computed once, and each distinct (wave state,
// muscle phase) pair gives one sine argument whatever the number of creatures and
// muscles sharing it: the same operations on the same bits give the same sine.
// The states are those of the last fill while every creature is still in its
// state's (its leader's): waves move in step until a direction changes, so the
// numbering of the arguments is kept from fill to fill (two states that come to
// agree stay apart until then: exact, only not shared).
void FusedScene::Data::fill_rows(State* const* st) {
  bool same_states = numbering_valid;
  for (std::size_t k = 0; k < wave_creatures.size() && same_states; ++k) {
    const int c = wave_creatures[k];
    same_states = same_wave(st, c, slot_leader[fill_slot[c]]);
  }
  if (!same_states) number_arguments(st);
  // Each state's rows of phases and the advance from the last (rules::advance_wave_phase).
  const std::size_t stride = creatures.size();
  bool all_standing = true;
  for (int k = 0; k < states; ++k) {
    const int c = slot_leader[k];
    double phase = st[c]->wave_phase;
    const WaveDirection mode = st[c]->wave_mode;
    const double speed = creatures[c].model->wave_speed;
    row_phase[k] = phase;
    for (int r = 1; r <= rows; ++r) {
      const double next = rules::advance_wave_phase(phase, speed, mode);
      row_phase[r * stride + k] = next;
      all_standing = all_standing && bits_of(next) == bits_of(phase);
      phase = next;
    }
  }
  for (int c : wave_creatures) creatures[c].rows_mode = st[c]->wave_mode;
  rows_standing = all_standing;
  // Every wave stands still (manual mode, speed 0): one row of sines serves all.
  const int filled = all_standing ? 1 : rows;
  args_fn(simd)(*this, filled);
  const int n = filled * distinct;
  sine_fn(dist_arg.data(), dist_sin.data(), n);
  sines += n;
  if (sine_rows == row_sin.data()) { // remapped, by group
    for (int r = 0; r < filled; ++r) {
      const double* from = dist_sin.data() + static_cast<std::size_t>(r) * distinct;
      double* to = row_sin.data() + static_cast<std::size_t>(r) * groups;
      for (int g = 0; g < groups; ++g) to[g] = from[group_arg[g]];
    }
  }
  for (int r = filled; r < rows; ++r) {
    std::copy(sine_rows, sine_rows + sine_stride, sine_rows + static_cast<std::size_t>(r) * sine_stride);
  }
  row_count = rows;
  row_next = 0;
}

void FusedScene::Data::update_targets(State* const* st) {
  if (const double* sine = row_for_frame(st)) targets_fn(simd)(*this, sine);
}

// Fixed bars (single-model scenes): rules::collide_with_bars on the pair arrays
// (x at even, y at odd offsets; bar ends and the mass as doubled indices).
void FusedScene::Data::collide_with_bars(int i, double x0, double y0) {
  const Model& m = *creatures[0].model;
  rules::collide_with_bars(pos.data(), pos.data() + 1, bar_a.data(), bar_b.data(), static_cast<int>(bar_a.size()),
                           2 * i, x0, y0, px(i), py(i), pvx(i), pvy(i), m.surface_friction, m.surface_reflection);
}

// Masses one by one in file order, exactly as step.cpp move_masses (single-model
// scenes; used when a bar has a free-mass end: a mass's bar test then sees the
// masses moved before it).
void FusedScene::Data::ordered_masses(State& s) {
  const Model& m = *creatures[0].model;
  for (int p = 0; p < nm; ++p) {
    const int i = creatures[0].work_of_point[p];
    // Impulses in file order of the links.
    double vxi = pvx(i), vyi = pvy(i);
    const std::uint32_t* sl = slots.data() + slot_of_mass[i];
    for (int r = 0; r < rounds_of_mass[i]; ++r, sl += kGatherGroup) {
      vxi += imp[*sl];
      vyi += imp[*sl + 1];
    }
    vyi = rules::apply_gravity(vyi, m.gravity, m.gravity_direction);
    const double factor = rules::friction_factor(vxi, vyi, m.friction);
    vxi = factor * vxi;
    vyi = factor * vyi;
    if (rules::is_at_rest(vxi, vyi)) {
      pvx(i) = vxi;
      pvy(i) = vyi;
      continue;
    }
    const double x0 = px(i), y0 = py(i);
    double xi = x0 + vxi, yi = y0 + vyi;
    const SideWall hit = rules::collide_with_container(xi, yi, vxi, vyi, m.width, m.height, m.surface_friction,
                                                       m.surface_reflection);
    rules::autoreverse_on_wall_hit(hit, m.autoreverse, s.wave_mode, s.last_side_wall);
    px(i) = xi;
    py(i) = yi;
    pvx(i) = vxi;
    pvy(i) = vyi;
    if (!bar_a.empty()) collide_with_bars(i, x0, y0);
  }
}

void FusedScene::Data::record(const KernelChoice& k) {
  last = k;
  if (std::find(used.begin(), used.end(), k) == used.end()) used.push_back(k);
}

// Autoreverse (rules::autoreverse_on_wall_hit) for the side-wall hits of this
// frame, per creature in its mass order as the reference meets them.
void FusedScene::Data::replay_side_hits(State* const* st) {
  leave_rows(); // a direction may change
  for (std::size_t c = 0; c < creatures.size(); ++c) {
    const Creature& cr = creatures[c];
    for (int p = 0; p < cr.model->mass_count; ++p) {
      double* hit = side.data() + 2 * static_cast<std::size_t>(cr.work_of_point[p]); // twice the same value
      const double h = hit[0];
      hit[0] = hit[1] = 0.0;
      if (h != 0.0) {
        rules::autoreverse_on_wall_hit(h < 0.0 ? SideWall::Left : SideWall::Right, cr.model->autoreverse,
                                       st[c]->wave_mode, st[c]->last_side_wall);
      }
    }
  }
}

// Bars whose ends are fixed nodes: each mass independent of the others, so the bar
// tests can follow the SIMD container step, in mass order.
void FusedScene::Data::bars_pass() {
  for (int p = 0; p < nm; ++p) {
    const int i = creatures[0].work_of_point[p];
    collide_with_bars(i, old_pos[2 * i], old_pos[2 * i + 1]);
  }
}

void FusedScene::Data::ordered_frame(State& s) {
  State* const st[1] = {&s};
  if (nwm > 0) update_targets(st);
  if (nl > 0) link_fn(simd)(*this);
  const WaveDirection mode = s.wave_mode;
  ordered_masses(s);
  if (s.wave_mode != mode) leave_rows();
  advance_waves(st);
}

// ---------------------------------------------------------------------------
// FusedScene.
// ---------------------------------------------------------------------------

bool FusedScene::can_fuse(const Model& model) { return model.bar_count() == 0; }

FusedScene::FusedScene(const std::vector<const Model*>& models, long long frame_budget, FastStepOptions options)
    : d_(std::make_unique<Data>()) {
  if (models.empty()) throw std::invalid_argument("FusedScene: no models");
  if (models.size() > 1) {
    if (options.force_ordered) throw std::invalid_argument("FusedScene: the ordered kernel takes one model");
    for (const Model* m : models) {
      if (!can_fuse(*m)) throw std::invalid_argument("FusedScene: a model with fixed bars cannot be fused");
    }
  }
  d_->build(models, frame_budget, options);
}
FusedScene::~FusedScene() = default;
FusedScene::FusedScene(FusedScene&&) noexcept = default;
FusedScene& FusedScene::operator=(FusedScene&&) noexcept = default;

int FusedScene::size() const { return static_cast<int>(d_->creatures.size()); }
const Model& FusedScene::model(int c) const { return *d_->creatures[c].model; }
const SceneNeeds& FusedScene::needs(int c) const { return d_->creatures[c].needs; }
bool FusedScene::used(const KernelChoice& k) const {
  return std::find(d_->used.begin(), d_->used.end(), k) != d_->used.end();
}
const KernelChoice& FusedScene::last_kernel() const { return d_->last; }
long long FusedScene::sines_evaluated() const { return d_->sines; }
bool FusedScene::points_in_registers() const { return d_->points_in_registers; }
bool FusedScene::frame_in_registers() const { return d_->frame_in_registers; }

void FusedScene::run(State* const* states, long long frames) {
  Data& s = *d_;
  require_batch_states(
      states, static_cast<int>(s.creatures.size()), [&](int c) { return s.creatures[c].model->point_count; },
      s.creatures.size() == 1 ? "FastStepper::run" : "FusedScene::run");
  if (frames <= 0) return;
  s.load_state(states);
  s.leave_rows(); // the states may be others, or changed since
  KernelChoice k;
  k.simd = s.simd;
  k.wave = s.any_wave;
  k.gravity = s.any_gravity;
  k.bars = s.bars;
  k.ordered = s.options.force_ordered || s.bars == BarKind::MovingEnds;
  // Walls: without bars, the walls no mass of any creature can reach within a
  // chunk of frames are not tested in that chunk. A chunk ends when a skipped wall
  // might come into reach; while every wall is tested the reach is re-checked
  // every kRecheck frames.
  constexpr long long kMinSkip = 32;  // a wall test costs less than re-checking the reach often
  constexpr long long kRecheck = 256;
  const bool adaptive = s.options.adaptive_walls && s.bars == BarKind::None && !k.ordered;
  long long done = 0;
  while (done < frames) {
    long long chunk = frames - done;
    if (adaptive) {
      WallSafeFrames safe{kSafeFramesCap, kSafeFramesCap, kSafeFramesCap};
      for (const Data::Creature& cr : s.creatures) {
        const double* p = s.pos.data() + 2 * static_cast<std::size_t>(cr.mass_base);
        const WallSafeFrames c = wall_safe_frames(*cr.model, p, p + 1, 2);
        safe.floor = std::min(safe.floor, c.floor);
        safe.ceiling = std::min(safe.ceiling, c.ceiling);
        safe.sides = std::min(safe.sides, c.sides);
      }
      k.walls = WallNeeds{safe.floor < kMinSkip, safe.ceiling < kMinSkip, safe.sides < kMinSkip};
      long long valid = kSafeFramesCap;
      if (!k.walls.floor) valid = std::min(valid, safe.floor);
      if (!k.walls.ceiling) valid = std::min(valid, safe.ceiling);
      if (!k.walls.sides) valid = std::min(valid, safe.sides);
      if (valid == kSafeFramesCap) valid = kRecheck; // every wall tested
      chunk = std::min(chunk, valid);
    } else {
      k.walls = WallNeeds{};
    }
    s.record(k);
    if (k.ordered) {
      for (long long f = 0; f < chunk; ++f) s.ordered_frame(*states[0]);
    } else {
      (s.frame_in_registers ? register_chunk_fn(k.gravity, k.walls) : chunk_fn(s.simd, k.gravity, k.walls))(
          s, states, chunk);
    }
    done += chunk;
  }
  s.store_state(states);
  for (std::size_t c = 0; c < s.creatures.size(); ++c) states[c]->frame += frames;
}

// ---------------------------------------------------------------------------
// FastStepper: a scene of one model.
// ---------------------------------------------------------------------------

FastStepper::FastStepper(const Model& model, long long frame_budget, FastStepOptions options)
    : scene_(std::make_unique<FusedScene>(std::vector<const Model*>{&model}, frame_budget, options)) {}
FastStepper::~FastStepper() = default;
FastStepper::FastStepper(FastStepper&&) noexcept = default;
FastStepper& FastStepper::operator=(FastStepper&&) noexcept = default;

const SceneNeeds& FastStepper::needs() const { return scene_->needs(0); }
const Model& FastStepper::model() const { return scene_->model(0); }
bool FastStepper::used(const KernelChoice& k) const { return scene_->used(k); }
const KernelChoice& FastStepper::last_kernel() const { return scene_->last_kernel(); }
long long FastStepper::sines_evaluated() const { return scene_->sines_evaluated(); }
bool FastStepper::points_in_registers() const { return scene_->points_in_registers(); }
bool FastStepper::frame_in_registers() const { return scene_->frame_in_registers(); }

void FastStepper::run(State& state, long long frames) {
  State* const st[1] = {&state};
  scene_->run(st, frames);
}

} // namespace soda
