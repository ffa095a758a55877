// WalkProblem: how far a creature walks on a flat floor, measured the same way
// every time (the Problem of every run today).
//
// A creature (a ModelDef of free masses and links) is first checked against the limits and
// prepared: the world applied (except the parameters the creature may evolve), scaled as the
// Sodarace racer scaled contenders (configs/README.md, /fitness/scaling) unless disabled, put
// in a container wide and tall enough that no wall can be reached at 20 px/frame, its lowest
// mass `drop_height` above the floor, wave forward, autoreverse off. The prepared model is
// exactly what `export` writes, so the original program runs it the same way. A rollout settles
// it for `settle_frames` and scores the centroid's displacement over the next `frames` frames
// in the configured direction. With a descriptor sample interval (MAP-Elites), the same
// rollout also measures the behaviour descriptors of evolve/problems/descriptors.hpp over the scored
// frames (Evaluation::descriptors); the fitness bits do not depend on it.
#pragma once

#include <optional>

#include "core/stepping.hpp"
#include "evolve/problems/creature_limits.hpp"
#include "evolve/problems/fitness_settings.hpp"
#include "evolve/problems/problem.hpp"
#include "evolve/problems/world_settings.hpp"

namespace sodaevo {

/// The Sodarace scale factor s = 211 / sqrt(sum of Lmax^2) (configs/README.md,
/// /fitness/scaling), Lmax the rest length of a spring, rest*(1 + Am*Aw) of a muscle. nullopt
/// without links.
std::optional<double> sodarace_scale(const soda::ModelDef& creature);

/// Scales `creature` by sodarace_scale: positions, velocities, rest lengths and
/// gravity. Throws soda::InputError without links, or when the scaled gravity
/// leaves the original's range (a creature too small).
void apply_sodarace_scale(soda::ModelDef& creature);

class WalkProblem final : public Problem {
 public:
  /// `describe_every` > 0: measure the descriptors every that many scored frames
  /// (and after the last one); 0: no descriptors.
  WalkProblem(const FitnessConfig& fitness, const WorldConfig& world, const LimitsConfig& limits,
              long long describe_every = 0);

  [[nodiscard]] const FitnessConfig& fitness() const { return fitness_; }
  [[nodiscard]] const WorldConfig& world() const { return world_; }
  [[nodiscard]] const LimitsConfig& limits() const { return limits_; }
  [[nodiscard]] long long describe_every() const { return describe_every_; }

  [[nodiscard]] FitnessKind fitness_kind() const override { return FitnessKind::Walk; }
  [[nodiscard]] soda::ModelDef prepare(const soda::ModelDef& creature) const override;
  /// In the soda mode with only the non-finite check and no honesty re-run, the
  /// models are stepped together (soda::BatchStepper, their links in shared SIMD
  /// batches), which gives every model exactly the bits it gets alone; otherwise
  /// one after the other, watched for divergence (fitness.divergence) and, with
  /// /fitness/honesty/max_change > 0, re-run with the refined step: a creature
  /// whose distance changes by more than that share is Diverged ("dishonest").
  [[nodiscard]] std::vector<Evaluation> rollouts(const std::vector<Rollout>& runs) const override;
  [[nodiscard]] soda::ModelDef export_form(const soda::ModelDef& creature, const std::string& id,
                                           const Evaluation& evaluation) const override;
  void write(WireWriter& out) const override;
  /// The fields `write` wrote after the kind tag.
  static WalkProblem read_fields(WireReader& in);

  /// One rollout stepped with `stepping` in place of the fitness's, watched for
  /// divergence, without the honesty re-run (the building block of the honesty
  /// check and of the accuracy benchmark).
  [[nodiscard]] Evaluation rollout_with(const soda::ModelDef& prepared, const soda::Stepping& stepping,
                                        const soda::SineJitter& jitter = {}) const;

 private:
  [[nodiscard]] Evaluation watched_rollout(const Rollout& run) const;

  FitnessConfig fitness_;
  WorldConfig world_;
  LimitsConfig limits_;
  long long describe_every_ = 0;
};

} // namespace sodaevo
