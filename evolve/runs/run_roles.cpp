#include "run_roles.hpp"

#include <stdexcept>

#include "evolve/algorithms/genetic_algorithm.hpp"
#include "evolve/problems/race_problem.hpp"
#include "evolve/estimators/replica_estimator.hpp"
#include "evolve/problems/walk_problem.hpp"

namespace sodaevo {

std::unique_ptr<Problem> problem_of(const RunConfig& config, long long describe_every) {
  // The one place a kind becomes its Problem (no default: a new kind must be added here).
  switch (config.fitness.kind) {
    case FitnessKind::Walk:
      return std::make_unique<WalkProblem>(config.fitness, config.world, config.limits, describe_every);
    case FitnessKind::Race:
      return std::make_unique<RaceProblem>(config.fitness, config.world, config.limits, describe_every);
  }
  throw std::logic_error("problem_of: fitness kind " + fitness_kind_name(config.fitness.kind));
}

namespace {
long long describe_every_of(const RunConfig& config) {
  return config.algorithm == AlgorithmKind::MapElites ? config.map_elites.sample_every : 0;
}
} // namespace

WalkProblem walk_problem_of(const RunConfig& config) {
  return WalkProblem(config.fitness, config.world, config.limits, describe_every_of(config));
}

RaceProblem race_problem_of(const RunConfig& config, long long describe_every) {
  return RaceProblem(config.fitness, config.world, config.limits, describe_every);
}

RaceProblem race_problem_of(const RunConfig& config) { return race_problem_of(config, describe_every_of(config)); }

std::unique_ptr<Problem> problem_of(const RunConfig& config) {
  return problem_of(config, describe_every_of(config));
}

ReplicaPlan replica_plan(const RunConfig& config) { return replica_plan(config.fitness, config.seed); }

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
