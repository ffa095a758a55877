#include "run_roles.hpp"

#include "evolve/algorithms/genetic_algorithm.hpp"
#include "evolve/problems/race_problem.hpp"
#include "evolve/estimators/replica_estimator.hpp"
#include "evolve/problems/walk_problem.hpp"

namespace sodaevo {

std::unique_ptr<Problem> problem_of(const RunConfig& config, long long describe_every) {
  if (config.fitness.kind == FitnessKind::Race) return std::make_unique<RaceProblem>(config, describe_every);
  return std::make_unique<WalkProblem>(config.fitness, config.world, config.limits, describe_every);
}

std::unique_ptr<Problem> problem_of(const RunConfig& config) {
  return problem_of(config, config.algorithm == AlgorithmKind::MapElites ? config.map_elites.sample_every : 0);
}

RunRoles roles_of(const RunConfig& config) {
  return {problem_of(config), std::make_unique<ReplicaEstimator>(replica_plan(config)),
          std::make_unique<GeneticAlgorithm>(config)};
}

Evaluation evaluate_creature(const soda::ModelDef& creature, const RunConfig& config, int rollouts) {
  const RunRoles roles = roles_of(config);
  if (rollouts > 0) {
    if (const std::unique_ptr<Estimator> estimator = roles.estimator->with_rollouts(rollouts)) {
      return estimator->estimate(*roles.problem, {&creature}).front();
    }
  }
  return roles.estimator->estimate(*roles.problem, {&creature}).front();
}

} // namespace sodaevo
