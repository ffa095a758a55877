// Problem: what is scored (pagmo's "problem" role). A Problem owns the world a
// creature is put in, the fitness definition and the limits of a genome; it
// turns a creature into the model that is stepped (prepare) and steps and scores
// that model (rollouts). It does not choose how many rollouts make a score (the
// Estimator does) nor where they run (the Evaluator does).
//
// Today's kind is WalkProblem (evolve/walk_problem.hpp): how far a creature walks
// on a flat floor. A race over terrains (fewer frames is better) is another
// kind: it implements the same four calls and its own wire tag.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/model_def.hpp"
#include "evolve/evaluation.hpp"

namespace sodaevo {

class WireWriter;
class WireReader;

class Problem {
 public:
  virtual ~Problem() = default;

  /// The kind's name, also its tag in the wire format ("walk").
  [[nodiscard]] virtual std::string kind() const = 0;

  /// The model that is stepped (and exported) for `creature`. Throws
  /// soda::InputError saying why the creature is refused (outside the limits, or
  /// it cannot be prepared).
  [[nodiscard]] virtual soda::ModelDef prepare(const soda::ModelDef& creature) const = 0;

  /// Steps each prepared model once from its start and scores that run, on this
  /// thread: one rollout each. Result i belongs to *prepared[i], whatever else is
  /// in the list. A run that blows up is Diverged, a model that cannot be built
  /// Invalid; never throws for physics reasons.
  [[nodiscard]] virtual std::vector<Evaluation> rollouts(const std::vector<const soda::ModelDef*>& prepared) const = 0;

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
