// The data of a fused scene (FusedScene, fused_scene.hpp): the working arrays the
// kernels step, the plan that arranged them, and the muscle-target and sine-row state.
//
// One plain struct, as MuJoCo's mjData, filled once by build() and then stepped.
// The files of core/fused/, each named for what it holds:
//   scene_data.hpp      this struct (the arrays; lane order helpers)
//   plan.cpp            build(): working order of the points, the order the link pass
//                       computes the links in (arrange_links, order_by_need), impulse
//                       slots, muscle groups, lane tables of the frame in registers
//   kernels.hpp         the SIMD kernels as templates over simd_ops (links, masses,
//                       muscle targets, sine arguments) and the frame loop (run_chunk)
//   register_frame.hpp  whole frames in AVX-512 registers (small scenes)
//   kernel_table.hpp    choosing a kernel per instruction set and specialisation;
//   kernels.cpp           the kernels compiled per instruction set (one unit)
//   sine_rows.hpp/.cpp  muscle targets from shared rows of sines
//   ordered.cpp         masses one by one in file order; autoreverse and bars after
//                       the SIMD mass pass
//   fused_scene.cpp     FusedScene: loading and storing states, the chunked run loop
// Sections of the struct:
//  - creatures: the models of the scene and where their masses sit;
//  - points: every point of every creature as (x, y) pairs in working order;
//  - per-mass parameters: each mass's own creature's world, in lane order;
//  - links: the acting links in the order the link pass computes them, and the
//    impulse slots that give each mass its impulses in its model's file order;
//  - the frame in registers (reg_*): lane tables for scenes of up to 16 points;
//  - muscle targets and sine rows: the shared sines of the next frames.
// Internal to core/fused/.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/detail/aligned_vector.hpp"
#include "core/detail/simd_ops.hpp"
#include "core/exact_sines.hpp"
#include "core/fast_step.hpp"
#include "core/model.hpp"
#include "core/physics_rules.hpp"
#include "core/scene_analysis.hpp"

namespace soda::fused {

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

inline int width_of(SimdLevel level) {
  switch (level) {
    case SimdLevel::Avx512: return 8;
    case SimdLevel::Avx2: return 4;
    default: return 2;
  }
}

struct SceneData {
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
    SineJitter jitter; ///< the sine jitter its rows and targets were made with (run sets it)
    Surface bar_surface; ///< what its bars respond with (its surface and container), for collide_with_fixed_bars
  };
  std::vector<Creature> creatures;
  bool any_wave = false, any_gravity = false;
  BarKind bars = BarKind::None; ///< the strongest kind among the creatures (KernelChoice::bars)

  // Working points, as (x, y) pairs: masses [0, masses) (the creatures' masses one
  // creature after the other), padding masses [masses, padded_masses) (at rest at (0, 0);
  // their results are never read), fixed nodes [padded_masses, padded_masses + fixed_points), and one
  // spare pair.
  int masses = 0, padded_masses = 0, fixed_points = 0, spare_point = 0;
  AVec<double> positions, velocities;  ///< [2*(spare_point+1)] x, y / vx, vy pairs
  AVec<double> side_hit;      ///< [2*padded_masses] side wall hit this frame (-1, 0, +1), twice per mass
  // Per-mass parameters, per block of W masses in kLaneLink order (as load_pairs
  // puts the masses in lanes): each mass's own creature's values.
  AVec<double> mass_gravity_step;        ///< gravity * direction, as rules::apply_gravity forms it
  AVec<double> mass_air_keep;      ///< 1 - friction, as rules::friction_factor forms it
  AVec<double> mass_width, mass_height, mass_surface_friction, mass_surface_reflection;

