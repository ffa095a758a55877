// LockstepBatch: creatures of one shape, one per SIMD lane; several such groups
// stepped frame by frame together.
//
// Why: a fused scene (fused_scene.hpp) takes any mix of creatures, at the price of
// moving every impulse to its mass by permutes or index loads; and a small
// creature alone is a short dependency chain per frame that leaves the core
// mostly idle. Creatures of one shape (the same number of masses and fixed
// nodes and the same links between them, in the same file order) can instead
// sit one per lane: lane l of every vector is creature l, and the reference step
// (step.cpp) runs as written, link by link in file order, each operation on 8
// creatures at once. Nothing is gathered or reordered, so every lane does the
// reference's operations in the reference's order: the same bits, by
// construction (tests/test_lockstep_batch.cpp checks them).
//
// Everything else may differ per lane: positions, velocities, rest lengths,
// which links are muscles and their phases and amplitudes, the wave, the world
// (gravity, friction, springyness, container, surfaces). That is what a genetic
// algorithm's population holds: most children are their parent's shape with
// other numbers (BatchStepper, batch_step.cpp, groups them by shape).
//
// Groups: a batch holds groups of at most 8 lanes, each group of one shape, the
// groups of any shapes (of_shapes). All groups step frame by frame together: a
// small creature's frame is a short dependency chain, and the chains of other
// groups fill the core while one waits (the GA's creatures average 6 links, and
// its evaluation batches hold 16 creatures x 8 replicas: 16 groups). Two groups
// at a time share one pass over their links and masses, each in its own order,
// so that their chains interleave (measured ~25 % faster than one at a time).
//
// Muscle sines: one per frame per distinct muscle phase of a lane (a column of
// links whose phases agree in every lane of the group shares it), Java's Math.sin in
// SIMD (exact_sines.hpp), for all lanes at once. Where every lane of a group has
// the same phase in each column and the same wave phase (replicas of one
// creature, until a wall turns one lane's wave), the lanes' arguments are equal:
// the sines are computed once per column and broadcast to the lanes (the same
// bits: the same operations on the same operands), the columns of all such
// groups packed 8 to a vector (a GA creature has about 4). A lane
// whose state carries sine jitter (sine_jitter.hpp: replicas of one creature,
// each its own seed) gets its sines moved before they are used, lane by lane
// from the same arguments as the reference's; groups with no jittered lane skip
// that work, and shared sines are copied to the lanes only in a frame where the
// hash moves one of them.
//
// Walls: the floor is tested every frame (a max per coordinate); the ceiling
// and the side walls too, except in a frame where every mass of the group is
// further from them than a mass can move in a frame (known from the previous
// frame's positions for a few compares per mass; there the tests would change
// nothing).
//
// Fixed bars (race lanes, terrains; fixed_bars.hpp): lanes of one shape also have
// the same bars (same_shape compares their geometry). The masses move in SIMD as
// without bars, each lane keeping each mass's move (its start and the velocity it
// takes); after the mass pass each lane runs the bar rules as FastStepper does
// (fused/ordered.cpp bar_pass): in file order, against its own State's BarMemory,
// for the masses a bar remembers or a corner holds and those whose move may touch
// a bar's box; the rules of the others would change nothing (a mass's rules read
// and change only its own move and memory). Autoreverse stays with the wall hit
// (a bar hit does not undo it), and every wall is tested in every frame (a bar's
// push-off is not bounded by the speed limit). Bars with a mass at an end
// (BarKind::MovingEnds) are not taken.
//
// Instruction sets: AVX-512 (a group's 8 lanes in one vector) or AVX2 (in two),
// chosen at run time (usable(), of_shapes' level); the same kernels
// (detail/lockstep_kernels.hpp) at both, so the same bits.
// The batch copies what it needs of the Models when it is built (a Model changed
// afterwards is not seen: build a new batch). One batch is used by one thread at a
// time, and each state must be a different object.
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "model.hpp"
#include "simd_level.hpp"

namespace soda {

class BatchStepper;

class LockstepBatch {
 public:
  /// Creatures per vector.
  static constexpr int kLanes = 8;

