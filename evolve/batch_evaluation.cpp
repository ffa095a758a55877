#include "batch_evaluation.hpp"

#include <algorithm>

#include "core/batch_step.hpp"
#include "evolve/parallel_for.hpp"

namespace sodaevo {

std::size_t evaluation_batch_size(std::size_t count, int threads) {
  const std::size_t per_thread = 2 * static_cast<std::size_t>(std::max(1, threads));
  return std::clamp<std::size_t>((count + per_thread - 1) / per_thread, 1, kMaxEvaluationBatch);
}

std::vector<Evaluation> evaluate_creatures(const std::vector<const soda::ModelDef*>& creatures,
                                           const RunConfig& config, int threads, std::size_t batch) {
  threads = resolve_thread_count(threads);
  if (batch == 0) batch = evaluation_batch_size(creatures.size(), threads);
  std::vector<Evaluation> results(creatures.size());
  // Batches cut where the batch stepper starts a new fused scene anyway: smaller
  // work items balance the threads better and lose none of the fusing. (The link
  // count of the file is close enough to the prepared model's for this.)
  std::vector<int> links;
  for (const soda::ModelDef* c : creatures) links.push_back(static_cast<int>(c->links.size()));
  const std::vector<std::size_t> ends = soda::fused_batch_ends(links, batch);
  parallel_for_index(ends.size(), threads, [&](std::size_t b) {
    const std::size_t first = b == 0 ? 0 : ends[b - 1], last = ends[b];
    const std::vector<const soda::ModelDef*> mine(creatures.begin() + static_cast<std::ptrdiff_t>(first),
                                                  creatures.begin() + static_cast<std::ptrdiff_t>(last));
    std::vector<Evaluation> scored = evaluate_creature_batch(mine, config);
    for (std::size_t k = 0; k < scored.size(); ++k) results[first + k] = std::move(scored[k]);
  });
  return results;
}

} // namespace sodaevo