  // Links that can act (a free end) in the order the link pass computes them
  // (arrange_links), with dummy links from a point to itself (length 0: no
  // impulse) where a block needs one, padded to a multiple of kMaxWidth likewise.
  struct ActingLink {
    int creature = -1;    ///< -1: a dummy link from point `dummy` to itself
    int link = 0;         ///< index in its model
    bool swapped = false; ///< end A is the file's end b (arrange_links: exact)
    bool wave = false;    ///< a wave muscle (its target changes per frame)
    int dummy = 0;        ///< working index of a dummy's point
  };
  int link_slots = 0, padded_link_slots = 0; ///< link slots in use (links and dummies), padded
  std::vector<std::uint32_t> end_a_offset, end_b_offset; ///< [padded_link_slots] 2 * working index of the ends (offset in positions)
  // Per block of W link slots: -1, or b when the A ends of the block are the W
  // masses [W*b, W*b + W) in slot order, loaded as two whole vectors.
  std::vector<std::int32_t> a_end_block;
  bool points_in_registers = false;  ///< the link pass keeps the points in registers (Avx512Ops)
  AVec<std::int64_t> end_a_point, end_b_point; ///< [padded_link_slots] working index of the ends, lane order (registers only)
  // Impulses as (x, y) pairs: pair k = end A of acting link k (+c*d), pair
  // padded_link_slots + k = end B (-c*d), pair 2*padded_link_slots = (-0, -0), the identity of +.
  AVec<double> impulses; ///< [4*padded_link_slots + 2]
  std::int32_t identity_impulse = 0;
  // Impulse pairs per mass in file order of its model's links, by groups of
  // kGatherGroup consecutive masses (masses are numbered by degree): group b,
  // round r, lane l at the next impulse_slots; lists shorter than the group's longest
  // are padded with identity_impulse (fixed trip counts: no branch mispredictions).
  std::vector<std::uint32_t> impulse_slots;      ///< double offsets into impulses (2 * pair)
  std::vector<std::int32_t> group_rounds; ///< per gather group
  std::vector<std::int32_t> first_slot_of_mass; ///< [masses] first slot of mass i; its rounds stride kGatherGroup
  std::vector<std::int32_t> rounds_of_mass;
  // The whole frame in registers (AVX-512; at most 16 points and 32 link slots,
  // no bars): register_chunk. Points sit as load_pairs puts them (lane l of block
  // r: working point 8r + kLaneLink(8, l)), impulses as the link pass computes them.
  bool frame_in_registers = false;
  AVec<std::int64_t> reg_end_a_lane, reg_end_b_lane; ///< [padded_link_slots] lane order: register lane of each end
  // Per mass block and round of its sums: which impulse each lane adds (a lane of
  // the link blocks 0-1 by a two-register permute, of block 2-3 where the bit of
  // reg_upper_blocks is set), with which sign (-0.0: an end B), or nothing (reg_has_impulse clear:
  // the lane adds -0.0, sign -0.0).
  AVec<std::int64_t> reg_impulse_lane; ///< [8 per round]
  AVec<double> reg_impulse_sign;        ///< [8 per round]
  std::vector<std::uint8_t> reg_upper_blocks, reg_has_impulse;
  std::vector<int> reg_rounds; ///< [mass blocks]
  std::vector<std::uint8_t> reg_real_links; ///< [link blocks] lanes of real links (not dummies, not padding)
  AVec<double> link_target;    ///< [padded_link_slots] desired length D, per block in kLaneLink order
  AVec<double> link_springyness;    ///< [padded_link_slots] springyness of the link's model, same order
  // -1 where the link is computed from its end b (ActingLink::swapped), else +1, same
  // order. Its impulse must come from the file's difference b - a, which for such
  // a link is the pass's a - b: the pass's b - a negated, except where both are +0
  // (equal coordinates), and that +0's sign reaches a velocity of -0. Each end
  // then takes its pair by the file's ends (the impulse_slots).
  AVec<double> link_swap_sign;

