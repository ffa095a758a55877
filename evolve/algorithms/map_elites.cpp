#include "map_elites.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <iterator>
#include <map>
#include <set>
#include <string>

#include "evolve/algorithms/rng.hpp"
#include "evolve/algorithms/variation.hpp"

namespace sodaevo {

namespace {

/// An estimate over `e.estimate.rollouts` replicas added to an entry (the
/// fitness as its replicas' mean, the descriptors as means weighted by count).
void add_estimate(ArchiveEntry& entry, const std::vector<double>& axis_values, const Evaluation& e) {
  const long long before = entry.fitness.n, count = e.estimate.rollouts;
  entry.fitness.merge(count, e.estimate.mean, e.estimate.sd);
  if (before == 0) {
    entry.descriptors = axis_values;
    return;
  }
  for (std::size_t a = 0; a < axis_values.size(); ++a) {
    entry.descriptors[a] += (axis_values[a] - entry.descriptors[a]) * static_cast<double>(count) /
                            static_cast<double>(before + count);
  }
}

/// A parent: uniform over the elites, or the fittest (highest mean; the first
/// drawn on a tie) of `tournament` uniform draws.
const ArchiveEntry& pick_parent(const std::vector<const ArchiveEntry*>& elites, int tournament, Rng& rng) {
  const ArchiveEntry* best = elites[rng.below(elites.size())];
  for (int k = 1; k < tournament; ++k) {
    const ArchiveEntry* other = elites[rng.below(elites.size())];
    if (other->fitness.mean > best->fitness.mean) best = other;
  }
  return *best;
}

/// A challenger waiting for its cell's verdict.
struct Pending {
  ArchiveEntry entry;
  bool confirmed = false; ///< sampled once more together with the elite
};

/// Which side of a cell's duel a sample request is for.
struct Asked {
  std::size_t cell = 0;
  bool elite = false;
};

} // namespace

std::vector<Individual> map_elites_children(const GeneticSettings& config, const MapElitesConfig& me,
                                            const GridArchive& archive, int iteration) {
  std::vector<const ArchiveEntry*> elites;
  for (const auto& [cell, e] : archive.elites()) elites.push_back(&e);
  std::vector<Individual> children;
  if (elites.empty()) return children;
  // The elite pool: the fittest elites, in cell order on ties (stable), for the
  // first elite_share of the batch (the optimising emitter).
  // With elite_recent, the recent entrants come first (each group fittest first),
  // so the pool is theirs and the fittest of all only top it up.
  std::vector<const ArchiveEntry*> pool = elites;
  const auto recent = [&](const ArchiveEntry* e) { return me.elite_recent > 0 && e->iteration >= iteration - me.elite_recent; };
  std::stable_sort(pool.begin(), pool.end(), [&](const ArchiveEntry* a, const ArchiveEntry* b) {
    if (recent(a) != recent(b)) return recent(a);
    return a->fitness.mean > b->fitness.mean;
  });
  pool.resize(std::min(pool.size(), static_cast<std::size_t>(me.elite_pool)));
  const int from_pool = static_cast<int>(std::lround(me.elite_share * me.batch_size));
  for (int k = 0; k < me.batch_size; ++k) {
    Rng rng = Rng::stream(config.seed, static_cast<std::uint64_t>(iteration), static_cast<std::uint64_t>(k),
                          kMapElitesPurpose);
    const std::vector<const ArchiveEntry*>& parents = k < from_pool ? pool : elites;
    const ArchiveEntry& a = pick_parent(parents, me.parent_tournament, rng);
    Individual child;
    // Appended piece by piece: "i" + std::string trips GCC 12's -Wrestrict (a false positive).
    child.id = std::to_string(iteration);
    child.id.insert(0, 1, 'i');
    child.id += '-';
    child.id += std::to_string(k);
    child.parents = {a.id};
    if (me.crossover_rate > 0.0 && rng.chance(me.crossover_rate)) {
      const ArchiveEntry& b = pick_parent(parents, me.parent_tournament, rng);
      child.creature = crossover(a.creature, b.creature, config, rng);
      child.parents.push_back(b.id);
    } else {
      child.creature = a.creature;
    }
    mutate(child.creature, config, rng);
    children.push_back(std::move(child));
  }
  return children;
}

InsertionCounts insert_challengers(GridArchive& archive, std::vector<Challenger> challengers, int iteration,
                                   const ResamplePlan& plan, const ReplicaSampler& sample) {
  InsertionCounts counts;
  // Each cell's challengers in child order. Cells do not interact, so every cell
  // waiting for replicas asks at once, and the decisions are those of inserting
  // one challenger after the other.
  std::map<std::size_t, std::deque<Pending>> queues;
  for (Challenger& c : challengers) {
    if (!c.first.ok() || c.first.estimate.rollouts < 1) {
      ++counts.rejected;
      continue;
    }
    Pending p;
    p.entry.id = c.individual.id;
    p.entry.parents = c.individual.parents;
    p.entry.creature = std::move(c.individual.creature);
    p.entry.iteration = iteration;
    p.entry.distance = c.first.distance;
    const std::vector<double> values = archive.axis_values(c.first.descriptors);
    add_estimate(p.entry, values, c.first);
    queues[archive.cell_of(values)].push_back(std::move(p));
  }
  while (!queues.empty()) {
    std::vector<SampleRequest> requests;
    std::vector<Asked> asked;
    for (auto it = queues.begin(); it != queues.end();) {
      const std::size_t cell = it->first;
      std::deque<Pending>& queue = it->second;
      while (!queue.empty()) {
        Pending& head = queue.front();
        ArchiveEntry* elite = archive.elite(cell);
        const Judgement j = judge(elite != nullptr ? &elite->fitness : nullptr, head.entry.fitness, plan, head.confirmed);
        if (j.verdict == Verdict::Enter || j.verdict == Verdict::Replace) {
          ++(j.verdict == Verdict::Enter ? counts.entered : counts.replaced);
          archive.place(cell, std::move(head.entry));
          queue.pop_front();
          continue;
        }
        if (j.verdict == Verdict::Reject) {
          ++counts.rejected;
          queue.pop_front();
          continue;
        }
        if (j.verdict != Verdict::SampleElite) {
          requests.push_back({&head.entry.creature, head.entry.fitness.n, j.replicas});
          asked.push_back({cell, false});
        }
        if (j.verdict != Verdict::SampleChallenger) {
          requests.push_back({&elite->creature, elite->fitness.n, j.replicas});
          asked.push_back({cell, true});
        }
        if (j.verdict == Verdict::SampleBoth) head.confirmed = true;
        break;
      }
      it = queue.empty() ? queues.erase(it) : std::next(it);
    }
    if (requests.empty()) break;
    const std::vector<Evaluation> more = sample(requests);
    counts.resampled += static_cast<long long>(requests.size());
    std::set<std::size_t> failed_challenger, failed_elite;
    for (std::size_t k = 0; k < requests.size(); ++k) {
      counts.resampled_rollouts += requests[k].count;
      const std::size_t cell = asked[k].cell;
      if (!more[k].ok()) {
        (asked[k].elite ? failed_elite : failed_challenger).insert(cell);
        continue;
      }
      ArchiveEntry& entry = asked[k].elite ? *archive.elite(cell) : queues.at(cell).front().entry;
      add_estimate(entry, archive.axis_values(more[k].descriptors), more[k]);
    }
    for (std::size_t cell : failed_challenger) {
      ++counts.rejected;
      queues.at(cell).pop_front();
      if (queues.at(cell).empty()) queues.erase(cell);
    }
    for (std::size_t cell : failed_elite) {
      ++counts.evicted;
      archive.remove(cell);
    }
  }
  return counts;
}

} // namespace sodaevo
