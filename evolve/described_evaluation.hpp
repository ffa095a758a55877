// Fitness and descriptors from the same rollouts: what MAP-Elites evaluates
// (evolve/map_elites.hpp). The descriptors are defined in evolve/descriptors.hpp.
#pragma once

#include <vector>

#include "core/model_def.hpp"
#include "evolve/descriptors.hpp"
#include "evolve/evaluation.hpp"
#include "evolve/run_config.hpp"

namespace sodaevo {

/// A fitness evaluation with the descriptors of the same rollout.
struct DescribedEvaluation {
  Evaluation evaluation;
  Behaviour behaviour{};
};

/// Scores prepared creatures exactly as evaluate_prepared_batch does (same
/// stepper, same bits: the fitness does not depend on the sampling) and measures
/// their descriptors every `sample_every` scored frames. Only the original's
/// stepping with the finite divergence check and no honesty re-run
/// (map_elites_config checks the config for it); otherwise throws soda::InputError.
std::vector<DescribedEvaluation> evaluate_described_batch(const std::vector<const soda::ModelDef*>& prepared,
                                                          const FitnessConfig& fitness, long long sample_every);

/// The same for genomes: checked against the limits and prepared as
/// evaluate_creature_batch does (an invalid creature's evaluation says why).
std::vector<DescribedEvaluation> evaluate_described_creatures(const std::vector<const soda::ModelDef*>& creatures,
                                                              const RunConfig& config, long long sample_every);

} // namespace sodaevo