  // Wave muscles (muscles whose power Aw*Am is not 0), first in the link order,
  // so target slots [0, padded_wave_muscles) are the ones that change per frame:
  // target = rest * (1 + power * sine[group]) (springs sharing those blocks have
  // power 0: rest * (1 + +-0) = rest exactly).
  int wave_muscles = 0, padded_wave_muscles = 0;
  std::vector<double> muscle_rest, muscle_power; ///< [padded_wave_muscles] rest length, Aw*Am
  std::vector<std::int32_t> muscle_group;    ///< [padded_wave_muscles] index into a row of sines
  // Rows of at most kRegisterPoints sines (Avx512Ops) sit in two registers while
  // the targets are formed: a muscle's sine is then one permute, not a gather.
  bool sines_in_registers = false;
  AVec<std::int64_t> muscle_group_lane;      ///< [padded_wave_muscles] muscle_group as permute indices
  std::vector<double> group_phase;       ///< distinct muscle phases, per creature
  int groups = 0;                        ///< all creatures'
  // Sines for this frame and the next rows - 1, computed for the phases each
  // creature's wave will have if its direction does not change (fill_rows). A row
  // is used only while every creature's phase is the row's, bit for bit; else all
  // rows are refilled.
  int rows_per_fill = 1, row_count = 0, row_next = 0;
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
  long long sines_evaluated = 0;
  long long bar_rules_run = 0; ///< masses that took the bar rules (bar_pass, ordered_masses)
  SinFn sine_fn = nullptr; ///< exact_sin_fn of the level (soda::sine alone without vector_sines), chosen at build
  // Wave states (fill_rows): creatures whose waves are in the same state (phase
  // bits, direction, speed bits) have the same rows of phases, and a muscle phase
  // they share then gives bit-identical sine arguments: each distinct (state,
  // muscle phase) pair is one argument per row (number_arguments).
  int muscle_phases = 0;                   ///< distinct muscle phases of the whole scene
  std::vector<int> muscle_phase_of_group;          ///< [groups] index of the group's phase among them
  int wave_states = 0;                    ///< wave states of this numbering
  std::vector<int> wave_state_of;        ///< [creatures] wave state of each wave creature
  std::vector<int> wave_state_leader;      ///< [creatures] first creature of each wave state
  bool numbering_valid = false;      ///< the arguments below are numbered for wave_state_of
  int distinct_arguments = 0;                  ///< distinct arguments per row
  std::vector<int> argument_of_key;         ///< [creatures * muscle_phases] distinct argument of (state, phase), -1: none
  std::vector<int> key_of_argument;         ///< [groups] (state, phase) key of each distinct argument
  std::vector<int> first_argument_of_state;      ///< [states + 1] first argument of each wave state
  std::vector<double> argument_muscle_phase;    ///< [groups, padded] the muscle phase of each distinct argument
  std::vector<int> argument_of_group;        ///< [groups] distinct argument of each group
  /// [(rows + 1) * creatures] wave state k's phase in row r at r * creatures + k;
  /// row r + 1 holds rules::advance_wave_phase of row r (the last one too)
  std::vector<double> row_phase;
  AVec<double> arguments, argument_sines;   ///< [rows * distinct, padded] the arguments of each row, their sines
  AVec<double> group_sines;              ///< [rows * groups, padded] sines by group (remapped, in registers)
  // Where the targets read their sines: the row of a frame starts at sine_rows +
  // row * sine_stride and muscle slot q's sine is at sine_index[q] in it. Either
  // the sines by group (argument_sines when every argument is distinct, else group_sines;
  // sine_index = muscle_group), or, after a numbering that shared arguments between
  // creatures, the distinct sines themselves (sine_index = muscle_argument, argument_of_group of
  // muscle_group[q]): copying them out per group and row cost more than the targets (a
  // GA scene: 13 rows of 74 groups from 56 distinct sines). Scenes with their sines
  // in registers read by group (muscle_targets permutes by group).
  double* sine_rows = nullptr;
  int sine_stride = 0;
  const std::int32_t* sine_index = nullptr;
  std::vector<std::int32_t> muscle_argument; ///< [padded_wave_muscles]
  AVec<std::int64_t> muscle_argument_lane;   ///< [padded_wave_muscles] muscle_argument as permute indices
  const std::int64_t* sine_lane = nullptr; ///< sine_index as permute indices (muscle_group_lane or muscle_argument_lane)

  // Fixed bars after the SIMD mass pass (bar_pass, ordered.cpp), each creature's
  // bars with its own memory (its State's bar_memory): each mass's move as the pass
  // made it (its start, and its velocity after friction: the end before the
  // container is start + velocity), and which masses (file order) a bar remembers
  // or a corner holds: those and the masses whose move may touch a bar's box take
  // the bar rules; for the others the rules would change nothing.
  // A scene mass index is a creature's mass_base + the mass's file index: ordered by
  // creature, then file order within each (the order its bar rules run in).
  std::vector<int> bar_creatures;        ///< creatures with fixed bars
  AVec<double> move_start, move_velocity; ///< [2*padded_masses] (x, y) pairs
  std::vector<std::uint32_t> bar_touch; ///< [padded_masses / W] lanes whose move may touch a bar (may_touch_bars)
  // Each mass keeps the tile (FixedBars::cell_tile) of where it was, as long as its
  // moves stay inside: per block of W masses, kTileValues vectors (the tile's x
  // range, its box) in lane order. The masses of creatures without bars keep an
  // endless tile with an empty box.
  static constexpr int kTileValues = 6;
  AVec<double> mass_tile; ///< [kTileValues * padded_masses]
  void keep_tile(int i, double x); ///< mass i (working) takes the tile of x
  /// Where mass i's (working) first tile value sits in mass_tile (the next at + W...).
  [[nodiscard]] std::size_t tile_at(int i) const {
    const int j = i & (W - 1); // W is 2, 4 or 8 (no division on the bar rules' path)
    const int base = i - j;
    const int lane = j < W / 2 ? 2 * j : 2 * (j - W / 2) + 1; // kLaneLink inverted
    return kTileValues * static_cast<std::size_t>(base) + static_cast<std::size_t>(lane);
  }
  /// Bits by scene mass index: held by a bar or corner; due for the rules this
  /// frame; of a creature with bars.
  std::vector<std::uint64_t> bar_held, bar_due, bar_scene_mask;
  std::vector<std::uint64_t> bar_rules_mask; ///< bar_scene_mask less the parked creatures (this run)
  /// Creature c stopped in run_until: its results are dropped, so its masses no
  /// longer take the bar rules (until the next run).
  void park(int c);
  std::vector<int> file_of_work;      ///< [masses] working index -> scene mass index
  std::vector<int> creature_of_mass; ///< [masses] working (or scene) mass index -> creature

