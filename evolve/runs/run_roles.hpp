// The one place where a run's config becomes its roles: the Problem (what is
// scored), the Estimator (how a score is estimated from rollouts) and the
// Algorithm (what is evaluated next). Everything below this (estimators,
// evaluators, MPI workers, the engine) sees the roles, never the RunConfig; the
// config file format stays as it is.
#pragma once

#include <memory>

#include "core/model_def.hpp"
#include "evolve/algorithms/algorithm.hpp"
#include "evolve/estimators/estimator.hpp"
#include "evolve/estimators/replica_estimator.hpp"
#include "evolve/problems/problem.hpp"
#include "evolve/problems/race_problem.hpp"
#include "evolve/problems/walk_problem.hpp"
#include "evolve/config/run_config.hpp"

namespace sodaevo {

struct RunRoles {
  std::unique_ptr<Problem> problem;
  std::unique_ptr<Estimator> estimator;
  std::unique_ptr<Algorithm> algorithm;
};

/// The run's Problem: a WalkProblem, or a RaceProblem for /fitness/kind "race",
/// measuring descriptors every `describe_every` frames (0: none; a check or an
/// export needs only the score).
std::unique_ptr<Problem> problem_of(const RunConfig& config, long long describe_every);
/// problem_of measuring descriptors as the run does: every /map_elites/sample_every
/// frames with /algorithm "map-elites", else not.
std::unique_ptr<Problem> problem_of(const RunConfig& config);

/// The WalkProblem of a walk run's config: its /fitness, /world and /limits; with
/// /algorithm "map-elites" measuring descriptors every /map_elites/sample_every frames.
WalkProblem walk_problem_of(const RunConfig& config);

/// The RaceProblem of a race run's config (its /fitness/race terrains read now),
/// measuring descriptors as the run does, or every `describe_every` frames.
RaceProblem race_problem_of(const RunConfig& config);
RaceProblem race_problem_of(const RunConfig& config, long long describe_every);

/// The ReplicaEstimator's plan of a run's config: its /fitness and /seed.
ReplicaPlan replica_plan(const RunConfig& config);

/// problem_of(config); a ReplicaEstimator
/// (/fitness/replicas...) and a GeneticAlgorithm.
RunRoles roles_of(const RunConfig& config);

/// One creature evaluated as the run `config` evaluates it (its problem and
/// estimator, on this thread): what replay checks and the report shows.
/// `rollouts` > 0: on that many replicas (as a survivor that gathered them was
/// estimated), else on the estimator's count for a new creature.
Evaluation evaluate_creature(const soda::ModelDef& creature, const RunConfig& config, int rollouts = 0);

} // namespace sodaevo
