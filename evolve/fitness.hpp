// Fitness: how far a creature walks, measured the same way every time.
//
// A creature (a ModelDef of free masses and links) is first prepared: the world
// of the config applied (except the parameters the creature may evolve), scaled as
// the Sodarace racer scaled contenders (spec 3.2) unless disabled, put in a
// container wide and tall enough that no wall can be reached at 20 px/frame, its
// lowest mass `drop_height` above the floor, wave forward, autoreverse off. The
// prepared model is exactly what `export` writes, so the original program runs it
// the same way. Then it settles for `settle_frames` and is scored on the centroid's
// displacement over the next `frames` frames in the configured direction.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "core/model_def.hpp"
#include "evolve/run_config.hpp"

namespace sodaevo {

/// The fitness given to invalid or diverged creatures: below every real one.
inline constexpr double kWorstFitness = -std::numeric_limits<double>::infinity();

enum class EvaluationStatus { Ok, Invalid, Diverged };

struct Evaluation {
  EvaluationStatus status = EvaluationStatus::Invalid;
  std::string reason;           ///< why invalid or diverged; empty when Ok
  double fitness = kWorstFitness;
  double distance = 0.0;        ///< centroid x displacement over the scored frames, px
  double px_per_frame = 0.0;    ///< distance / frames
  /// Honesty check (/fitness/honesty): relative change of the distance under the
  /// refined step (evolve/honesty.hpp); 0 when the check is off.
  double honesty_change = 0.0;

  [[nodiscard]] bool ok() const { return status == EvaluationStatus::Ok; }
};

/// Why `creature` is not a valid genome under `limits` (masses only, at least one
/// link, connected, within counts), or nullopt if it is.
std::optional<std::string> check_creature(const soda::ModelDef& creature, const LimitsConfig& limits);

/// The Sodarace scale factor s = 211 / sqrt(sum of Lmax^2) (spec 3.2), Lmax the
/// rest length of a spring, rest*(1 + Am*Aw) of a muscle. nullopt without links.
std::optional<double> sodarace_scale(const soda::ModelDef& creature);

/// The model that is simulated (and exported). Throws soda::InputError when the
/// creature cannot be prepared (e.g. scaled gravity above the original's limit).
soda::ModelDef prepare_for_evaluation(const soda::ModelDef& creature, const FitnessConfig& fitness,
                                      const WorldConfig& world);

/// check_creature, then prepare_for_evaluation: the model the GA steps for
/// `creature`, or nullopt with the reason it is refused in `why` (as
/// Evaluation::reason gives it).
std::optional<soda::ModelDef> prepare_creature(const soda::ModelDef& creature, const RunConfig& config,
                                               std::string& why);

/// The prepared model with name = `id` and a comment stating the score and how it
/// was measured: what `export` and the run store's best/ files hold.
soda::ModelDef export_form(const soda::ModelDef& creature, const std::string& id, const Evaluation& evaluation,
                           const RunConfig& config);

/// Runs a prepared model: settle, then score, stepped as fitness.stepping() says,
/// watched for divergence (fitness.divergence; core/divergence.hpp) and, with
/// /fitness/honesty/max_change > 0, re-run with the refined step: a creature whose
/// distance changes by more than that share is flagged Diverged ("dishonest").
/// Never throws for physics reasons.
Evaluation evaluate_prepared(const soda::ModelDef& prepared, const FitnessConfig& fitness);

/// evaluate_prepared for several models at once on this thread: in the soda mode
/// with only the non-finite check and no honesty re-run they are stepped together
/// (soda::BatchStepper, their links in shared SIMD batches), which gives every model
/// exactly the bits it gets alone; otherwise one after the other. Result i is
/// evaluate_prepared(*prepared[i]).
std::vector<Evaluation> evaluate_prepared_batch(const std::vector<const soda::ModelDef*>& prepared,
                                                const FitnessConfig& fitness);

/// evaluate_prepared with an explicit stepping and no honesty re-run (the
/// building block of the honesty check and of the accuracy benchmark).
Evaluation evaluate_prepared_with(const soda::ModelDef& prepared, const FitnessConfig& fitness,
                                  const soda::Stepping& stepping);

/// check_creature + prepare_for_evaluation + evaluate_prepared; problems become
/// an Invalid evaluation with the reason, never an exception.
Evaluation evaluate_creature(const soda::ModelDef& creature, const RunConfig& config);

/// evaluate_creature for several creatures at once on this thread (one batch, as
/// evaluate_prepared_batch). Result i is exactly evaluate_creature(*creatures[i]).
std::vector<Evaluation> evaluate_creature_batch(const std::vector<const soda::ModelDef*>& creatures,
                                                const RunConfig& config);

} // namespace sodaevo
