// FastStepper: the exact SodaConstructor step (docs/physics.md), fast.
//
// Equal bit for bit to the reference step (step.hpp) for every model and every
// number of frames: same operations in the same order per value, only grouped
// differently.
//
// How (the engine is core/fused/; scene_data.hpp says which file holds what):
//  - scene analysis once per model (scene_analysis.hpp) picks specialised kernels:
//    no wave work without muscles, no gravity when it is +0, no bar tests without
//    bars, no wall test for walls no mass can reach in the next chunk of frames;
//  - muscle targets: one sin per distinct muscle phase per frame (shared), computed
//    for the next frames in one SIMD batch (the phases the wave will have if its
//    direction holds; a row is used only when the phase matches bit for bit), with
//    Java's Math.sin repeated in SIMD (exact_sines.hpp); the target update is skipped
//    while the wave phase does not change (manual mode, speed 0);
//  - links: impulses of all links computed in SIMD (SSE2, AVX2 or AVX-512, chosen
//    at run time; all bit-exact, no FMA in the physics) from positions only -
//    positions do not change while links act. Their order and which end is "A" are free (swapping
//    the ends negates dx, dy and the impulse exactly), so links are arranged in
//    blocks whose A ends are one block of consecutive masses (one vector load);
//    scenes of at most 16 points keep every point in registers (AVX-512). The
//    square root and division per link cost the same per instruction whatever the
//    width;
//  - masses: numbered by decreasing degree within each creature; each sums its
//    impulses in file order of the links (the order of the additions into one
//    velocity is the only order that matters), in groups of 8 consecutive masses
//    whose sums stay in registers for the rest of the mass step: gravity,
//    friction, rest test, move and walls, in SIMD over masses, with the frame
//    loop inside the specialised function;
//  - scenes of at most 16 points and 32 links (AVX-512; the Dainty Walker) run
//    whole frames in registers: positions, velocities, impulses and targets stay
//    in vector registers from frame to frame, each mass's impulses come by
//    permutes from the link registers (still added in file order), and nothing
//    is called per frame while a row of sines is ready (a call spills every
//    vector register);
//  - autoreverse hits are replayed in mass order; fixed bars: the masses move in
//    SIMD as without bars, each keeping its move, then the bar rules run in file
//    order for the masses a bar remembers or a corner holds and those whose move
//    may touch a bar's box (a vector test against the tile of the bars' x grid
//    each mass keeps); the rules of the others would change nothing (a mass's
//    rules read and change only its own move and memory).
//
// The engine is FusedScene (fused_scene.hpp) holding this one model; BatchStepper
// (batch_step.hpp) uses the same engine for several models at once.
//
// The Model must outlive the stepper. The stepper keeps scratch arrays, so one
// stepper is used by one thread at a time; make one per thread (cheap).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "model.hpp"
#include "scene_analysis.hpp"
#include "simd_level.hpp"

namespace soda {

class FusedScene;

struct FastStepOptions {
  SimdLevel simd = SimdLevel::Auto;
  /// Re-check, every chunk of frames, which walls a mass could reach (exact).
  bool adaptive_walls = true;
  /// Force the per-mass ordered kernel (masses one by one in file order); for tests.
  bool force_ordered = false;
  /// Muscle sines in SIMD, Java's Math.sin repeated operation for operation
  /// (exact_sines.hpp). Off: soda::sine one by one. Both give the same bits.
  bool vector_sines = true;
  /// Scenes of at most 16 points and 32 links (AVX-512) keep the whole frame in
  /// registers (positions, velocities, impulses). Off: the general kernels. Both
  /// give the same bits.
  bool register_frames = true;
  /// BatchStepper: models of one shape, enough of them, in a LockstepBatch (one
  /// creature per lane, AVX2 or AVX-512; lockstep_batch.hpp). Off: fused scenes. Both give
  /// the same bits.
  bool lockstep = true;
};

/// The kernel a chunk of frames ran with, for tests and diagnostics.
struct KernelChoice {
  SimdLevel simd = SimdLevel::Sse2;
  bool ordered = false; ///< masses one by one in file order (force_ordered)
  bool wave = false;
  bool gravity = false;
  WallNeeds walls;
  BarKind bars = BarKind::None;
  [[nodiscard]] std::string describe() const;
  bool operator==(const KernelChoice&) const = default;
};

class FastStepper {
 public:
  /// `frame_budget`: how many frames the caller means to run from the model's
  /// initial state (used by the scene analysis; running more is still exact).
  FastStepper(const Model& model, long long frame_budget, FastStepOptions options = {});
  ~FastStepper();
  FastStepper(FastStepper&&) noexcept;
  FastStepper& operator=(FastStepper&&) noexcept;
  FastStepper(const FastStepper&) = delete;
  FastStepper& operator=(const FastStepper&) = delete;

  /// Steps `state` (a state of this model) by `frames` frames; afterwards it equals,
  /// bit for bit, what soda::run(model, state, frames) gives.
  void run(State& state, long long frames);
  /// One frame (for traces).
  void step(State& state) { run(state, 1); }
  /// Steps until `stop(min_x, max_x)` holds after a frame (the free masses' least and
  /// greatest x, in mass order), at most `frames` frames; returns the frames run
  /// (FusedScene::run_until). A race checks its finish this way.
  long long run_until(State& state, long long frames, const std::function<bool(double, double)>& stop);

  [[nodiscard]] const SceneNeeds& needs() const;
  [[nodiscard]] const Model& model() const;
  /// Whether kernel `k` has run since construction; for tests.
  [[nodiscard]] bool used(const KernelChoice& k) const;
  [[nodiscard]] const KernelChoice& last_kernel() const;
  /// Sines evaluated since construction (shared per phase, skipped when the wave
  /// phase did not move).
  [[nodiscard]] long long sines_evaluated() const;
  /// Moves that took the fixed-bar rules since construction (the reference runs them
  /// for every moving mass; the fast path only for masses a bar remembers or whose
  /// move may touch a bar); for diagnostics.
  [[nodiscard]] long long bar_rules_run() const;
  /// Whether the link pass keeps every point in registers (AVX-512, at most 16
  /// points with the padding masses); for tests.
  [[nodiscard]] bool points_in_registers() const;
  /// Whether whole frames run in registers (FastStepOptions::register_frames:
  /// AVX-512, at most 16 points and 32 link slots, no bars); for tests.
  [[nodiscard]] bool frame_in_registers() const;

 private:
  std::unique_ptr<FusedScene> scene_; ///< a scene of this one model (fused_scene.hpp)
};

} // namespace soda
