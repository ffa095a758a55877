// BatchStepper: K independent models stepped together on one thread.
//
// Why: the genetic algorithm scores many small creatures, so what counts is
// creature-frames per second per core. One small creature alone cannot keep the
// core busy: each frame is a short dependency chain (positions -> link square
// roots and divisions -> impulse sums -> masses -> next frame), a few SIMD batches
// of links cannot fill the square-root/divide pipeline, and the per-frame overhead
// is paid for a handful of links. Fusing K creatures into one scene (FusedScene,
// fused_scene.hpp, the same engine FastStepper runs) puts their links in shared
// SIMD batches and interleaves their chains, for K times the work per frame at
// the same overhead.
//
// Fusing pays only while the scene stays small: a fused scene's impulse arrays
// must stay in the L1 cache, and a creature of a few hundred links already fills
// the SIMD batches on its own (16 monster trucks fused stepped slower than one
// alone: bench/README.md, "Design figures"). So the models are packed, in order,
// into scenes of at most kMaxFusedLinks links; a bigger model gets a scene of its
// own.
//
// Exact: after run(), every state equals bit for bit what soda::run gives for its
// model alone (fused_scene.hpp explains why; tests/test_batch_step.cpp checks it).
// Models with fixed bars (race lanes: each its own terrain) are fused too, among
// themselves: a scene with bars tests every wall every frame and runs the bar pass
// after the mass pass, which models without bars would pay for in the same scene.
//
// Models of one shape (LockstepBatch::same_shape: the same masses and links, and
// the same fixed bars if any, any other numbers), kMinLockstep or more of them
// (lockstep_share), that share few muscle sines (shared_sine_fraction), run
// instead in a LockstepBatch (lockstep_batch.hpp), one creature per SIMD lane,
// where the CPU has AVX2 or AVX-512: measured faster than fusing them (bench
// speed, fast-batch; results/bench/avx2_profile.md for AVX2). Exact either way.
// All shapes' groups go in one LockstepBatch, which steps them frame by frame
// together (a group of a small creature alone leaves the core mostly idle).
//
// Sine jitter (sine_jitter.hpp): replicas of one creature are the same Model given
// several times, each state with its own jitter seed. Such replicas (kMinLockstep
// or more of a shape) go in lockstep whatever their sines, each lane jittered on
// its own; a jittered state left over goes in a fused scene (its own wave state
// there: its sines are not shared). Which states carry jitter is seen in run():
// the plan is made again when that changes.
//
// The Models must outlive the stepper; one stepper is used by one thread at a time.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "fast_step.hpp"
#include "lockstep_batch.hpp"
#include "model.hpp"

namespace soda {

class FusedScene;

/// Most links (springs and muscles) fused in one scene (see above).
inline constexpr int kMaxFusedLinks = 512;

/// Fewest models of one shape run as a LockstepBatch: with fewer, the lanes left
/// empty cost more than fusing would (bench/README.md, "Design figures").
inline constexpr int kMinLockstep = 6;

/// The share of the muscle sines of models[members] (counted once per distinct
/// phase in each model) that a fused scene computes once for several models (the
/// same wave start and muscle phase), 0 to 1.
double shared_sine_fraction(const std::vector<const Model*>& models, const std::vector<int>& members);

/// Above this share a shape is fused, where a sine shared between creatures is
/// computed once; lockstep lanes each compute their own. Small creatures sharing
/// every sine step faster fused, larger ones still faster in lockstep, and on the
/// GA's own workload the rule makes no measurable difference (its batches seldom
/// hold kMinLockstep of a shape): bench/README.md, "Design figures".
inline constexpr double kMaxSharedSines = 0.25;

/// How many of `count` models of one shape BatchStepper runs in lockstep: whole
/// vectors of LockstepBatch::kLanes, and the rest too if it fills kMinLockstep
/// lanes (else the rest is fused).
inline int lockstep_share(int count) {
  constexpr int lanes = LockstepBatch::kLanes;
  const int rest = count % lanes;
  const int share = count - rest + (rest >= kMinLockstep ? rest : 0);
  return share >= kMinLockstep ? share : 0;
}

/// Whether a model of `links` links starts a new scene after a non-empty scene of
/// `scene_links` links (the packing rule of BatchStepper).
inline bool starts_new_scene(int scene_links, int links) { return scene_links + links > kMaxFusedLinks; }

/// Consecutive batches of at most `max_models` models (links[i]: model i's links),
/// cut where BatchStepper starts a new fused scene anyway (for models alike in
/// having fixed bars or not: BatchStepper packs those with bars apart, and
/// run_races_together, whose lanes all have bars, cuts its scenes by this too). Returns each batch's
/// end index. Why: a work item for a thread pool should be as small as fusing
/// allows; a batch of 16 mixed creatures holds several scenes run one after the
/// other, and 12 such batches on 2 threads leave one thread idle for up to a
/// batch at the end. Cutting at scene boundaries loses nothing of the fusing.
std::vector<std::size_t> fused_batch_ends(const std::vector<int>& links, std::size_t max_models);

class BatchStepper {
 public:
  /// `models[i]` may repeat (each entry has its own state). `frame_budget` as for
  /// FastStepper. `jittered[i]`: whether state i will carry sine jitter (empty: none),
  /// so that the plan fits the first run; run() plans again if that turns out wrong.
  BatchStepper(const std::vector<const Model*>& models, long long frame_budget, FastStepOptions options = {},
               const std::vector<bool>& jittered = {});
  ~BatchStepper();
  BatchStepper(BatchStepper&&) noexcept;
  BatchStepper& operator=(BatchStepper&&) noexcept;
  BatchStepper(const BatchStepper&) = delete;
  BatchStepper& operator=(const BatchStepper&) = delete;

  /// Steps states[i] (a state of models[i]) by `frames` frames, for every i;
  /// afterwards each equals, bit for bit, soda::run(*models[i], *states[i], frames),
  /// with each state's sine jitter (throws std::invalid_argument for an invalid one).
  void run(const std::vector<State*>& states, long long frames);

  [[nodiscard]] int size() const { return count_; }
  /// Models fused or in lockstep (not alone),
  /// as planned for the last run (before any run: for exact states).
  [[nodiscard]] int fused_count() const;
  /// Models in lockstep batches.
  [[nodiscard]] int lockstep_count() const;
  /// Number of fused scenes.
  [[nodiscard]] int scene_count() const { return static_cast<int>(scenes_.size()); }

 private:
  struct Scene {
    std::unique_ptr<FusedScene> scene;
    std::vector<int> index; ///< index in the batch of scene model c
  };
  int count_ = 0;
  /// The models in lockstep, every shape's groups in one batch (they step frame by
  /// frame together: lockstep_batch.hpp).
  std::optional<LockstepBatch> lockstep_;
  std::vector<int> lockstep_index_;   ///< index in the batch of lockstep state c
  std::vector<Scene> scenes_;         ///< the other fusable models, packed by kMaxFusedLinks
  std::vector<FastStepper> alone_;    ///< FastStepOptions::force_ordered: each model alone
  std::vector<int> alone_index_;
  std::vector<State*> scratch_;
  std::vector<int> point_count_; ///< [count_] points of models[i] (run checks the states)
  std::vector<const Model*> models_;
  long long frame_budget_ = 0;
  FastStepOptions options_;
  std::vector<bool> planned_jitter_; ///< [count_] which states carried jitter when planned

  /// Splits the models into lockstep batches, fused scenes and the rest, given
  /// which states carry jitter.
  void plan(const std::vector<bool>& jittered);
};

} // namespace soda