  /// Whether this machine runs the batch at `level` (Auto: at AVX2 or AVX-512,
  /// the best it has; AVX-512 needs F and DQ). SSE2 has no lockstep kernels.
  static bool usable(SimdLevel level = SimdLevel::Auto);
  /// The level a batch made for `level` runs at: Auto's best (AVX-512, else AVX2).
  static SimdLevel level_for(SimdLevel level);
  /// Whether `model` can be in a batch (no fixed bar with a mass at an end).
  static bool can_take(const Model& model);
  /// Whether two models have one shape: the same masses and fixed nodes (by
  /// count) and the same links, end for end, in file order, and the same fixed
  /// bars (ends, geometry, box rule) if any; both taken (can_take).
  static bool same_shape(const Model& a, const Model& b);

  /// Throws std::invalid_argument when `models` is empty, a model cannot be taken,
  /// or two models differ in shape, and std::runtime_error when !usable(level).
  explicit LockstepBatch(const std::vector<const Model*>& models, SimdLevel level = SimdLevel::Auto);
  /// Several shapes in one batch: shapes[s] are models of one shape (as for the
  /// constructor), cut into groups of kLanes; run() takes their states in this
  /// order (shapes[0]'s, then shapes[1]'s, ...). Throws as the constructor, also
  /// when `shapes` or one of them is empty.
  static LockstepBatch of_shapes(const std::vector<std::vector<const Model*>>& shapes, SimdLevel level = SimdLevel::Auto);
  /// The instruction set the batch's kernels run (Avx512 or Avx2).
  [[nodiscard]] SimdLevel level() const;
  ~LockstepBatch();
  LockstepBatch(LockstepBatch&&) noexcept;
  LockstepBatch& operator=(LockstepBatch&&) noexcept;
  LockstepBatch(const LockstepBatch&) = delete;
  LockstepBatch& operator=(const LockstepBatch&) = delete;

  /// Steps states[c] (a state of model c) by `frames` frames, for every c;
  /// afterwards each equals, bit for bit, soda::run(*models[c], *states[c], frames),
  /// with the state's sine jitter (throws std::invalid_argument for an invalid one).
  void run(State* const* states, long long frames);
  /// `stop(c, min_x, max_x)`: whether state c ends after this frame, from its free
  /// masses' least and greatest x (in mass order, as FastStepper::run_until takes them).
  using StopFn = std::function<bool(int, double, double)>;
  /// Steps each state until `stop` holds for it after a frame, at most `frames`
  /// frames; done[c] gets the frames state c ran, and the state equals what
  /// FastStepper::run_until(state, frames, stop for c) leaves, bit for bit (a race's
  /// finish: race replicas). Returns the frames the batch ran (the most of done).
  long long run_until(State* const* states, long long frames, const StopFn& stop, std::vector<long long>& done);

  [[nodiscard]] int size() const;
  /// Groups of at most kLanes lanes.
  [[nodiscard]] int group_count() const;
  /// Sine columns per lane and frame of group g (distinct muscle phases with a moving wave).
  [[nodiscard]] int sine_columns(int g = 0) const;
  /// Whether group g's lanes share their muscle phases, column by column (replicas
  /// of one creature): their sines are computed once per column while their waves agree.
  [[nodiscard]] bool shares_sines(int g) const;
  /// Lane-moves that took the fixed-bar rules since construction (bar_pass); for
  /// tests and diagnostics (FastStepper::bar_rules_run counts the same for one state).
  [[nodiscard]] long long bar_rules_run() const;

  struct Data;

 private:
  LockstepBatch(std::unique_ptr<Data> d, int groups); // of_shapes' (two arguments: LockstepBatch({}) stays unambiguous)
  /// run() without its checks of the states, for BatchStepper, which has made them.
  void step(State* const* states, long long frames);
  /// step, each state until `stop` (if given) holds for it; done[c] its frames.
  long long step_until(State* const* states, long long frames, const StopFn* stop, long long* done);
  friend class BatchStepper;
  std::unique_ptr<Data> d_;
};

} // namespace soda
