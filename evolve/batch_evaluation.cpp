#include "batch_evaluation.hpp"

#include <algorithm>

#include "core/batch_step.hpp"
#include "evolve/parallel_for.hpp"

namespace sodaevo {

std::size_t evaluation_batch_size(std::size_t count, int threads) {
  const std::size_t per_thread = 2 * static_cast<std::size_t>(std::max(1, threads));
  return std::clamp<std::size_t>((count + per_thread - 1) / per_thread, 1, kMaxEvaluationBatch);
}

namespace {

/// Whether two creatures have one shape as soda::LockstepBatch::same_shape sees
/// it once built: the same nodes (mass or fixed, in order) and the same links
/// between them in file order, no fixed bars. Muscle or spring does not matter
/// (a spring is a muscle of power 0 in its lane).
bool same_shape(const soda::ModelDef& a, const soda::ModelDef& b) {
  if (a.nodes.size() != b.nodes.size() || a.links.size() != b.links.size()) return false;
  for (std::size_t i = 0; i < a.nodes.size(); ++i) {
    if (a.nodes[i].fixed != b.nodes[i].fixed) return false;
  }
  for (std::size_t i = 0; i < a.links.size(); ++i) {
    const soda::LinkDef &x = a.links[i], &y = b.links[i];
    if (x.a != y.a || x.b != y.b || x.kind == soda::LinkKind::FixedBar || y.kind == soda::LinkKind::FixedBar) return false;
  }
  return true;
}

} // namespace

EvaluationPlan plan_evaluation(const std::vector<const soda::ModelDef*>& creatures, std::size_t batch) {
  batch = std::max<std::size_t>(batch, 1);
  // Creatures by shape, shapes in order of their first creature.
  std::vector<std::vector<std::size_t>> shapes;
  for (std::size_t i = 0; i < creatures.size(); ++i) {
    auto same = std::find_if(shapes.begin(), shapes.end(), [&](const std::vector<std::size_t>& members) {
      return same_shape(*creatures[members[0]], *creatures[i]);
    });
    if (same == shapes.end()) {
      shapes.push_back({i});
    } else {
      same->push_back(i);
    }
  }
  EvaluationPlan plan;
  // Shapes with enough creatures for a lockstep batch: batches of `batch`, and
  // the rest as a batch of its own if it is enough for one (else it joins the
  // others).
  std::vector<bool> planned(creatures.size(), false);
  const std::size_t enough = static_cast<std::size_t>(soda::kMinLockstep);
  for (const std::vector<std::size_t>& members : shapes) {
    for (std::size_t first = 0; first < members.size() && members.size() - first >= enough; first += batch) {
      const std::size_t last = std::min(members.size(), first + batch);
      if (last - first < enough) break;
      for (std::size_t k = first; k < last; ++k) {
        plan.order.push_back(members[k]);
        planned[members[k]] = true;
      }
      plan.ends.push_back(plan.order.size());
    }
  }
  // The others in their order, cut where the batch stepper starts a new fused
  // scene anyway (smaller work items balance the threads better and lose none of
  // the fusing; the link count of the file is close enough to the prepared
  // model's for this).
  std::vector<std::size_t> rest;
  std::vector<int> links;
  for (std::size_t i = 0; i < creatures.size(); ++i) {
    if (planned[i]) continue;
    rest.push_back(i);
    links.push_back(static_cast<int>(creatures[i]->links.size()));
  }
  const std::size_t base = plan.order.size();
  plan.order.insert(plan.order.end(), rest.begin(), rest.end());
  for (std::size_t end : soda::fused_batch_ends(links, batch)) plan.ends.push_back(base + end);
  return plan;
}

std::vector<Evaluation> evaluate_creatures(const std::vector<const soda::ModelDef*>& creatures,
                                           const RunConfig& config, int threads, std::size_t batch) {
  threads = resolve_thread_count(threads);
  if (batch == 0) batch = evaluation_batch_size(creatures.size(), threads);
  std::vector<Evaluation> results(creatures.size());
  const EvaluationPlan plan = plan_evaluation(creatures, batch);
  parallel_for_index(plan.ends.size(), threads, [&](std::size_t b) {
    const std::size_t first = b == 0 ? 0 : plan.ends[b - 1], last = plan.ends[b];
    std::vector<const soda::ModelDef*> mine;
    for (std::size_t k = first; k < last; ++k) mine.push_back(creatures[plan.order[k]]);
    std::vector<Evaluation> scored = evaluate_creature_batch(mine, config);
    for (std::size_t k = 0; k < scored.size(); ++k) results[plan.order[first + k]] = std::move(scored[k]);
  });
  return results;
}

} // namespace sodaevo