  std::vector<KernelChoice> used;
  KernelChoice last;

  [[nodiscard]] double& px(int w) { return positions[2 * static_cast<std::size_t>(w)]; }
  [[nodiscard]] double& py(int w) { return positions[2 * static_cast<std::size_t>(w) + 1]; }
  [[nodiscard]] double& pvx(int w) { return velocities[2 * static_cast<std::size_t>(w)]; }
  [[nodiscard]] double& pvy(int w) { return velocities[2 * static_cast<std::size_t>(w) + 1]; }

  // The plan (plan.cpp): build() in its steps.
  void build(const std::vector<const Model*>& models, long long budget, FastStepOptions opt);
  void place_points(const std::vector<const Model*>& models, long long budget);
  void set_mass_parameters();
  std::vector<ActingLink> order_links();
  std::vector<std::vector<std::int32_t>> place_links(const std::vector<ActingLink>& acting);
  [[nodiscard]] std::vector<int> lane_slot_of_link() const;
  void place_link_ends_in_lanes(const std::vector<int>& slot_of_link);
  void set_link_parameters(const std::vector<ActingLink>& acting, const std::vector<int>& slot_of_link);
  void prepare_sine_rows();
  void place_bars();
  void plan_register_frame(const std::vector<ActingLink>& acting, const std::vector<int>& slot_of_link,
                           const std::vector<std::vector<std::int32_t>>& per_mass);
  void arrange_links(std::vector<ActingLink>& acting);
  void order_by_need(std::vector<ActingLink>& acting);
  /// Working index of end a (or b) of acting link l of a creature: below masses for a
  /// mass, from padded_masses on for a fixed node.
  [[nodiscard]] int working_end(const ActingLink& l, bool b_end) const {
    const Creature& cr = creatures[l.creature];
    const Model& m = *cr.model;
    return cr.work_of_point[b_end ? m.link_b[l.link] : m.link_a[l.link]];
  }
  /// Whether whole frames of this scene with `links` link slots run in registers
  /// (register_chunk): AVX-512, at most 16 points and 32 link slots, no bars.
  [[nodiscard]] bool frames_fit_registers(int links) const {
    return options.register_frames && simd == SimdLevel::Avx512 && padded_masses + fixed_points <= Avx512Ops::kRegisterPoints &&
           links <= 4 * kMaxWidth && bars == BarKind::None && !options.force_ordered;
  }
  void load_state(State* const* st);
  void store_state(State* const* st);
  // Muscle targets and sine rows (sine_rows.hpp, sine_rows.cpp).
  [[gnu::always_inline]] const double* row_for_frame(State* const* st);
  [[nodiscard]] std::size_t row_at(int c, int r) const;
  [[nodiscard]] bool same_wave(State* const* st, int a, int b) const;
  void leave_rows();
  void update_targets(State* const* st);
  void fill_rows(State* const* st);
  void jitter_sines(State* const* st, int filled); ///< after the sines of a fill (sine_rows.cpp)
  void number_arguments(State* const* st);
  [[nodiscard]] [[gnu::always_inline]] double advance_phase(int c, const State& st) const;
  [[gnu::always_inline]] void advance_waves(State* const* st);
  void ordered_frame(State& s);
  void replay_side_hits(State* const* st);
  void ordered_masses(State& s);
  void collide_with_bars(State& s, int c, int p, int i, const MassMove& move);
  rules::MassStepResult move_one_mass(const rules::MassConstants& k, int i, double& x, double& y, double& vx,
                                      double& vy) const;
  void watch_bars(State* const* st);
  void bar_pass(State* const* st);
  void bar_rules(State& s, int c, int p);
  void record(const KernelChoice& k);
};

} // namespace soda::fused
