#include "run_roles.hpp"

#include "evolve/genetic_algorithm.hpp"
#include "evolve/walk_problem.hpp"

namespace sodaevo {

RunRoles roles_of(const RunConfig& config) {
  return {std::make_unique<WalkProblem>(config), std::make_unique<SingleRollout>(),
          std::make_unique<GeneticAlgorithm>(config)};
}

Evaluation evaluate_creature(const soda::ModelDef& creature, const RunConfig& config) {
  const RunRoles roles = roles_of(config);
  return roles.estimator->estimate(*roles.problem, {&creature}).front();
}

} // namespace sodaevo
