// GeneticAlgorithm: makes generations (the Algorithm of evolve/algorithms/algorithm.hpp).
// It neither simulates nor writes files: an Evaluator scores creatures, the run
// store keeps them.
//
// Generational GA with elitism and tournament selection. All randomness of a
// child comes from the stream (seed, generation, index), so a generation depends
// only on the config and the previous generation: runs are reproducible and
// resumable from any checkpoint, whatever the number of threads.
#pragma once

#include <vector>

#include "core/model_def.hpp"
#include "evolve/algorithms/algorithm.hpp"
#include "evolve/algorithms/population.hpp"
#include "evolve/algorithms/genetic_settings.hpp"

namespace sodaevo {

/// Purposes of RNG streams (the fourth stream coordinate).
enum class RngPurpose : std::uint64_t { Initial = 1, Breed = 2 };

/// Generation 0: seeds (index 0..: first each seed as is, then mutated copies)
/// and random creatures, in the proportions of the config. Not evaluated.
Generation initial_generation(const GeneticSettings& config, const std::vector<soda::ModelDef>& seeds);

/// The next generation from an evaluated one: the elites (copied with their
/// evaluation) then children by tournament selection, optional crossover and
/// mutation. Not evaluated (except the elites).
Generation next_generation(const GeneticSettings& config, const Generation& evaluated);

/// The GA as the run loop drives it: initial_generation and next_generation with
/// the config's population, selection, variation and limits.
class GeneticAlgorithm final : public Algorithm {
 public:
  explicit GeneticAlgorithm(const GeneticSettings& config) : config_(config) {}
  [[nodiscard]] Generation first(const std::vector<soda::ModelDef>& seeds) const override {
    return initial_generation(config_, seeds);
  }
  [[nodiscard]] Generation next(const Generation& evaluated) const override {
    return next_generation(config_, evaluated);
  }
  /// Every child; the elites keep their evaluations.
  [[nodiscard]] long long evaluations_per_generation() const override {
    return config_.population.size - config_.selection.elites;
  }

 private:
  GeneticSettings config_;
};

} // namespace sodaevo
