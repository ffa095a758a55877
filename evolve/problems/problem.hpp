// Problem: what is scored (pagmo's "problem" role). A Problem owns the world a
// creature is put in, the fitness definition and the limits of a genome; it
// turns a creature into the model that is stepped (prepare) and steps and scores
// that model (rollouts). It does not choose how many rollouts make a score (the
// Estimator does) nor where they run (the Evaluator does).
//
// Its kinds (fitness_kind.hpp: each kind's name, unit and how its score is shown)
// are WalkProblem (walk_problem.hpp): how far a creature walks on a flat floor,
// and RaceProblem (race_problem.hpp): how fast it races over terrains, fewer
// frames is better.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/model_def.hpp"
#include "core/sine_jitter.hpp"
#include "evolve/problems/evaluation.hpp"
#include "evolve/problems/fitness_kind.hpp"

namespace sodaevo {

class WireWriter;
class WireReader;

/// One rollout to run: a prepared model and its state's sine jitter (seed 0: the
/// exact engine). Replicas of one creature are rollouts of the same prepared model
/// that differ only in the jitter.
struct Rollout {
  // Implicit from a model alone: an exact rollout.
  Rollout(const soda::ModelDef* model, soda::SineJitter state_jitter = {}) : prepared(model), jitter(state_jitter) {}
  const soda::ModelDef* prepared;
  soda::SineJitter jitter;
};

class Problem {
 public:
  virtual ~Problem() = default;

  /// What it scores: its row of kFitnessKinds says how the scores read.
  [[nodiscard]] virtual FitnessKind fitness_kind() const = 0;
  /// The kind's name, also its tag in the wire format ("walk").
  [[nodiscard]] std::string kind() const { return fitness_kind_name(fitness_kind()); }

  /// The model that is stepped (and exported) for `creature`. Throws
  /// soda::InputError saying why the creature is refused (outside the limits, or
  /// it cannot be prepared).
  [[nodiscard]] virtual soda::ModelDef prepare(const soda::ModelDef& creature) const = 0;

  /// Steps each rollout's model from its start with its jitter and scores that
  /// run, on this thread. Result i belongs to runs[i], whatever else is in the
  /// list (rollouts of one model share its build and step together). A run that blows up is Diverged, a model that cannot be built
  /// Invalid; never throws for physics reasons.
  [[nodiscard]] virtual std::vector<Evaluation> rollouts(const std::vector<Rollout>& runs) const = 0;

  /// The prepared creature as `export` and the run store's best/ files hold it:
  /// named `id`, with its score and how it was measured in the comment.
  [[nodiscard]] virtual soda::ModelDef export_form(const soda::ModelDef& creature, const std::string& id,
                                                   const Evaluation& evaluation) const = 0;

  /// Writes the definition, kind tag first, so that read_problem in another
  /// process makes an equal Problem (the MPI workers get theirs this way).
  virtual void write(WireWriter& out) const = 0;
};

/// The Problem `write` wrote. Throws WireError for an unknown kind or bad fields.
std::unique_ptr<Problem> read_problem(WireReader& in);

} // namespace sodaevo
