// FusedScene: one or more independent models stepped as one scene.
//
// This is the engine behind FastStepper (one model) and BatchStepper (K models
// fused on one core, batch_step.hpp); its data, plan and kernels live in this folder
// (scene_data.hpp says which file holds what).
//
// Why fusing is exact: models never interact (the engine has no mass-mass
// collision), and bit-exactness only needs, per value, the reference's operations
// in the reference's order. So the masses of K models can sit side by side in one
// array, their links in one list computed in shared SIMD batches, as long as
//  - each mass adds its impulses in file order of its own model's links (the
//    per-mass slot lists keep that, whatever the fused order of the links);
//  - every parameter stays the creature's own: springyness per link; gravity
//    g*d, 1 - friction, container width and height, surface friction and
//    reflection per mass (vectors, not broadcasts); wave phase, direction, speed
//    and muscle sines per creature; autoreverse replayed per creature, in its mass
//    order, into its own State;
//  - a sine is computed once for all creatures whose waves are in the same state
//    (phase and speed bit for bit, same direction) and all their muscles with the
//    same phase bits: the same operations on the same bits give the same sine;
//  - the optional work is only ever skipped when it is an identity for every lane:
//    a wall is tested when some creature may reach it (testing an unreachable
//    wall changes nothing), gravity is applied when some creature has it (g*d = +0
//    is an identity for the others), targets are recomputed when some creature's
//    wave moved (recomputing an unchanged target gives the same bits).
// Fixed bars: each creature has its own (a race lane's terrain is part of its
// model) and keeps their memory in its own State. The bar rules run after the mass
// pass, each creature's masses in file order (bar_pass), only for the masses that
// may meet a bar; a scene may mix creatures with and without bars.
//
// The Models must outlive the scene; one scene is used by one thread at a time.
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "core/fast_step.hpp"
#include "core/model.hpp"
#include "core/scene_analysis.hpp"

namespace soda {

namespace fused {
struct SceneData; // scene_data.hpp
} // namespace fused

class FusedScene {
 public:
  /// `frame_budget` as for FastStepper. Throws std::invalid_argument if there are
  /// no models, or several with FastStepOptions::force_ordered (one model only).
  FusedScene(const std::vector<const Model*>& models, long long frame_budget, FastStepOptions options = {});
  ~FusedScene();
  FusedScene(FusedScene&&) noexcept;
  FusedScene& operator=(FusedScene&&) noexcept;
  FusedScene(const FusedScene&) = delete;
  FusedScene& operator=(const FusedScene&) = delete;

  /// Steps states[c] (a state of model c) by `frames` frames, for every model c.
  void run(State* const* states, long long frames);

  /// A scene of one model: steps `state` until `stop(min_x, max_x)` is true after a
  /// frame (the free masses' least and greatest x, taken in mass order with std::min
  /// and std::max), at most `frames` frames; returns the frames run. The state after
  /// n frames is what run gives for n frames. (A race ends when its contender passes
  /// the finish: checking that per frame inside the scene keeps the state and the
  /// rows of sines in place.)
  long long run_until(State& state, long long frames, const std::function<bool(double, double)>& stop);

  /// Whether creature c stops after a frame, given its free masses' least and greatest x.
  using StopFn = std::function<bool(int c, double min_x, double max_x)>;
  /// Several models, each state stepped until stop(c, ...) is true after a frame (as
  /// run_until above for each alone), at most `frames` frames; returns the frames
  /// the scene ran. done[c]: the frames states[c] ran, stopped[c]: whether it
  /// stopped. With min_running > 0 it returns as soon as fewer than that are still
  /// running (the caller may go on with a smaller scene of the rest: a stopped
  /// creature's masses are still stepped, without their bar rules, their results dropped).
  /// If `stop` throws, every state is left as after the frames it ran, and the
  /// exception goes on.
  long long run_until(State* const* states, long long frames, const StopFn& stop, std::vector<long long>& done,
                      std::vector<bool>& stopped, int min_running = 0);

  [[nodiscard]] int size() const;
  [[nodiscard]] const Model& model(int c) const;
  [[nodiscard]] const SceneNeeds& needs(int c) const;
  [[nodiscard]] bool used(const KernelChoice& k) const;
  [[nodiscard]] const KernelChoice& last_kernel() const;
  [[nodiscard]] long long sines_evaluated() const;
  [[nodiscard]] long long bar_rules_run() const;
  [[nodiscard]] bool points_in_registers() const;
  [[nodiscard]] bool frame_in_registers() const;

 private:
  std::unique_ptr<fused::SceneData> d_;
};

} // namespace soda
