// LockstepBatch::Data: the lanes' rows and the plan of a lockstep batch, shared by
// its construction (lockstep_plan.cpp: groups, columns, layout, load/store) and its
// frame kernels (lockstep_kernels.hpp, compiled per instruction set).
//
// Why a header of its own: the construction is plain C++ and the kernels are
// compiled for AVX-512 or AVX2; one file held both past the project's size limit.
// Private to those files (core/detail/).
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/detail/aligned_vector.hpp"
#include "core/exact_sines.hpp"
#include "core/fixed_bars.hpp"
#include "core/lockstep_batch.hpp"

namespace soda {

namespace lockstep_detail {
/// Lanes of a group: one row of 8 doubles (an AVX-512 vector, or two AVX2 ones).
inline constexpr int kW = LockstepBatch::kLanes;
/// Groups stepped side by side in one pass over their links and masses (two,
/// three and four measured alike on the GA's creatures; one alone ~25 % slower).
inline constexpr int kSideBySide = 2;
} // namespace lockstep_detail

/// A level's frame kernels (lockstep_kernels.hpp): one frame of every group, and
/// group g's sines for the phase it has now.
struct LockstepEntry {
  void (*step_frame)(LockstepBatch::Data&) = nullptr;
  void (*sines_now)(LockstepBatch::Data&, int g) = nullptr;
};
LockstepEntry lockstep_kernels_avx512();
LockstepEntry lockstep_kernels_avx2();

// Lane l of group g is state groups[g].first + l (padding lanes past a group's
// own repeat its last state; their results are never read). Every per-lane value
// is a row of 8 doubles.
struct LockstepBatch::Data {
  static constexpr int kW = lockstep_detail::kW;
  /// A point's rows x, y, vx, vy in bytes (point_row).
  static constexpr std::uint32_t kPointBytes = 4 * kW * sizeof(double);
  SimdLevel level = SimdLevel::Avx512; ///< the kernels' instruction set (Avx512 or Avx2)
  LockstepEntry kernels;              ///< that level's
  struct Group {
    int first = 0, lanes = 0;            ///< its states: [first, first + lanes)
    int points = 0, masses = 0, links = 0;
    std::vector<int> link_a, link_b;     ///< point indices, file order (the group's shape)
    /// [2 * links] each link's ends a, b as byte offsets of their points in the
    /// block (kPointBytes each): the link pass addresses a point's four rows by
    /// constant displacements from one register, no index arithmetic.
    std::vector<std::uint32_t> link_ends;
    std::vector<int> wave_links;         ///< links with a moving target in some lane
    std::vector<int> column_of;          ///< [wave_links] its sine column
    int columns = 0;
    bool uniform = false;                ///< every lane has the same phase in each column
    bool jittered = false;               ///< some lane's state carries sine jitter (run)
    /// Where its rows start: a block of points, each x, y, vx, vy [points][4], links
    /// rest, power, target [3][links], column phases [columns] and the world
    /// [kWorldRows]; sine arguments and sines [columns]; shared ones: columns
    /// [pool_at, pool_at + columns) of the pool.
    std::size_t block = 0, sine_at = 0, pool_at = 0;
    bool bars = false;     ///< fixed bars (group_bars[g]): bar_pass after the mass pass
    std::size_t move_at = 0; ///< with bars: where its rows of moves start in `moves`
    std::size_t due_at = 0;  ///< with bars: where its masses' lanes start in `bar_due`
  };
  int count = 0;
  std::vector<Group> groups;
  std::vector<int> state_points; ///< [count] points of state c's model
  std::vector<std::pair<int, int>> schedule; ///< (first group, groups stepped side by side: same links)
  std::vector<std::uint8_t> schedule_bars;   ///< [schedule] some of those groups has fixed bars
  /// [groups] each group's fixed bars (one copy for its lanes: same_shape), empty without.
  std::vector<FixedBars> group_bars;
  /// Each bar group's moves of this frame, per mass: start x, y and the velocity
  /// the move takes (vx, vy) [4][masses] rows, for the bar rules (bar_pass).
  AVec<double> moves;
  std::vector<std::uint8_t> bar_held; ///< [masses] scratch: a bar remembers the mass (all 0 between uses)
  std::vector<std::uint8_t> bar_due;  ///< [masses of bar groups] lanes whose move may meet a bar (may_meet_bars)
  long long bar_rules_run = 0;        ///< lane-moves that took the bar rules
  SinFn sine_fn = nullptr;

