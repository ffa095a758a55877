// Evaluating many creatures on several threads, in batches.
//
// Each thread takes batches of up to kMaxEvaluationBatch creatures and steps each
// batch fused on one core (evaluate_creature_batch, soda::BatchStepper): small
// creatures alone leave most of the core idle, fused they share its SIMD batches.
// A batch gives every creature exactly the bits it gets alone, and results are
// stored by index, so neither the batch size nor the thread count can change a
// result (tests/test_evolve.cpp).
#pragma once

#include <cstddef>
#include <vector>

#include "core/model_def.hpp"
#include "evolve/fitness.hpp"
#include "evolve/run_config.hpp"

namespace sodaevo {

/// Largest number of creatures stepped together on one core.
inline constexpr std::size_t kMaxEvaluationBatch = 16;

/// Creatures per batch for `count` creatures on `threads` threads: at most
/// kMaxEvaluationBatch, and small enough that every thread gets about two batches
/// (evaluate_creatures cuts them further where a new fused scene starts).
std::size_t evaluation_batch_size(std::size_t count, int threads);

/// Result i is exactly evaluate_creature(*creatures[i], config), for any `threads`
/// (0 = all cores) and `batch` size (0 = evaluation_batch_size).
std::vector<Evaluation> evaluate_creatures(const std::vector<const soda::ModelDef*>& creatures,
                                           const RunConfig& config, int threads, std::size_t batch = 0);

} // namespace sodaevo