  // kLeft, kRight, kTop: the walls are out of reach this frame where every mass
  // is right of kLeft, left of kRight and below kTop (walls_far).
  enum World { kSpringyness, kGravityStep, kKeep, kWidth, kHeight, kFs, kRs, kSpeed, kMode, kPhase, kLeft, kRight, kTop, kWorldRows };
  // One allocation: the distances between the rows, hence which loads and stores
  // share their low 12 address bits (a false dependency), are then the same in
  // every run; with four allocations the speed changed from process to process
  // (bench/README.md, "Design figures").
  AVec<double> rows;
  // Sines of the next frame: computed during this frame's links (where the
  // square-root/divide unit is the bottleneck and the other units idle), for the
  // phase each wave will have if no lane's direction turns; a group whose phase
  // came out otherwise gets them again after the frame (sines_now). A group whose
  // lanes share them (packed) has one per column in the pool, the columns of all
  // such groups one after the other, 8 to a row, each with its muscle phase and
  // its group's wave phase (pool_wave): a row's arguments are then those of each
  // column's group, whatever groups the row holds.
  AVec<double> arguments, sines;                                      ///< rows at sine_at
  AVec<double> pool_phase, pool_wave, pool_arguments, pool_sines;     ///< columns at pool_at
  int pool_rows = 0;
  std::vector<std::uint8_t> redo;   ///< [groups] the wave turned: sines again after the frame
  int total_links = 0;              ///< the link passes of a frame, over all steps
  int sine_rows = 0, sines_done = 0, sine_credit = 0; ///< a frame's sines, spread over its link passes
  unsigned far_lanes = 0; ///< lanes the vector sine leaves to soda::sine (|x| >= 90112, NaN): none from phases in [0, 1)
  AVec<double> predicted;        ///< [groups] rows: the phase the sines are for
  std::vector<std::uint8_t> packed; ///< [groups] the group's sines are the packed ones
  /// [groups] no mass of any lane can reach the ceiling or a side wall this frame
  /// (the floor is tested always: walkers touch it every frame).
  std::vector<std::uint8_t> walls_far;
  bool inline_sines = false;     ///< the CPU has the vector sine (exact_sines.hpp)
  std::vector<std::uint8_t> autoreverse; ///< [groups * 8]
  std::vector<State*> lane_state;        ///< [groups * 8] the state each lane loads from
  /// [groups * 8] each lane's sine jitter as PreparedJitter holds it (threshold 0:
  /// exact), in rows that jitter_sines loads 8 lanes at a time.
  std::vector<std::uint64_t> lane_seed_mix, lane_threshold;
  std::vector<std::pair<const double*, double*>> sine_work; ///< (arguments, sines) rows of a step
  // Until lay_out: each group's lane models [groups * 8] and the link of each of its columns.
  std::vector<const Model*> lane_models;
  std::vector<std::vector<int>> group_column_links;

  double* block_row(int g, std::size_t row) { return rows.data() + (groups[static_cast<std::size_t>(g)].block + row) * kW; }
  /// Row k (x, y, vx, vy) of point p: a point's four rows side by side (kPointBytes).
  double* point_row(int g, int k, int p) { return block_row(g, 4 * static_cast<std::size_t>(p) + static_cast<std::size_t>(k)); }
  double* link_row(int g, int k, int j) {
    const Group& G = groups[static_cast<std::size_t>(g)];
    return block_row(g, 4 * static_cast<std::size_t>(G.points) + static_cast<std::size_t>(k) * G.links + j);
  }
  double* column_row(int g, int q) {
    const Group& G = groups[static_cast<std::size_t>(g)];
    return block_row(g, 4 * static_cast<std::size_t>(G.points) + 3 * static_cast<std::size_t>(G.links) + q);
  }
  double* world_row(int g, int k) { return column_row(g, groups[static_cast<std::size_t>(g)].columns + k); }
  double* move_row(int g, int k, int p) {
    const Group& G = groups[static_cast<std::size_t>(g)];
    return moves.data() + (G.move_at + static_cast<std::size_t>(k) * G.masses + p) * kW;
  }
  double* arguments_row(int g, int q) { return arguments.data() + (groups[static_cast<std::size_t>(g)].sine_at + q) * kW; }
  double* sines_row(int g, int q) { return sines.data() + (groups[static_cast<std::size_t>(g)].sine_at + q) * kW; }
  double* pool(AVec<double>& v, int g) { return v.data() + groups[static_cast<std::size_t>(g)].pool_at; }

  void add_group(const std::vector<const Model*>& models, int first, int lanes);
  void lay_out();
  void load(State* const* st);
  void store_lane(int g, int l, State& s); ///< lane l of group g into its state s
  void bar_pass(int g);
};

} // namespace soda
